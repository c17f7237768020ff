"""SH evaluation, projection, rotation, windowing; lights; shade and render."""
import math
from typing import Any

import numpy as np
import pytest

import shprt

SQRT_4PI = math.sqrt(4 * math.pi)


def random_rotation(seed):
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def test_sh_eval_known_values():
    y = shprt.sh_eval(np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]), 4)
    c1 = math.sqrt(3 / (4 * math.pi))
    # index l(l+1)+m: y_1^-1 = -c1·y, y_1^0 = c1·z, y_1^1 = -c1·x (Condon–Shortley phase)
    np.testing.assert_allclose(y, [[0.5 / math.sqrt(math.pi), -c1, 0, 0],
                                   [0.5 / math.sqrt(math.pi), 0, c1, 0]], atol=1e-12)
    assert shprt.sh_index(2, -1) == 5 and shprt.sh_count(4) == 16


def test_projection_round_trip():
    dirs, weights = shprt.sh_directions("sobol", 1 << 14, 1)
    assert dirs.shape == (1 << 14, 3) and np.isclose(weights.sum(), 4 * math.pi, rtol=1e-5)
    c = np.random.default_rng(1).normal(size=(2, 9))
    values = shprt.sh_eval(dirs.astype(np.float64), 9) @ c.T  # (S, 2)
    back = shprt.sh_project(dirs, values, 9, weights)
    np.testing.assert_allclose(back, c, atol=2e-2)
    np.testing.assert_allclose(shprt.sh_project(dirs, np.ones(len(dirs)), 4),
                               [SQRT_4PI, 0, 0, 0], atol=1e-3)
    np.testing.assert_allclose(shprt.sh_reconstruct(c, dirs[:5].astype(np.float64)),
                               values[:5], atol=1e-5)


def test_rotation_identity_and_band_norms():
    c = np.random.default_rng(2).normal(size=(3, 25))
    R = random_rotation(3)
    r = shprt.sh_rotate(c, R)
    np.testing.assert_allclose(shprt.sh_rotate(r, R.T), c, atol=1e-10)
    for lo, hi in [(0, 1), (1, 4), (4, 9), (9, 16), (16, 25)]:
        np.testing.assert_allclose(np.linalg.norm(r[:, lo:hi], axis=1),
                                   np.linalg.norm(c[:, lo:hi], axis=1), rtol=1e-10)
    # A lobe toward v ends toward R·v.
    v = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
    lobe = shprt.sh_eval(v[None], 25)[0]
    np.testing.assert_allclose(shprt.sh_rotate(lobe, R), shprt.sh_eval((R @ v)[None], 25)[0],
                               atol=1e-10)


def test_window():
    w = shprt.sh_window_weights("hann", 4)
    assert w[0] == 1 and all(0 <= x <= 1 for x in w)
    c = np.ones(16)
    np.testing.assert_allclose(shprt.sh_window(c, "hann"), np.repeat(w, [1, 3, 5, 7]))
    np.testing.assert_array_equal(shprt.sh_window(c, "none"), c)


def test_lights_from_specs_and_arrays():
    L = shprt.light("constant:1,2,3", K=9)
    assert L.shape == (3, 9) and L.dtype == np.float32
    np.testing.assert_allclose(L[:, 0], SQRT_4PI * np.array([1, 2, 3]), rtol=1e-6)
    np.testing.assert_allclose(L[:, 1:], 0, atol=1e-6)
    both = shprt.light(["constant", "sun:0,1,0"], K=9)
    np.testing.assert_allclose(both - shprt.light("sun:0,1,0", K=9), shprt.light("constant", K=9),
                               atol=1e-5)
    E = shprt.light_from_equirect(np.full((16, 32, 3), 2.0, np.float32), K=4)
    np.testing.assert_allclose(E[:, 0], 2 * SQRT_4PI, rtol=1e-5)
    np.testing.assert_allclose(E[:, 1:], 0, atol=1e-5)
    # Rotating the light by R moves the sun toward R·s.
    R = random_rotation(4)
    sun = shprt.light("sun:0,1,0", K=16)
    turned = shprt.light_rotate(sun, R)
    np.testing.assert_allclose(turned, shprt.sh_rotate(sun.astype(np.float64), R), atol=1e-4)


