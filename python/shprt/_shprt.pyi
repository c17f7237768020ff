# Type stubs of the extension shprt._shprt (python/src/*.cpp), written by hand: Debian 12 packages
# no stub generator. Every name the module binds has its stub here with the same parameters (names,
# order, keyword-only marker, defaults), which python/tests/test_stubs.py checks against the
# signatures pybind11 gives; the CTest test `python_mypy` runs `mypy --strict` over this file, the
# package and the examples. The meaning of each argument is in its docstring (help(shprt.bake)).
#
# Arrays in are numpy.typing.ArrayLike (the module converts and checks dtype and shape, one
# shprt.Error naming the argument); arrays out are float32 (mesh, transfer, lights, images),
# float64 (SH evaluation, projection, rotation) or uint32 (triangles).
import os
from typing import Any, Callable, Sequence, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str
HAS_RENDER: bool  # shade, render and save_image exist only when it is True
HAS_CUDA: bool

_Progress = Callable[[int, int], bool | None]  # progress(done, total): False cancels
_StrPath = str | os.PathLike[str]

class Error(RuntimeError):
    # The library's ErrorCode: 'invalid_argument', 'io', 'format', 'unsupported', 'cuda',
    # 'out_of_memory' or 'cancelled'.
    code: str

class Mesh:
    def __init__(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        normals: ArrayLike | None = None,
        albedo: ArrayLike | None = None,
    ) -> None: ...
    @property
    def positions(self) -> NDArray[np.float32]: ...  # (V, 3), a view
    @property
    def normals(self) -> NDArray[np.float32]: ...  # (V, 3), a view
    @property
    def albedo(self) -> NDArray[np.float32]: ...  # (V, 3), a view
    @property
    def triangles(self) -> NDArray[np.uint32]: ...  # (T, 3), a view
    @property
    def source(self) -> str: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...
    def __repr__(self) -> str: ...

def load_scene(spec: str) -> Mesh: ...
def builtin_scenes() -> list[str]: ...

class File:
    def __init__(
        self,
        mesh: Mesh,
        transfer: ArrayLike,
        kind: str = "shadowed",
        sampler: str = "sobol",
        samples: int = 0,
        seed: int = 0,
        encoding: str = "float32",
    ) -> None: ...
    @property
    def mesh(self) -> Mesh: ...
    @property
    def transfer(self) -> NDArray[np.float32]: ...  # (V, K), (V, C, K) or (V, K(K+1)/2)
    @property
    def direct(self) -> NDArray[np.float32] | None: ...  # (V, K): interreflected files only
    @property
    def K(self) -> int: ...
    @property
    def channels(self) -> int: ...
    @property
    def kind(self) -> str: ...
    @property
    def sampler(self) -> str: ...
    @property
    def samples(self) -> int: ...
    @property
    def seed(self) -> int: ...
    @property
    def target_error(self) -> float: ...
    @property
    def receiver_samples(self) -> NDArray[np.uint32] | None: ...  # error-bounded bakes only
    @property
    def receiver_error(self) -> NDArray[np.float32] | None: ...  # error-bounded bakes only
    @property
    def encoding(self) -> str: ...
    @property
    def metadata_json(self) -> str: ...
    def summary(self) -> str: ...
    def __repr__(self) -> str: ...

def compress(
    file: File,
    clusters: int,
    vectors: int,
    *,
    half: bool = False,
    seed: int = 1,
    iterations: int = 16,
    threads: int = 0,
    probe_cpca: tuple[int, int] | None = None,
) -> tuple[File, dict[str, Any]]: ...
def load(path: str) -> File: ...
@overload
def save(path: str, file: File, reproducible: bool = False) -> None: ...
@overload
def save(
    path: str,
    mesh: Mesh,
    transfer: ArrayLike,
    kind: str = "shadowed",
    sampler: str = "sobol",
    samples: int = 0,
    seed: int = 0,
    encoding: str = "float32",
    reproducible: bool = False,
) -> None: ...

