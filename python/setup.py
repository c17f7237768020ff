"""Builds shprt._shprt with the repository's CMake build, then lets setuptools package it.

Environment: SHPRT_BUILD_DIR (default <repo>/build-python), SHPRT_CMAKE_ARGS (extra arguments
for the configure step, split on spaces, e.g. "-DSHPRT_CUDA=OFF -DCMAKE_CXX_COMPILER_LAUNCHER=ccache").
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = pathlib.Path(__file__).resolve().parent.parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("SHPRT_BUILD_DIR") or SOURCE / "build-python")
        configure = ["cmake", "-S", str(SOURCE), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     f"-DPython_EXECUTABLE={sys.executable}", "-DSHPRT_PYTHON=ON",
                     "-DSHPRT_BUILD_TESTS=OFF", "-DSHPRT_BUILD_BENCH=OFF",
                     "-DSHPRT_BUILD_VIEWER=OFF", "-DCMAKE_UNITY_BUILD=ON"]
        if shutil.which("ninja") and not (build / "CMakeCache.txt").exists():
            configure += ["-G", "Ninja"]
        configure += os.environ.get("SHPRT_CMAKE_ARGS", "").split()
        # pip shows this only with -v; without it, one spinner line for the whole build.
        print(f"shprt: building the C++ extension with CMake in {build} (a few minutes on 2 "
              "cores)", file=sys.stderr, flush=True)
        subprocess.check_call(configure)
        subprocess.check_call(["cmake", "--build", str(build), "--target", "shprt_python",
                               "-j", str(os.cpu_count() or 2)])
        built = next((build / "python" / "shprt").glob("_shprt*.so"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


# The extension's type stubs and the PEP 561 marker go into the wheel beside it.
setup(packages=["shprt"], package_data={"shprt": ["py.typed", "*.pyi"]},
      ext_modules=[CMakeExtension("shprt._shprt")],
      cmdclass={"build_ext": CMakeBuild})
