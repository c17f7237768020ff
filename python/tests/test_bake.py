"""shprt.bake against the C++ results: the same options and seed give the bits of `shprt bake`."""
from typing import Any

import numpy as np
import pytest

import shprt

CASES = [
    dict(bands=3, samples=256, sampler="sobol", transfer="shadowed", seed=1),
    dict(coeffs=10, samples=200, sampler="uniform", transfer="shadowed", seed=7, threads=1),
    dict(bands=2, samples=128, sampler="fibonacci", transfer="unshadowed", seed=3),
    dict(bands=2, samples=128, sampler="sobol", transfer="interreflected", bounces=2, seed=1),
    dict(bands=1, samples=64, sampler="sobol", transfer="interreflected", bounces="converged",
         tolerance=1e-3, seed=2),
    dict(bands=2, samples=256, sampler="sobol", transfer="interreflected", bounces=2, seed=1,
         indirect_samples=32, source_spacing=0.3, two_sided=True),
    dict(bands=2, samples=128, sampler="sobol", transfer="interreflected", bounces=1, seed=4,
         source_spacing="vertices"),
]


def cli_args(case):
    args = []
    for key, value in case.items():
        option = "--" + key.replace("_", "-")
        args += [option] if value is True else [option, value]
    return args


@pytest.mark.parametrize("case", CASES,
                         ids=lambda c: f"{c['sampler']}-{c['transfer']}-{c.get('bounces', '')}")
def test_bake_arrays_bit_identical_to_cli(cli, tmp_path, case):
    out = tmp_path / "box.shprt"
    cli("bake", "builtin:box_on_plane", "-o", out, *cli_args(case))
    baked = shprt.load(str(out))
    m = baked.mesh
    T = shprt.bake(m.positions, m.triangles, m.normals, m.albedo, **case)
    assert T.dtype == np.float32 and T.shape == baked.transfer.shape
    assert T.tobytes() == baked.transfer.tobytes()
    assert baked.samples == case["samples"] and baked.seed == case["seed"]


def test_bake_of_a_ply_file_bit_identical_to_cli(cli, tmp_path):
    ply = tmp_path / "sphere.ply"
    cli("scene", "sphere", "-o", ply)
    cli("bake", ply, "-o", tmp_path / "s.shprt", "--bands", 4, "--samples", 512)
    mesh = shprt.load_scene(str(ply))  # the scene loader, as the batch example uses it
    T = shprt.bake(mesh, bands=4, samples=512)
    assert T.tobytes() == shprt.load(str(tmp_path / "s.shprt")).transfer.tobytes()


def test_shadow_makes_a_difference(box):
    shadowed = shprt.bake(box, bands=2, samples=256)
    unshadowed = shprt.bake(box, bands=2, samples=256, transfer="unshadowed")
    assert shadowed.shape == (box.vertex_count, 4)
    assert np.all(shadowed[:, 0] <= unshadowed[:, 0] + 1e-5)
    assert np.any(shadowed[:, 0] < unshadowed[:, 0] - 0.1)


def test_default_normals_and_input_dtypes(sphere):
    # float64 vertices, int64 faces and no normals: the mesh's normals are computed (for the
    # icosphere they equal the positions to rounding), so the bake is close to the mesh's.
    v = sphere.positions.astype(np.float64)
    f = sphere.triangles.astype(np.int64)
    T = shprt.bake(v, f, bands=2, samples=256)
    ref = shprt.bake(sphere, bands=2, samples=256)
    np.testing.assert_allclose(T, ref, atol=2e-2)


def test_output_owns_its_buffer_without_copy(box):
    T = shprt.bake(box, bands=2, samples=64)
    assert not T.flags.owndata and T.base is not None  # the library's vector, in a capsule
    assert T.flags.c_contiguous and T.flags.writeable


def test_save_load_round_trip(box, tmp_path, cli):
    T = shprt.bake(box, bands=3, samples=256, seed=5)
    path = tmp_path / "box.shprt"
    shprt.save(str(path), box, T, samples=256, seed=5)
    f = shprt.load(str(path))
    assert f.transfer.tobytes() == T.tobytes()
    assert f.K == 9 and f.channels == 1 and f.kind == "shadowed" and f.seed == 5
    assert f.sampler == "sobol" and shprt.metadata(f)["samples"] == 256
    for name in ("positions", "normals", "albedo", "triangles"):
        assert np.array_equal(getattr(f.mesh, name), getattr(box, name)), name
    # The file's arrays are views of the loaded file (no copies).
    assert np.shares_memory(f.transfer, f.transfer) and not f.transfer.flags.owndata
    # The command line reads what Python wrote.
    assert "K" in cli("info", path)
    # float16 storage.
    shprt.save(str(tmp_path / "h.shprt"), shprt.File(box, T, samples=256, encoding="float16"))
    h = shprt.load(str(tmp_path / "h.shprt"))
    assert h.encoding == "float16"
    np.testing.assert_allclose(h.transfer, T, rtol=1e-3, atol=1e-3)


def test_a_file_without_its_sample_count_is_not_written(box, tmp_path):
    # samples = 0 says "no directions": only unshadowed transfer has a closed form, so a shadowed
    # file saying 0 is refused by the reader, and the writer refuses it first (file and field).
    T = shprt.bake(box, bands=2, samples=64)
    with pytest.raises(shprt.Error, match=r"z\.shprt: samples = 0 for shadowed transfer"):
        shprt.save(str(tmp_path / "z.shprt"), box, T)
    assert not (tmp_path / "z.shprt").exists()
    shprt.save(str(tmp_path / "u.shprt"), box, T, kind="unshadowed")
    assert shprt.load(str(tmp_path / "u.shprt")).samples == 0