def test_shade_is_transfer_dot_light(box):
    T = shprt.bake(box, bands=3, samples=256)
    f = shprt.File(box, T)
    L = shprt.light("builtin", K=9)
    E, R = shprt.shade(f, L)
    assert E.shape == R.shape == (box.vertex_count, 3)
    np.testing.assert_allclose(E, T.astype(np.float64) @ L.T.astype(np.float64), rtol=1e-4,
                               atol=1e-4)
    np.testing.assert_allclose(R, box.albedo / math.pi * E, rtol=1e-4, atol=1e-5)


@pytest.mark.skipif(not shprt.HAS_RENDER, reason="this build has no renderer (render/)")
def test_render_to_array(box, tmp_path):
    f = shprt.File(box, shprt.bake(box, bands=3, samples=256))
    L = shprt.light("builtin", K=9)
    img = shprt.render(f, L, width=96, height=64, samples=1)
    assert img.shape == (64, 96, 3) and img.dtype == np.float32
    assert np.isfinite(img).all() and img.mean() > 0.01
    again = shprt.render(f, L, width=96, height=64, samples=1)
    assert np.array_equal(img, again)
    ao = shprt.render(f, L, width=96, height=64, samples=1, view="transfer",
                      camera=(3, 3, 3, 0, 0, 0))
    assert ao.max() <= 1.5
    shprt.save_image(str(tmp_path / "box.png"), img)
    assert (tmp_path / "box.png").stat().st_size > 100


def test_light_from_a_file_equals_light_from_the_array(tmp_path):
    sky = np.random.default_rng(5).uniform(0.5, 2.0, size=(16, 32, 3)).astype(np.float32)
    shprt.save_image(str(tmp_path / "sky.exr"), sky)
    from_file = shprt.light(str(tmp_path / "sky.exr"), K=16)
    np.testing.assert_allclose(from_file, shprt.light_from_equirect(sky, K=16), rtol=1e-3,
                               atol=1e-3)


