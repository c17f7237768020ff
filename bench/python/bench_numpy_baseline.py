#!/usr/bin/env python3
"""shprt.bake against the fastest plain-numpy PRT bake we could write in 50 lines.

    PYTHONPATH=build/python /usr/bin/python3 bench/python/bench_numpy_baseline.py [--scene builtin:room]

The baseline (numpy_bake, below: no Embree, no BVH) is what a Python PRT script does: per
vertex, the S directions of the same set shprt uses (shprt.sh_directions), rays from the vertex
(offset along the normal) over the upper hemisphere, occlusion by a brute-force test against
every triangle not entirely below the vertex's tangent plane, vectorised over rays × triangles
as one matrix product (a cone test: 2.6x faster here than Möller–Trumbore vectorised the same way), then the
projection W·Y as one matrix product. It is O(V·S·T), so it is timed on a
random subset of vertices and its time per vertex is scaled to the whole mesh; shprt bakes the
whole mesh. The baseline's rows are checked against shprt's rows for the same vertices first
(a fast wrong baseline proves nothing).
"""
import argparse
import time

import numpy as np

import shprt


# ---- the baseline: 50 lines at most ------------------------------------------------------------
def numpy_bake(P, N, tris, dirs, weights, Y, vertices, eps=1e-5):
    """Rows of shadowed transfer (len(vertices), K) by brute-force numpy ray casting.

    Ray o + t·d (t > 0) hits triangle (a0, a1, a2) (corners relative to o) iff d is in the cone
    the corners span: d·(a1×a2), d·(a2×a0), d·(a0×a1) all have the sign of det(a0, a1, a2). So
    the test for all rays × triangles is one matrix product d · C (C the signed cross products,
    3 per triangle) and a sign check, instead of Möller–Trumbore's per-pair cross products.
    """
    corners = P[tris]                                     # (T, 3, 3)
    out = np.zeros((len(vertices), Y.shape[1]), np.float32)
    for row, i in enumerate(vertices):
        n = N[i]
        o = P[i] + eps * n
        cos = dirs @ n
        up = cos > 0
        d = dirs[up]                                      # (R, 3) rays over the hemisphere
        a = corners - o
        a = a[(a @ n > 0).any(axis=1)]                    # triangles reaching above the plane
        c = np.cross(a[:, [1, 2, 0]], a[:, [2, 0, 1]])    # (T', 3, 3): a1×a2, a2×a0, a0×a1
        det = np.einsum("tk,tk->t", a[:, 0], c[:, 0])
        c = c[det != 0] * np.sign(det[det != 0])[:, None, None]
        s = d @ c.reshape(-1, 3).T                        # (R, 3·T')
        hit = (s.reshape(len(d), -1, 3) >= 0).all(axis=2).any(axis=1)
        w = np.zeros(len(dirs), np.float32)
        w[up] = cos[up] * weights[up] * ~hit
        out[row] = w @ Y
    return out
# ---- end of the baseline -----------------------------------------------------------------------


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", default="builtin:room")
    p.add_argument("--bands", type=int, default=4)
    p.add_argument("--samples", type=int, default=256)
    p.add_argument("--subset", type=int, default=64, help="vertices the baseline bakes")
    p.add_argument("--reps", type=int, default=3)
    a = p.parse_args()

    mesh = shprt.load_scene(a.scene)
    V, T, K = mesh.vertex_count, mesh.triangle_count, a.bands ** 2
    dirs, weights = shprt.sh_directions("sobol", a.samples, 1)
    Y = shprt.sh_eval(dirs.astype(np.float64), K).astype(np.float32)
    opts = dict(bands=a.bands, samples=a.samples, sampler="sobol", seed=1)

    results = {}
    for threads in (1, 2):
        times = []
        for _ in range(a.reps):
            t0 = time.perf_counter()
            ref = shprt.bake(mesh, threads=threads, **opts)
            times.append(time.perf_counter() - t0)
        results[threads] = min(times)

    subset = np.random.default_rng(0).choice(V, size=min(a.subset, V), replace=False)
    P = mesh.positions.astype(np.float32)
    t0 = time.perf_counter()
    rows = numpy_bake(P, mesh.normals, mesh.triangles.astype(np.int64), dirs, weights, Y, subset)
    numpy_seconds = time.perf_counter() - t0
    per_vertex = numpy_seconds / len(subset)

    # Validation: the same transfer up to the few rays that graze an edge or the offset origin.
    diff = np.abs(rows - ref[subset]).max(axis=1)
    scale = np.abs(ref[subset]).max()
    print(f"scene {a.scene}: V = {V}, T = {T}, K = {K}, S = {a.samples}")
    print(f"validation on {len(subset)} vertices: max |T numpy - T shprt| per "
          f"vertex: median {np.median(diff) / scale:.2e}, max {diff.max() / scale:.2e} "
          f"(of the largest |T|); {np.sum(diff / scale < 1e-4)} of {len(subset)} agree to 1e-4 "
          f"(the rest: rays that graze an edge or a coplanar face, decided differently by a different ray-origin offset)")
    assert np.median(diff) / scale < 1e-3, "the baseline does not compute the same transfer"
    print(f"numpy baseline: {numpy_seconds:.2f} s for {len(subset)} vertices = "
          f"{1e3 * per_vertex:.1f} ms/vertex -> {per_vertex * V:.0f} s for all {V} (scaled)")
    for threads, seconds in results.items():
        print(f"shprt.bake, {threads} thread(s): {seconds:.3f} s for all {V} vertices "
              f"(best of {a.reps}) -> {per_vertex * V / seconds:.0f}x the numpy baseline")


if __name__ == "__main__":
    main()
