"""shprt: precomputed radiance transfer in real spherical harmonics.

A thin shell over the C++ library (the extension shprt._shprt): numpy arrays in and out.

    import shprt
    mesh = shprt.load_scene("builtin:room")          # or a PLY/OBJ/glTF file
    T = shprt.bake(mesh, bands=4, samples=1024)       # (V, 16) float32, the GIL released
    light = shprt.light("builtin", K=16)              # (3, 16) RGB SH coefficients
    E = T @ light.T                                   # (V, 3) irradiance

Errors from the library are shprt.Error (a RuntimeError) with .code, e.g. 'invalid_argument',
'io', 'format', 'unsupported', 'cancelled'.
"""

from ._shprt import *  # noqa: F401,F403
from ._shprt import __version__, Error, HAS_RENDER, HAS_CUDA  # noqa: F401

import json as _json


def metadata(file):
    """The .shprt file's JSON metadata as a dict."""
    return _json.loads(file.metadata_json)
