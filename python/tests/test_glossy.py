"""Glossy transfer matrices from Python: a File from bake(transfer='glossy'), shaded with a BRDF
(shade and render, brdf= and albedo=) as `shprt shade --brdf` shades it."""
from typing import Any, Callable

import numpy as np
import pytest

import shprt

needs_render = pytest.mark.skipif(not shprt.HAS_RENDER,
                                  reason="this build has no renderer (render/)")


@pytest.fixture(scope="module")
def glossy_box(box):
    T = shprt.bake(box, bands=3, samples=256, transfer="glossy", seed=3)
    return shprt.File(box, T, kind="glossy", samples=256, seed=3)


def test_a_glossy_file_holds_packed_matrices_and_round_trips(box, glossy_box, tmp_path):
    f = glossy_box
    assert f.K == 9 and f.channels == 1 and f.kind == "glossy"
    assert f.transfer.shape == (box.vertex_count, 45)
    path = str(tmp_path / "g.shprt")
    shprt.save(path, f)
    back = shprt.load(path)
    assert back.K == 9 and back.kind == "glossy"
    assert np.array_equal(back.transfer, f.transfer)
    with pytest.raises(shprt.Error, match=r"kind 'glossy' expects \(V, K\(K\+1\)/2\)"):
        shprt.File(box, f.transfer[:, :44], kind="glossy")
    with pytest.raises(shprt.Error, match="kind 'glossy' expects"):
        shprt.File(box, np.stack([f.transfer] * 3, axis=1), kind="glossy")


