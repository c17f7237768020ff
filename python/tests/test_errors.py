"""Bad input gives shprt.Error with the library's code and a message naming the problem."""
import numpy as np
import pytest

import shprt

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
F = np.array([[0, 1, 2]], dtype=np.int32)


def check(code, match, fn, *args, **kwargs):
    with pytest.raises(shprt.Error, match=match) as info:
        fn(*args, **kwargs)
    assert info.value.code == code, info.value
    assert isinstance(info.value, RuntimeError)


def test_bad_shapes():
    check("invalid_argument", r"vertices: expected an array of shape \(V, 3\), got \(3, 2\)",
          shprt.bake, V[:, :2], F)
    check("invalid_argument", r"faces: expected an array of shape \(T, 3\), got \(3,\)",
          shprt.bake, V, F[0])
    check("invalid_argument", r"normals", shprt.bake, V, F, normals=V[:2])
    check("invalid_argument", r"transfer: expected .* \(V, K\)", shprt.File,
          shprt.Mesh(V, F), np.zeros(3, np.float32))


def test_bad_dtypes():
    check("invalid_argument", r"vertices: expected a floating-point array .* got \(3, 3\) int64",
          shprt.bake, V.astype(np.int64), F)
    check("invalid_argument", r"faces: expected an integer array", shprt.bake, V,
          F.astype(np.float32))
    check("invalid_argument", r"vertices: expected a floating-point array", shprt.bake,
          np.array([["a", "b", "c"]] * 3), F)


def test_nan_and_bad_indices():
    bad = V.copy()
    bad[1, 2] = np.nan
    check("format", r"vertex 1 has a non-finite coordinate", shprt.bake, bad, F)
    check("format", r"index", shprt.bake, V, np.array([[0, 1, 3]]))
    check("invalid_argument", r"faces: triangle 0 has the index -1", shprt.bake, V,
          np.array([[0, 1, -1]]))


def test_bad_options():
    check("invalid_argument", r"bands=0", shprt.bake, V, F, bands=0)
    check("invalid_argument", r"both", shprt.bake, V, F, bands=2, coeffs=4)
    check("invalid_argument", r"samples=0", shprt.bake, V, F, samples=0)
    check("invalid_argument", r"bogus", shprt.bake, V, F, sampler="bogus")
    check("invalid_argument", r"progress: expected a callable", shprt.bake, V, F, progress=3)
    check("invalid_argument", r"faces .* is required", shprt.bake, V)


def test_files(tmp_path):
    check("io", r"cannot open", shprt.load, str(tmp_path / "missing.shprt"))
    junk = tmp_path / "junk.shprt"
    junk.write_bytes(b"not a shprt file at all, but long enough to have a header......")
    check("format", r"junk.shprt", shprt.load, str(junk))
    check("io", r"missing-dir", shprt.load_scene, str(tmp_path / "missing-dir" / "x.ply"))


def test_sh_and_light_arguments():
    check("invalid_argument", r"K=0", shprt.sh_eval, [[0.0, 0, 1]], 0)
    check("invalid_argument", r"direction 0 is zero", shprt.sh_eval, [[0.0, 0, 0]], 4)
    check("invalid_argument", r"not a rotation", shprt.sh_rotate, np.ones(4), np.ones((3, 3)))
    check("invalid_argument", r"R: expected an array of shape \(3, 3\)", shprt.sh_rotate,
          np.ones(4), np.eye(2))
    check("invalid_argument", r"unknown|sphinx|light", shprt.light, "sphinx", 9)
    f = shprt.File(shprt.Mesh(V, F), np.ones((3, 4), np.float32))
    check("invalid_argument", r"light: expected an array of shape \(3, K\)", shprt.shade, f,
          np.ones((4, 4)))


@pytest.mark.parametrize("project", ["light_from_equirect", "light_from_cube_cross"])
@pytest.mark.parametrize("value, match", [
    (np.nan, r"image array has a NaN value at pixel \(3, 2\) channel G"),
    (np.inf, r"image array has a infinite value at pixel \(3, 2\) channel G"),
    (-1.0, r"image array has a negative value -1 at pixel \(3, 2\) channel G"),
])
def test_a_light_image_is_checked_as_the_command_line_checks_a_file(project, value, match):
    # The same check (and words) as `shprt shade --light FILE.exr`: no NaN coefficients come out.
    image = np.ones((12, 16, 3), np.float32)
    image[2, 3, 1] = value
    check("format", match, getattr(shprt, project), image, K=9)
    check("format", r"NaN value at pixel \(0, 0\) channel R", getattr(shprt, project),
          np.full((12, 16, 3), np.nan, np.float32))


def test_a_light_too_bright_for_float_is_refused():
    check("invalid_argument", r"the image is too bright: its SH coefficient 0 of channel R "
                              r"overflows float",
          shprt.light_from_equirect, np.full((8, 16, 3), 3e38, np.float32))
    # A coefficient array given directly is checked as well (shade and render take them).
    bad = np.zeros((3, 4), np.float32)
    bad[1, 2] = np.nan
    check("invalid_argument", r"light is not a number: its SH coefficient 2 of channel G is NaN",
          shprt.light_rotate, bad, np.eye(3))
    bad[1, 2] = np.inf
    check("invalid_argument", r"light is too bright", shprt.light_rotate, bad, np.eye(3))


def test_shade_refuses_a_light_that_is_not_finite():
    f = shprt.File(shprt.Mesh(V, F), np.ones((3, 4), np.float32), samples=1)
    bad = np.full((3, 4), np.nan, np.float32)
    check("invalid_argument", r"light is not a number", shprt.shade, f, bad)
