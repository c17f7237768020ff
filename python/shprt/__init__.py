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

from typing import Any as _Any, Dict as _Dict

from ._shprt import *  # noqa: F401,F403
# Named again "as" themselves: the stubs' way of saying that the package re-exports them (mypy
# --strict: no implicit re-export); __version__ is not in the * above.
from ._shprt import __version__ as __version__, Error as Error  # noqa: F401
from ._shprt import HAS_RENDER as HAS_RENDER, HAS_CUDA as HAS_CUDA  # noqa: F401

import json as _json


def metadata(file: "File") -> _Dict[str, _Any]:  # noqa: F405 (File is from the * import)
    """The .shprt file's JSON metadata as a dict."""
    result: _Dict[str, _Any] = _json.loads(file.metadata_json)
    return result
