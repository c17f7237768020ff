"""Shared fixtures: the `shprt` command line beside the module (CTest passes SHPRT_CLI; by hand,
build/shprt is used) and small scenes. Run: PYTHONPATH=build/python python3 -m pytest python/tests
"""
import os
import pathlib
import subprocess

import pytest

import shprt

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli_process():
    """cli_process(*args): the command line's subprocess.CompletedProcess, whatever its exit."""
    path = os.environ.get("SHPRT_CLI") or str(ROOT / "build" / "shprt")
    if not os.path.exists(path):
        pytest.skip(f"the shprt command line is not built ({path})")

    # Under the sanitizers CTest preloads ASan's shared runtime into this interpreter
    # (python/CMakeLists.txt, SHPRT_ASAN_PRELOAD); the program carries its own and must not get it.
    env = dict(os.environ)
    if os.environ.get("SHPRT_ASAN_PRELOAD"):
        env.pop("LD_PRELOAD", None)

    def run(*args):
        return subprocess.run([path, *map(str, args)], capture_output=True, text=True, env=env)

    return run


@pytest.fixture(scope="session")
def cli(cli_process):
    def run(*args):
        done = cli_process(*args)
        assert done.returncode == 0, f"shprt {' '.join(map(str, args))}: {done.stderr}"
        return done.stdout

    return run


@pytest.fixture(scope="session")
def box():
    """builtin:box_on_plane: a box whose shadow makes shadowed transfer differ from unshadowed."""
    return shprt.load_scene("builtin:box_on_plane")


@pytest.fixture(scope="session")
def sphere():
    return shprt.load_scene("builtin:sphere")
