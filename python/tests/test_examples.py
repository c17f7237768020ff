"""The examples run: python/examples/quickstart.py (which must be the README's Python example, line
for line: the README's used to load a bunny.ply that is not in the repository) and
python/examples/bake_folder.py on a folder of meshes that `shprt scene` writes, one of them broken.
"""
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import shprt

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "python" / "examples"


def run_example(name, *args, cwd):
    """The example in a fresh interpreter (this one's shprt: PYTHONPATH as the suite's)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    return subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)], cwd=cwd,
                          env=env, capture_output=True, text=True, timeout=600)


def readme_python_example():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    start = text.index("```python\n") + len("```python\n")
    return text[start:text.index("```", start)]


def test_the_readme_example_is_quickstart_py():
    code = (EXAMPLES / "quickstart.py").read_text(encoding="utf-8")
    assert code[code.index("import shprt"):] == readme_python_example()


@pytest.mark.skipif(not shprt.HAS_RENDER, reason="this build has no renderer (shprt.render)")
def test_quickstart_runs(tmp_path):
    done = run_example("quickstart.py", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "100%"
    f = shprt.load(str(tmp_path / "box.shprt"))
    assert f.K == 16 and f.samples == 1024 and f.mesh.vertex_count > 0


def test_bake_folder_bakes_each_mesh_and_skips_a_broken_one(cli, tmp_path):
    meshes = tmp_path / "meshes"
    meshes.mkdir()
    cli("scene", "plane", "-o", meshes / "plane.ply")
    cli("scene", "box_on_plane", "-o", meshes / "box.ply")
    (meshes / "broken.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\n")
    out = tmp_path / "out"
    done = run_example("bake_folder.py", meshes, "-o", out, "--bands", "2", "--samples", "64",
                       cwd=tmp_path)
    assert done.returncode == 1, done.stderr  # one mesh failed
    assert "broken.ply" in done.stderr and "skipped" in done.stderr
    assert done.stdout.startswith("baked 2 of 3 meshes")
    for name in ("plane", "box"):
        data = np.load(out / f"{name}.npz")
        mesh = shprt.load_scene(str(meshes / f"{name}.ply"))
        assert data["transfer"].shape == (mesh.vertex_count, 4)
        assert data["transfer"].dtype == np.float32 and int(data["K"]) == 4
        np.testing.assert_array_equal(data["positions"], mesh.positions)
