"""The shading options that exist both on the command line (`shprt shade --help`) and in Python
(shprt.shade's signature) take the same values: each is tried inside, at and past its limits on
both, both must accept or both refuse, and what both accept gives the same irradiance and radiance.
The defaults agree too. (Issue 35: one ShadingParams, shade/params.hpp, checked and resolved once;
before it the front ends had drifted — Python shaded the glossy term from an eye at the origin where
the command line takes the default camera's, and had no `glossy='paper'`.)

Every option found in both must have a row in PROBES: a new shared option without one fails here.
"""
import re
import warnings
from typing import Any

import numpy as np
import pytest

import shprt

LIGHT = "builtin"
K = 9

# option -> (the file it shades and the options the values need, values to try). A value is tried
# as `--option value` (True: the bare flag) and as option=value.
GLOSSY: dict[str, Any] = dict(file="glossy")
PROBES: dict[str, tuple[dict[str, Any], list[Any]]] = {
    "k": ({}, [-0.1, 0, 0.35, 1, 1.5]),
    "gloss": (dict(k=0.5), [-1, 0, 3.5, 1e4]),
    "shading_coeffs": ({}, [-1, 0, 1, 4, 9, 100]),
    "coeffs": ({}, [-1, 0, 4]),  # the deprecated name of shading_coeffs in both
    "eye": (dict(k=0.5), [(1, 2, 3), (0, 0, 0)]),
    "direct": (dict(file="interreflected"), [True]),
    "brdf": (GLOSSY, ["phong:16", "ggx:0.3:1,0.7,0.2", "blinn:40", "ggx:-1", "lambert:1"]),
    "albedo": (dict(GLOSSY, brdf="ggx:0.3"), [(0.5, 0.25, 1), (0, 0, 0), (1.5, 0, 0)]),
    "glossy": (dict(GLOSSY, k=0.5), ["matrix", "paper", "both"]),
    "sun": (dict(file="interreflected"), ["1,1,0.3,2", "0,1,0", "0,1,0,2,3,2,1", "1,2"]),
    "sun_samples": (dict(file="interreflected", sun="1,1,0.3,2"), [0, 1, 9, 10, 16, 4096, 4097]),
}

# Names both front ends have that mean different things, and why; and the harness's own.
NOT_THE_SAME = {
    "light": "the command line's is a spec (repeatable); Python's the (3, K) coefficients",
}
HARNESS = {"output"}


def cli_options(cli_process):
    text = cli_process("shade", "--help").stdout
    return {m.replace("-", "_") for m in re.findall(r"--([a-z][a-z0-9-]*)", text)}


def python_options():
    signature = (shprt.shade.__doc__ or "").splitlines()[0]
    return set(re.findall(r"\b([a-z_0-9]+)\s*[:=]", signature)) - {"file"}


def test_every_shared_option_is_probed(cli_process):
    shared = (cli_options(cli_process) & python_options()) - set(NOT_THE_SAME) - HARNESS
    assert {"k", "gloss", "shading_coeffs", "brdf", "sun_samples"} <= shared, shared
    assert shared <= set(PROBES), f"shared options without a probe: {sorted(shared - set(PROBES))}"


@pytest.fixture(scope="module")
def files(tmp_path_factory, cli):
    folder = tmp_path_factory.mktemp("files")
    paths = {}
    for name, bake in [
        ("shadowed", ["--bands", "3", "--samples", "64"]),
        ("glossy", ["--transfer", "glossy", "--bands", "3", "--samples", "64"]),
        ("interreflected",
         ["--transfer", "interreflected", "--bounces", "1", "--bands", "3", "--samples", "64"]),
    ]:
        paths[name] = str(folder / f"{name}.shprt")
        cli("bake", "builtin:box_on_plane", "-o", paths[name], *bake)
    return paths


def cli_text(value):
    if isinstance(value, tuple):
        return ",".join(str(v) for v in value)
    return str(value)


def shade_cli(cli_process, path, out, options):
    args = []
    for key, value in options.items():
        option = "--" + key.replace("_", "-")
        args += [option] if value is True else [option, cli_text(value)]
    done = cli_process("shade", path, "--light", LIGHT, "-o", out, *args)
    if done.returncode != 0:
        return None, done.stderr.strip()
    rows = np.load(out)
    return (rows[:, 3:6], rows[:, 6:9]), ""


def shade_python(path, options):
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)  # coeffs=: tested below
            return shprt.shade(shprt.load(path), shprt.light(LIGHT, K=K), **options), ""
    except (shprt.Error, TypeError, ValueError, OverflowError) as e:
        return None, str(e)


def agree(cli, py, what):
    assert (cli[0] is None) == (py[0] is None), (
        f"{what}: the command line {'refused' if cli[0] is None else 'accepted'} it ({cli[1]}), "
        f"Python {'refused' if py[0] is None else 'accepted'} it ({py[1]})")
    if cli[0] is not None:
        for a, b, name in zip(cli[0], py[0], ("irradiance", "radiance")):
            np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-6, err_msg=f"{what}: {name}")


@pytest.mark.parametrize("option", sorted(PROBES))
def test_shared_option_takes_the_same_values(cli_process, files, tmp_path, option):
    extra, values = PROBES[option]
    for value in values:
        options = dict(extra)
        options[option] = value
        path = files[options.pop("file", "shadowed")]
        out = str(tmp_path / "s.npy")
        agree(shade_cli(cli_process, path, out, options), shade_python(path, options),
              f"{option}={value!r}")


@pytest.mark.parametrize("kind", ["shadowed", "glossy", "interreflected"])
def test_defaults_agree(cli_process, files, tmp_path, kind):
    # k < 1 without an eye: both take the default camera's eye; a glossy file without --brdf is
    # shaded by both with gloss's Phong lobe (its scene has no material BRDFs), or both refuse.
    options = dict(k=0.5)
    agree(shade_cli(cli_process, files[kind], str(tmp_path / "s.npy"), options),
          shade_python(files[kind], options), f"{kind} with k=0.5")


def test_coeffs_is_the_deprecated_name_of_shading_coeffs(cli_process, files, tmp_path):
    # K' is --shading-coeffs / shading_coeffs= (bake's --coeffs is K); the old name still works,
    # with one warning on each side, and both names at once are refused on each side.
    path, out = files["shadowed"], str(tmp_path / "s.npy")
    done = cli_process("shade", path, "--light", LIGHT, "--coeffs", "4", "-o", out)
    assert done.returncode == 0 and "--coeffs 4 is deprecated" in done.stderr, done.stderr
    with pytest.warns(DeprecationWarning, match="shading_coeffs="):
        old = shprt.shade(shprt.load(path), shprt.light(LIGHT, K=K), coeffs=4)
    new = shprt.shade(shprt.load(path), shprt.light(LIGHT, K=K), shading_coeffs=4)
    np.testing.assert_array_equal(old[0], new[0])
    both = cli_process("shade", path, "--coeffs", "4", "--shading-coeffs", "4", "-o", out)
    assert both.returncode != 0 and "give --shading-coeffs alone" in both.stderr
    with pytest.raises(shprt.Error, match="give shading_coeffs alone"):
        shprt.shade(shprt.load(path), shprt.light(LIGHT, K=K), coeffs=4, shading_coeffs=4)