# bake() returns the transfer array, or with output= a dict describing the file it wrote.
@overload
def bake(
    vertices: Mesh | ArrayLike,
    faces: ArrayLike | None = None,
    normals: ArrayLike | None = None,
    albedo: ArrayLike | None = None,
    *,
    bands: int | None = None,
    coeffs: int | None = None,
    samples: int = 1024,
    sampler: str = "sobol",
    directions: str = "local",
    target_error: float = 0.0,
    max_samples: int = 0,
    transfer: str = "shadowed",
    seed: int = 1,
    bounces: int | str | None = None,
    tolerance: float | None = None,
    two_sided: bool = False,
    indirect_samples: int | None = None,
    source_spacing: float | str | None = None,
    bounce_coeffs: int | None = None,
    threads: int = 0,
    device: str = "cpu",
    progress: _Progress | None = None,
    domain: str = "vertex",
    resolution: int | str | tuple[int, int] | None = None,
    uv_set: int = 0,
    unwrap: bool = False,
    texel_density: float | None = None,
    refine: float | None = None,
    max_vertices: int | None = None,
    max_edge_split_depth: int | None = None,
    shard: str | tuple[int, int] | None = None,
    probes: str | tuple[int, int, int] | None = None,
    probe_box: str | tuple[float, float, float, float, float, float] | None = None,
    probe_bands: int | None = None,
    output: None = None,
    half: bool = False,
    float32: bool = False,
    stream: bool = False,
    reproducible: bool = False,
    checkpoint: _StrPath | None = None,
    resume: _StrPath | None = None,
    checkpoint_every: float = 30.0,
    max_memory: int | str | None = None,
) -> NDArray[np.float32]: ...
@overload
def bake(
    vertices: Mesh | ArrayLike,
    faces: ArrayLike | None = None,
    normals: ArrayLike | None = None,
    albedo: ArrayLike | None = None,
    *,
    bands: int | None = None,
    coeffs: int | None = None,
    samples: int = 1024,
    sampler: str = "sobol",
    directions: str = "local",
    target_error: float = 0.0,
    max_samples: int = 0,
    transfer: str = "shadowed",
    seed: int = 1,
    bounces: int | str | None = None,
    tolerance: float | None = None,
    two_sided: bool = False,
    indirect_samples: int | None = None,
    source_spacing: float | str | None = None,
    bounce_coeffs: int | None = None,
    threads: int = 0,
    device: str = "cpu",
    progress: _Progress | None = None,
    domain: str = "vertex",
    resolution: int | str | tuple[int, int] | None = None,
    uv_set: int = 0,
    unwrap: bool = False,
    texel_density: float | None = None,
    refine: float | None = None,
    max_vertices: int | None = None,
    max_edge_split_depth: int | None = None,
    shard: str | tuple[int, int] | None = None,
    probes: str | tuple[int, int, int] | None = None,
    probe_box: str | tuple[float, float, float, float, float, float] | None = None,
    probe_bands: int | None = None,
    output: _StrPath,
    half: bool = False,
    float32: bool = False,
    stream: bool = False,
    reproducible: bool = False,
    checkpoint: _StrPath | None = None,
    resume: _StrPath | None = None,
    checkpoint_every: float = 30.0,
    max_memory: int | str | None = None,
) -> dict[str, Any]: ...

def sh_index(l: int, m: int) -> int: ...
def sh_count(bands: int) -> int: ...
def sh_eval(dirs: ArrayLike, K: int) -> NDArray[np.float64]: ...
def sh_directions(
    sampler: str = "sobol", count: int = 1024, seed: int = 1
) -> tuple[NDArray[np.float32], NDArray[np.float32]]: ...
def sh_project(
    dirs: ArrayLike, values: ArrayLike, K: int, weights: ArrayLike | None = None
) -> NDArray[np.float64]: ...
def sh_reconstruct(coeffs: ArrayLike, dirs: ArrayLike) -> NDArray[np.float64]: ...
def sh_rotate(coeffs: ArrayLike, R: ArrayLike, method: str = "ivanic") -> NDArray[np.float64]: ...
def sh_window(coeffs: ArrayLike, kind: str, strength: float = 0.0) -> NDArray[np.float64]: ...
def sh_window_weights(kind: str, bands: int, strength: float = 0.0) -> list[float]: ...
def light(
    specs: str | Sequence[str] = "builtin",
    K: int = 16,
    rotate: Sequence[float] | None = None,
    window: str = "none",
    window_strength: float = 0.0,
) -> NDArray[np.float32]: ...
def light_from_equirect(image: ArrayLike, K: int = 16) -> NDArray[np.float32]: ...
def light_from_cube_cross(image: ArrayLike, K: int = 16) -> NDArray[np.float32]: ...
def light_rotate(light: ArrayLike, R: ArrayLike) -> NDArray[np.float32]: ...

# With the renderer only (HAS_RENDER).
def shade(
    file: File,
    light: ArrayLike,
    *,
    k: float = 1.0,
    gloss: float = 16.0,
    eye: Sequence[float] | None = None,
    shading_coeffs: int = 0,
    coeffs: int | None = None,
    brdf: str | None = None,
    albedo: Sequence[float] | None = None,
    direct: bool = False,
    glossy: str = "matrix",
    sun: str | Sequence[float] | None = None,
    sun_samples: int = 64,
) -> tuple[NDArray[np.float32], NDArray[np.float32]]: ...
def render(
    file: File,
    light: ArrayLike,
    *,
    width: int = 1280,
    height: int = 720,
    camera: Sequence[float] | None = None,
    fov: float | None = None,
    k: float = 1.0,
    gloss: float = 16.0,
    shading_coeffs: int = 0,
    coeffs: int | None = None,
    view: str = "radiance",
    background: bool = False,
    wireframe: bool = False,
    samples: int = 4,
    brdf: str | None = None,
    albedo: Sequence[float] | None = None,
    direct: bool = False,
    glossy: str = "matrix",
    sun: str | Sequence[float] | None = None,
    object: str | None = None,
    at: Sequence[float] | None = None,
    object_scale: float = 1.0,
    object_rotate: Sequence[float] | None = None,
) -> NDArray[np.float32]: ...
def save_image(path: str, image: ArrayLike, exposure: float = 1.0) -> None: ...
