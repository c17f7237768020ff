"""The bake options that exist both on the command line (`shprt bake --help`) and in Python
(shprt.bake's signature) take the same values: each is tried inside, at and past its limits on
both, both must accept or both refuse, and what both accept writes the same bytes (both bake into
a reproducible .shprt file). The defaults agree too. (Issue 35: the front ends had drifted —
bounces up to 10000 on one and 1000 on the other, a glossy default of K = 25 on one and 16 on the
other.)

Every option found in both must have a row in PROBES: a new shared option without one fails here.
"""
import re
from typing import Any

import pytest

import shprt

SCENE = "builtin:box_on_plane"
TEXEL_SCENE = "builtin:quad_box"  # has UVs
BASE = dict(samples=16, reproducible=True)  # small bakes: the values are the point, not the light

# option -> (extra options the values need, values to try). A value is tried as `--option value`
# (True: the bare flag) and as option=value; "{tmp}" is the test's folder. "scene" picks the scene.
INTERREFLECTED = dict(transfer="interreflected", bands=1)
TEXELS = dict(scene=TEXEL_SCENE, domain="texel", resolution="8")
PROBES: dict[str, tuple[dict[str, Any], list[Any]]] = {
    "bands": ({}, [0, 1, 3, 8, 33, -1]),
    "coeffs": ({}, [0, 1, 10, 1024, 1025]),
    "samples": ({}, [0, 1, 17, 16777217]),
    "sampler": ({}, ["sobol", "uniform", "stratified", "fibonacci", "halton"]),
    "directions": ({}, ["sphere", "local", "tangent"]),
    "target_error": ({}, [0, 0.05, 1, 1.5, -0.1]),
    "max_samples": (dict(target_error=0.05), [0, 64, 128, 100, 32, 33554432]),
    "transfer": ({}, ["unshadowed", "shadowed", "glossy", "interreflected", "specular"]),
    "seed": ({}, [0, 7, 2**64 - 1]),
    "threads": ({}, [-1, 0, 1, 4097]),
    "device": ({}, ["cpu", "gpu"]),
    "bounces": (INTERREFLECTED, [-1, 0, 2, 10000, 10001, "converged", "many"]),
    "tolerance": (dict(INTERREFLECTED, bounces="converged"), [0, 1e-3, 0.5, 1, 2]),
    "two_sided": (INTERREFLECTED, [True]),
    "indirect_samples": (INTERREFLECTED, [-1, 1, 8, 16777217]),
    "source_spacing": (INTERREFLECTED, ["vertices", 0.25, 0, -1]),
    "bounce_coeffs": (dict(INTERREFLECTED, bands=2), [-1, 1, 4, 5]),
    "domain": (dict(scene=TEXEL_SCENE), ["vertex", "texel", "face"]),
    "resolution": (dict(scene=TEXEL_SCENE, domain="texel"), ["8", "8x4", "0", "16385", "x"]),
    "uv_set": (TEXELS, [0, 1, -1]),
    "float32": (TEXELS, [True]),
    "unwrap": (dict(domain="texel", resolution="16"), [True]),
    "texel_density": (dict(domain="texel", unwrap=True), [4, 0, -1]),
    "refine": ({}, [0.2, 0, -1]),
    "max_vertices": (dict(refine=0.2), [1, 100000, 0]),
    "max_edge_split_depth": (dict(refine=0.2), [0, 1, 30, 31]),
    "shard": ({}, ["0/2", "1/2", "2/2", "x", "-1/2"]),
    "probes": ({}, ["auto", "auto:0.5", "2,2,2", "2,2,2:0.5", "0,1,1", "x", "1,1", "auto:-1"]),
    "probe_box": (dict(probes="2,2,2"), ["-1,0,-1,1,1,1", "1,0,0,0,1,1", "1,2"]),
    "probe_bands": (dict(probes="2,2,2"), [0, 1, 3, 8, 9]),
    "half": ({}, [True]),
    "stream": ({}, [True]),
    "reproducible": ({}, [True]),
    "checkpoint": ({}, ["{tmp}/c.ckpt"]),
    "resume": ({}, ["{tmp}/missing.ckpt"]),
    "checkpoint_every": (dict(checkpoint="{tmp}/c.ckpt"), [0, 5, -1]),
    "max_memory": ({}, ["1G", "1K", "lots", "0"]),
}

# Names both front ends have that mean different things, and why; and the harness's own.
NOT_THE_SAME = {
    "albedo": "the command line's is one R,G,B for every vertex; Python's the per-vertex array",
}
HARNESS = {"output"}  # both always write a file here


def cli_options(cli_process):
    text = cli_process("bake", "--help").stdout
    return {m.replace("-", "_") for m in re.findall(r"--([a-z][a-z0-9-]*)", text)}


def python_options():
    signature = (shprt.bake.__doc__ or "").splitlines()[0]
    return set(re.findall(r"\b([a-z_0-9]+)\s*[:=]", signature))


def test_every_shared_option_is_probed(cli_process):
    shared = (cli_options(cli_process) & python_options()) - set(NOT_THE_SAME) - HARNESS
    assert {"bands", "samples", "bounces", "shard", "resolution"} <= shared, shared
    assert shared <= set(PROBES), f"shared options without a probe: {sorted(shared - set(PROBES))}"


def cli_args(options):
    args = []
    for key, value in options.items():
        option = "--" + key.replace("_", "-")
        args += [option] if value is True else [option, str(value)]
    return args


def fresh(tmp_path, name):
    for leftover in tmp_path.glob("*"):
        leftover.unlink()
    return tmp_path / name


def bake_cli(cli_process, tmp_path, scene, options):
    out = fresh(tmp_path, "cli.shprt")
    done = cli_process("bake", scene, "-o", out, *cli_args(options))
    return (out.read_bytes() if done.returncode == 0 else None), done.stderr.strip()


def bake_python(tmp_path, scene, options):
    out = fresh(tmp_path, "py.shprt")
    try:
        shprt.bake(shprt.load_scene(scene), output=out, **options)
    except (shprt.Error, TypeError, ValueError, OverflowError) as e:
        return None, str(e)
    return out.read_bytes(), ""


def with_tmp(options, tmp_path):
    return {k: v.replace("{tmp}", str(tmp_path)) if isinstance(v, str) else v
            for k, v in options.items()}


@pytest.mark.parametrize("option", sorted(PROBES))
def test_shared_option_takes_the_same_values(cli_process, tmp_path, option):
    extra, values = PROBES[option]
    for value in values:
        options = dict(BASE, **extra)
        options[option] = value
        options = with_tmp(options, tmp_path)
        scene = options.pop("scene", SCENE)
        cli, cli_error = bake_cli(cli_process, tmp_path, scene, options)
        py, py_error = bake_python(tmp_path, scene, options)
        assert (cli is None) == (py is None), (
            f"{option}={value!r}: the command line {'refused' if cli is None else 'accepted'} it "
            f"({cli_error}), Python {'refused' if py is None else 'accepted'} it ({py_error})")
        assert cli == py, f"{option}={value!r}: the two files differ"


@pytest.mark.parametrize("transfer", ["shadowed", "glossy", "interreflected"])
def test_defaults_agree(cli_process, tmp_path, transfer):
    cli, error = bake_cli(cli_process, tmp_path, SCENE, dict(BASE, transfer=transfer))
    assert cli is not None, error
    py, error = bake_python(tmp_path, SCENE, dict(BASE, transfer=transfer))
    assert py is not None, error
    assert cli == py