def test_an_interreflected_files_direct_part_shades_as_the_command_line_shades_it(
        box, tmp_path, cli):
    path = str(tmp_path / "i.shprt")
    cli("bake", "builtin:box_on_plane", "--transfer", "interreflected", "--bounces", "2",
        "--bands", "3", "--samples", "128", "-o", path)
    f = shprt.load(path)
    assert f.channels == 3 and f.direct is not None and f.direct.shape == (box.vertex_count, 9)
    out = str(tmp_path / "d.csv")
    cli("shade", path, "--direct", "--light", "builtin", "-o", out)
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    L = shprt.light("builtin", K=9)
    E, R = shprt.shade(f, L, direct=True)
    np.testing.assert_allclose(E, rows[:, 3:6], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(R, rows[:, 6:9], rtol=1e-6, atol=1e-6)
    # The same as shading File.direct as a file of its own; the bounces add light.
    E0, _ = shprt.shade(shprt.File(box, np.array(f.direct)), L)
    np.testing.assert_allclose(E, E0, rtol=1e-6, atol=1e-7)
    E_all, _ = shprt.shade(f, L)
    assert (E_all >= E - 1e-5).all() and (E_all - E).max() > 1e-3
    if shprt.HAS_RENDER:
        kw: dict[str, Any] = dict(width=48, height=32, samples=1)
        assert np.abs(shprt.render(f, L, direct=True, **kw) - shprt.render(f, L, **kw)).max() > 1e-3
    # Other files have no direct part.
    shadowed = shprt.File(box, shprt.bake(box, bands=3, samples=64))
    assert shadowed.direct is None
    with pytest.raises(shprt.Error, match="has no direct part"):
        shprt.shade(shadowed, L, direct=True)


def test_a_sun_kept_out_of_the_sh_sum_shades_as_the_command_line_shades_it(box, tmp_path, cli):
    path, out = str(tmp_path / "i.shprt"), str(tmp_path / "s.csv")
    cli("bake", "builtin:box_on_plane", "--transfer", "interreflected", "--bounces", "1",
        "--bands", "3", "--samples", "128", "-o", path)
    f = shprt.load(path)
    stdout = cli("shade", path, "--light", "gradient", "--sun", "1,1,0.3,2", "--sun-samples", "16",
                 "-o", out)
    assert "bounced light from the file's T - T0" in stdout
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    sky = shprt.light("gradient", K=9)
    E, R = shprt.shade(f, sky, sun="1,1,0.3,2", sun_samples=16)
    np.testing.assert_allclose(E, rows[:, 3:6], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(R, rows[:, 6:9], rtol=1e-6, atol=1e-6)
    E2, _ = shprt.shade(f, sky, sun=[1, 1, 0.3, 2], sun_samples=16)
    np.testing.assert_array_equal(E, E2)
    # The sun adds light.
    E_sky, _ = shprt.shade(f, sky)
    assert ((E - E_sky)[:, 0] > 1e-3).sum() > 0
    with pytest.raises(shprt.Error, match=r"sun='1,2': expected X,Y,Z"):
        shprt.shade(f, sky, sun="1,2")
    with pytest.raises(shprt.Error, match="sun_samples=9 needs sun="):
        shprt.shade(f, sky, sun_samples=9)


@pytest.mark.skipif(not shprt.HAS_RENDER, reason="this build has no renderer (render/)")
def test_render_draws_a_sun_kept_out_of_the_sh_sum(box):
    # render(sun=) is `shprt render --sun` (tests/cli/test_cli_view.cpp compares that with the
    # viewer's picture): the shadow-mapped sun beside the sky, its shadow on the floor.
    f = shprt.File(box, shprt.bake(box, bands=3, samples=128))
    sky = shprt.light("gradient", K=9)
    camera = (-0.4, 2.6, 1.7, -1.0, 0.0, 0.0)  # above the shadow, which falls toward -x
    with_sun = shprt.render(f, sky, sun="1,1.2,0.3,2", width=96, height=64, samples=1,
                            camera=camera)
    assert np.array_equal(with_sun, shprt.render(f, sky, sun=[1, 1.2, 0.3, 2], width=96,
                                                 height=64, samples=1, camera=camera))
    sky_only = shprt.render(f, sky, width=96, height=64, samples=1, camera=camera)
    added = (with_sun - sky_only)[:, :, 0]
    assert added.min() >= -1e-6
    # Lit floor gains the sun; the shadow gains nothing: both are large parts of the picture.
    assert (added > 0.1).mean() > 0.2 and (np.abs(added) < 1e-6).mean() > 0.03
    with pytest.raises(shprt.Error, match=r"sun='1,2': expected X,Y,Z"):
        shprt.render(f, sky, sun="1,2")
    with pytest.raises(shprt.Error, match="lights diffuse receivers only"):
        shprt.render(f, sky, sun="1,1,1", k=0.5)


def test_a_texel_file_shades_per_texel_as_the_command_line_shades_it(tmp_path, cli):
    path, npy = str(tmp_path / "t.shprt"), str(tmp_path / "e.npy")
    cli("bake", "builtin:quad_box", "--domain", "texel", "--resolution", "16", "--coeffs", "4",
        "--samples", "64", "-o", path)
    cli("shade", path, "--light", "builtin", "-o", npy)
    image = np.load(npy)  # (H, W, 3), NaN outside the charts
    covered = ~np.isnan(image[:, :, 0])
    f = shprt.load(path)
    E, R = shprt.shade(f, shprt.light("builtin", K=4))
    assert E.shape == (f.transfer.shape[0], 3) == (covered.sum(), 3)
    np.testing.assert_allclose(E, image[covered], rtol=1e-6, atol=1e-6)


def test_shade_writes_named_arrays_to_npz_and_exact_floats_to_ply(box, tmp_path, cli):
    # `shprt shade -o OUT.npz`: numpy.load gives position, irradiance and radiance by name, the
    # numbers Python's shade() returns; the PLY's float properties hold the same values.
    path, npz = str(tmp_path / "b.shprt"), str(tmp_path / "s.npz")
    cli("bake", "builtin:box_on_plane", "--bands", "3", "--samples", "64", "-o", path)
    cli("shade", path, "--light", "builtin", "-o", npz)
    E, R = shprt.shade(shprt.load(path), shprt.light("builtin", K=9))
    with np.load(npz) as arrays:
        assert sorted(arrays.files) == ["irradiance", "position", "radiance"]
        np.testing.assert_allclose(arrays["irradiance"], E, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(arrays["radiance"], R, rtol=1e-6, atol=1e-6)
        assert arrays["position"].shape == (box.vertex_count, 3)