def test_bad_bounce_source_options_are_refused(box):
    bads: list[dict[str, Any]] = [dict(source_spacing=0), dict(source_spacing=-1.0),
                                  dict(source_spacing="cells"), dict(indirect_samples=-1)]
    for bad in bads:
        with pytest.raises(shprt.Error):
            shprt.bake(box, bands=1, samples=64, transfer="interreflected", **bad)
    with pytest.raises(shprt.Error, match="need transfer='interreflected'"):
        shprt.bake(box, bands=1, samples=64, indirect_samples=8)


def test_interreflected_bounces_add_light_and_bad_bounces_are_refused(box):
    T0 = shprt.bake(box, bands=2, samples=128, transfer="interreflected", bounces=0)
    T2 = shprt.bake(box, bands=2, samples=128, transfer="interreflected", bounces=2)
    assert T0.shape == T2.shape == (len(box.positions), 3, 4)
    # The box's vertices on the floor see light off the box: more DC, never less.
    assert (T2[:, :, 0] >= T0[:, :, 0]).all() and (T2[:, :, 0] > T0[:, :, 0]).any()
    wrong: list[Any] = [-1, "forever", 1.5, True]
    for bad in wrong:
        with pytest.raises(shprt.Error):
            shprt.bake(box, bands=2, samples=64, transfer="interreflected", bounces=bad)


def test_rgb_transfer_shape(box):
    T = shprt.bake(box, bands=2, samples=64)
    rgb = np.stack([T, 0.5 * T, 0.25 * T], axis=1)  # (V, 3, K)
    f = shprt.File(box, rgb)
    assert f.channels == 3 and f.transfer.shape == rgb.shape
    assert np.array_equal(f.transfer, rgb)


def test_unwrap_bakes_a_mesh_without_uvs(tmp_path):
    """unwrap=True lays out a new atlas (the dict says how: charts, resolution, texels per metre,
    stretch) and the file keeps the unwrapped mesh with its UVs."""
    out = tmp_path / "u.shprt"
    mesh = shprt.load_scene("builtin:sphere")
    result: Any = shprt.bake(mesh, coeffs=4, samples=16, domain="texel", unwrap=True,
                             texel_density=20, output=out)
    unwrap = result["unwrap"]
    assert unwrap["texels_per_metre"] == 20
    assert 1 <= unwrap["max_stretch"] <= 2
    assert "overlap 0" in unwrap["summary"]
    f = shprt.load(str(out))
    assert f.mesh.vertex_count == mesh.vertex_count + unwrap["added_vertices"]
    assert result["covered_texels"] > 0


def test_probes_go_into_the_file_as_the_command_line_bakes_them(box, tmp_path, cli):
    # The same grid spelled as a tuple and as the command line's text: the same bytes.
    out = tmp_path / "p.shprt"
    done = shprt.bake(box, bands=2, samples=64, probes=(3, 2, 3), probe_box=(-1, 0, -1, 1, 1, 1),
                      probe_bands=2, output=out, reproducible=True)
    assert done["probes"]["counts"] == (3, 2, 3)
    assert done["probes"]["K"] == 4 and done["probes"]["channels"] == 1
    assert 0 < done["probes"]["valid"] <= 18
    cli("bake", "builtin:box_on_plane", "--bands", "2", "--samples", "64", "--probes", "3,2,3",
        "--probe-box", "-1,0,-1,1,1,1", "--probe-bands", "2", "--reproducible", "-o",
        tmp_path / "c.shprt")
    assert out.read_bytes() == (tmp_path / "c.shprt").read_bytes()
    with pytest.raises(shprt.Error, match="probes: the probes are written into the .shprt file"):
        shprt.bake(box, bands=2, samples=64, probes="auto")
    with pytest.raises(shprt.Error, match="probes: expected a str or 3 numbers"):
        shprt.bake(box, bands=2, samples=64, probes=(3, 2), output=out)  # type: ignore[arg-type]


def test_probes_compress_as_the_command_line_compresses_them(box, tmp_path, cli):
    # compress(probe_cpca=) writes the bytes `shprt compress --probe-cpca` writes.
    raw = tmp_path / "p.shprt"
    shprt.bake(box, bands=2, samples=64, probes=(3, 2, 3), probe_box=(-1, 0, -1, 1, 1, 1),
               probe_bands=2, output=raw, reproducible=True)
    packed, report = shprt.compress(shprt.load(str(raw)), 8, 2, probe_cpca=(2, 2))
    assert 0 < report["probe_relative_rmse"] < 1
    assert report["bytes_per_probe"] < report["raw_bytes_per_probe"] == 64
    shprt.save(str(tmp_path / "py.shprt"), packed, reproducible=True)
    cli("compress", raw, "-o", tmp_path / "c.shprt", "--cpca", "8,2", "--probe-cpca", "2,2",
        "--reproducible")
    assert (tmp_path / "py.shprt").read_bytes() == (tmp_path / "c.shprt").read_bytes()
    assert "; CPCA 2 clusters x 2 vectors" in shprt.load(str(tmp_path / "py.shprt")).summary()
    with pytest.raises(shprt.Error, match="clusters = 99 must be 1 to the valid probes"):
        shprt.compress(shprt.load(str(raw)), 8, 2, probe_cpca=(99, 3))
    shprt.bake(box, bands=2, samples=16, output=tmp_path / "n.shprt")
    with pytest.raises(shprt.Error, match="the file has no probes"):
        shprt.compress(shprt.load(str(tmp_path / "n.shprt")), 8, 2, probe_cpca=(2, 2))