def test_shade_with_a_brdf_is_what_the_command_line_shades(glossy_box, tmp_path, cli):
    path = str(tmp_path / "g.shprt")
    shprt.save(path, glossy_box)
    out = str(tmp_path / "g.csv")
    cli("shade", path, "--brdf", "ggx:0.4:1,0.71,0.29", "--k", "0.3", "--eye", "1,2,3",
        "--light", "sun:0.3,1,0.2,5", "--light", "constant:0.2", "-o", out)
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    L = shprt.light(["sun:0.3,1,0.2,5", "constant:0.2"], K=9)
    E, R = shprt.shade(glossy_box, L, brdf="ggx:0.4:1,0.71,0.29", k=0.3, eye=(1, 2, 3))
    np.testing.assert_allclose(E, rows[:, 3:6], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(R, rows[:, 6:9], rtol=1e-6, atol=1e-6)
    # The specular colour reaches the radiance: white gives another answer.
    _, white = shprt.shade(glossy_box, L, brdf="ggx:0.4", k=0.3, eye=(1, 2, 3))
    assert np.abs(white - R).max() > 1e-3
    # albedo replaces both colours: the same as a white lobe on a white surface, scaled.
    _, grey = shprt.shade(glossy_box, L, brdf="ggx:0.4:0.5,0.5,0.5", k=0.3, eye=(1, 2, 3),
                          albedo=(0.5, 0.5, 0.5))
    _, one = shprt.shade(glossy_box, L, brdf="ggx:0.4", k=0.3, eye=(1, 2, 3), albedo=(1, 1, 1))
    np.testing.assert_allclose(grey, 0.5 * one, rtol=1e-5, atol=1e-7)


def test_without_a_brdf_the_materials_shade_their_vertices(tmp_path, cli):
    spheres = shprt.load_scene("builtin:gloss_spheres")
    f = shprt.File(spheres, shprt.bake(spheres, bands=3, samples=64, transfer="glossy"),
                   kind="glossy", samples=64)
    L = shprt.light("sun:-0.5,0.8,0.4,8", K=9)
    eye = (0, 1.6, 4)
    _, materials = shprt.shade(f, L, k=0.4, eye=eye)
    _, gold = shprt.shade(f, L, k=0.4, eye=eye, brdf="ggx:0.8:1,0.71,0.29")
    _, floor = shprt.shade(f, L, k=0.4, eye=eye, gloss=16)  # no material: phong:gloss
    _, phong16 = shprt.shade(f, L, k=0.4, eye=eye, brdf="phong:16")
    floor_vertices = 29 * 57  # builtin:gloss_spheres' floor comes first, then 4 × 642 per sphere
    second = slice(floor_vertices + 642, floor_vertices + 2 * 642)
    np.testing.assert_array_equal(materials[second], gold[second])
    np.testing.assert_array_equal(floor[:floor_vertices], phong16[:floor_vertices])
    assert np.abs(materials[second] - phong16[second]).max() > 1e-3
    # materials+SPEC: the materials' BRDFs where they give one and SPEC elsewhere (the viewer's
    # panel's "material BRDFs" with a lobe), the same in Python and on the command line.
    _, mixed = shprt.shade(f, L, k=0.4, eye=eye, brdf="materials+ggx:0.25")
    _, ggx = shprt.shade(f, L, k=0.4, eye=eye, brdf="ggx:0.25")
    np.testing.assert_array_equal(mixed[second], gold[second])
    np.testing.assert_array_equal(mixed[:floor_vertices], ggx[:floor_vertices])
    _, plain = shprt.shade(f, L, k=0.4, eye=eye, brdf="materials")
    np.testing.assert_array_equal(plain, materials)
    path, out = str(tmp_path / "spheres.shprt"), str(tmp_path / "mixed.csv")
    shprt.save(path, f)
    cli("shade", path, "--brdf", "materials+ggx:0.25", "--k", "0.4", "--eye", "0,1.6,4",
        "--light", "sun:-0.5,0.8,0.4,8", "-o", out)
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(mixed, rows[:, 6:9], rtol=1e-6, atol=1e-6)
    with pytest.raises(shprt.Error, match="expected materials, materials\\+SPEC"):
        shprt.shade(f, L, brdf="materials-ggx:0.25")


@needs_render
def test_render_takes_the_brdf(box, glossy_box):
    L = shprt.light("builtin", K=9)
    kw: dict[str, Any] = dict(width=64, height=48, samples=1, k=0.3, camera=(2.5, 2, 2.5, 0, 0.3, 0))
    gold = shprt.render(glossy_box, L, brdf="ggx:0.4:1,0.71,0.29", **kw)
    white = shprt.render(glossy_box, L, brdf="ggx:0.4", **kw)
    assert np.isfinite(gold).all() and gold.mean() > 0.01
    assert np.abs(gold - white).max() > 1e-3


def test_vector_files_refuse_a_brdf(box, glossy_box):
    L = shprt.light("builtin", K=9)
    vector = shprt.File(box, shprt.bake(box, bands=3, samples=64))
    calls: list[Callable[..., Any]] = [shprt.shade]
    if shprt.HAS_RENDER:
        calls.append(lambda f, l, **a: shprt.render(f, l, samples=1, **a))
    for call in calls:
        with pytest.raises(shprt.Error, match=r"brdf= needs a glossy bake \(transfer=glossy\)"):
            call(vector, L, brdf="phong:16")
        with pytest.raises(shprt.Error, match="albedo= needs brdf="):
            call(vector, L, albedo=(1, 1, 1))
    with pytest.raises(shprt.Error, match="unknown model"):
        shprt.shade(glossy_box, L, brdf="lambert:1")
    with pytest.raises(shprt.Error, match="specular colour"):
        shprt.shade(glossy_box, L, brdf="phong:16:2,0,0")


def test_compress_is_what_the_command_line_compresses(box, glossy_box, tmp_path, cli):
    # One cluster per vertex holds every row exactly.
    exact, report = shprt.compress(glossy_box, box.vertex_count, 1)
    assert report["relative_rmse"] == 0.0
    assert np.array_equal(exact.transfer, glossy_box.transfer)
    # 8 clusters x 4 vectors: the rows the command line's file rebuilds, and its error.
    path, out = str(tmp_path / "g.shprt"), str(tmp_path / "c.shprt")
    shprt.save(path, glossy_box)
    printed = cli("compress", path, "-o", out, "--cpca", "8,4")
    coded, report = shprt.compress(glossy_box, 8, 4)
    assert np.array_equal(coded.transfer, shprt.load(out).transfer)
    assert f"relative RMSE {100 * report['relative_rmse']:.3f}%" in printed
    assert 0 < report["relative_rmse"] < 0.5
    assert report["receiver_rmse"].shape == (box.vertex_count,)
    assert report["bytes_per_receiver"] < report["raw_bytes_per_receiver"] == 4 * 45
    assert report["direct_bytes_per_receiver"] == 0
    # The coded File saves as a CPCA file and reads back to the same rows.
    saved = str(tmp_path / "p.shprt")
    shprt.save(saved, coded)
    assert "cpca         8 clusters x 4 vectors" in shprt.load(saved).summary()
    assert np.array_equal(shprt.load(saved).transfer, coded.transfer)
    with pytest.raises(shprt.Error, match="clusters"):
        shprt.compress(glossy_box, 0, 4)
    with pytest.raises(shprt.Error, match="vectors"):
        shprt.compress(glossy_box, 8, 46)
