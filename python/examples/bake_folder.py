#!/usr/bin/env python3
"""Bakes every mesh (PLY, OBJ) in a folder into one .npz per mesh, with a progress bar.

    PYTHONPATH=build/python python3 python/examples/bake_folder.py MESHES/ -o out/ --bands 4

Each OUT/NAME.npz holds positions (V, 3), normals (V, 3), albedo (V, 3), triangles (T, 3) and
transfer (V, K) float32 (shprt's SH convention: index l(l+1)+m, Condon–Shortley phase), plus
K, samples, sampler and seed. PLY keeps its vertex order, so row i is the file's vertex i.
Meshes that fail to load are reported and skipped; Ctrl-C stops the bake in progress.
"""
import argparse
import pathlib
import sys
import time

import numpy as np

import shprt


class Bar:
    """One line on stderr: the file, its bar, rays/s and ETA, and the folder's progress."""

    def __init__(self, index: int, count: int, name: str, width: int = 30) -> None:
        self.index, self.count, self.name, self.width = index, count, name, width
        self.start = time.monotonic()

    def __call__(self, done: int, total: int) -> None:
        frac = done / total if total else 0.0
        elapsed = time.monotonic() - self.start
        rate = done / elapsed if elapsed > 0 else 0.0
        eta = (total - done) / rate if rate > 0 else 0.0
        fill = int(frac * self.width)
        sys.stderr.write(f"\r[{self.index}/{self.count}] {self.name[:24]:24} "
                         f"[{'#' * fill}{'.' * (self.width - fill)}] {100 * frac:5.1f}% "
                         f"{rate / 1e6:6.1f} Mrays/s ETA {eta:5.1f} s ")
        sys.stderr.flush()


def main() -> int:
    p = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    p.add_argument("folder", type=pathlib.Path)
    p.add_argument("-o", "--output", type=pathlib.Path, required=True)
    p.add_argument("--bands", type=int, default=4)
    p.add_argument("--samples", type=int, default=1024)
    p.add_argument("--sampler", default="sobol")
    p.add_argument("--transfer", default="shadowed")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=0)
    a = p.parse_args()

    meshes = sorted(f for f in a.folder.iterdir() if f.suffix.lower() in (".ply", ".obj"))
    if not meshes:
        sys.exit(f"bake_folder: no .ply or .obj files in {a.folder}")
    a.output.mkdir(parents=True, exist_ok=True)
    failed, start = 0, time.monotonic()
    for i, path in enumerate(meshes, 1):
        try:
            mesh = shprt.load_scene(str(path))
            transfer = shprt.bake(mesh, bands=a.bands, samples=a.samples, sampler=a.sampler,
                                  transfer=a.transfer, seed=a.seed, threads=a.threads,
                                  progress=Bar(i, len(meshes), path.name))
        except shprt.Error as e:
            sys.stderr.write(f"\nbake_folder: {path.name}: {e} ({e.code}); skipped\n")
            failed += 1
            continue
        np.savez(a.output / f"{path.stem}.npz", positions=mesh.positions, normals=mesh.normals,
                 albedo=mesh.albedo, triangles=mesh.triangles, transfer=transfer,
                 K=transfer.shape[-1], samples=a.samples, sampler=a.sampler, seed=a.seed)
        sys.stderr.write(f" -> {path.stem}.npz ({mesh.vertex_count} vertices)\n")
    print(f"baked {len(meshes) - failed} of {len(meshes)} meshes in "
          f"{time.monotonic() - start:.1f} s -> {a.output}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
