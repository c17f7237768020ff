"""Every option that both the command line and Python have — `shprt bake`, `shade`, `render` and
`view` (its bake and shading options) against shprt.bake, shade and render — has the same default
and the same limits on both (issue 35; the tables are bake/bake_option_table.hpp and
shade/params.hpp's shading_option_table).

Each side is read on its own: the command line's defaults and limits from its help
(`--samples INT:[1 to 16777216]=1024`, what the table-walking registration shows), Python's
defaults from pybind11's signature, and Python's limits by trying each keyword at and just past
the limits the help gives: at them no error names it, past them one does. Cheap: no bake or shading
runs (an empty mesh or a file-less call stops right after the options are checked).
"""
import re

import numpy as np
import pytest

import shprt

# Names both front ends have that mean different things, and why; and the harness's own.
NOT_THE_SAME = {
    "output": "the harness's own",
    "albedo": "bake: one R,G,B for every vertex on the command line, the per-vertex array in "
              "Python",
    "light": "a spec (repeatable) on the command line; the (3, K) coefficients in Python",
    "camera": "EX,EY,EZ,TX,TY,TZ text on the command line, a 6-tuple in Python",
}
# (command, Python function): `view` has the bake options (with --bake) and the shading ones;
# shprt.light has the light's (light/light_setup.hpp: light_option_table).
PAIRS = [("bake", "bake"), ("shade", "shade"), ("render", "render"), ("view", "render"),
         ("view", "bake"), ("render", "light")]
# How many options a pair shares at least (6 where not named).
AT_LEAST = {("render", "light"): 3}
# render's --samples are MSAA samples (Python's too; not a table row); view's --samples and
# --coeffs are the bake's (with --bake), Python render's samples= MSAA and coeffs= K'.
ALSO_NOT = {("render", "render"): {"samples"}, ("view", "render"): {"samples", "coeffs"}}
# What the values a keyword takes need around them (the options they depend on).
CONTEXT: dict[str, dict[str, object]] = {
    "max_samples": dict(target_error=0.05),
    "tolerance": dict(transfer="interreflected", bounces="converged"),
    "bounces": dict(transfer="interreflected"),
    "indirect_samples": dict(transfer="interreflected"),
    "source_spacing": dict(transfer="interreflected"),
    "sun_samples": dict(sun="0,1,0"),
}
OPTION = re.compile(r"^  (?:-\w,)?--([a-z][a-z0-9-]*)(?: ([A-Z]+)(?::\[([^\]]*)\])?(?:=(\S+))?)?",
                    re.M)


def cli_options(cli_process, command):
    text = cli_process(command, "--help").stdout
    options = {}
    for name, kind, limits, default in OPTION.findall(text):
        options[name.replace("-", "_")] = (kind, limits, default)
    return options


def split_top(text):
    parts, depth, current = [], 0, ""
    for ch in text:
        depth += ch in "[(" and 1 or (ch in "])" and -1 or 0)
        if ch == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += ch
    return parts + [current.strip()] if current.strip() else parts


def python_defaults(function):
    signature = (function.__doc__ or "").splitlines()[0]
    inner = signature[signature.index("(") + 1:signature.rindex(")")]
    defaults = {}
    for part in split_top(inner):
        if ":" in part and "=" in part:
            name = part.split(":")[0].strip()
            defaults[name] = part.rsplit("=", 1)[1].strip()
    return defaults


def normal(value):
    """A default as one text: '' for unset (None, False, an empty text), numbers as floats."""
    value = value.strip("'\"")
    if value in ("None", "False", ""):
        return ""
    try:
        return float(value)
    except ValueError:
        return value


def shared(cli_process, command, python):
    function = getattr(shprt, python, None)
    if function is None:
        pytest.skip(f"this build has no shprt.{python}")
    cli = cli_options(cli_process, command)
    py = python_defaults(function)
    names = (set(cli) & set(py)) - set(NOT_THE_SAME) - ALSO_NOT.get((command, python), set())
    return cli, py, names


@pytest.mark.parametrize("command,python", PAIRS)
def test_shared_options_have_the_same_defaults(cli_process, command, python):
    cli, py, names = shared(cli_process, command, python)
    assert len(names) >= AT_LEAST.get((command, python), 6), names
    wrong = {n: (cli[n][2], py[n]) for n in names if normal(cli[n][2]) != normal(py[n])}
    assert not wrong, f"{command} and shprt.{python}: defaults (command line, Python) differ: {wrong}"


def limits_of(text):
    """'1 to 32', '0 (all) to 4096', 'between 0 and 1', '≥ 0', '> 0' as (low, high, exclusive)."""
    m = re.match(r"(-?[\d.e+]+)(?: \([^)]*\))? to (-?[\d.e+]+)", text)
    if m:
        return float(m[1]), float(m[2]), False
    m = re.match(r"between (-?[\d.e+]+) and (-?[\d.e+]+)", text)
    if m:
        return float(m[1]), float(m[2]), True
    m = re.match(r"(≥|>) (-?[\d.e+]+)", text)
    if m:
        return float(m[2]), None, m[1] == ">"
    m = re.match(r"a square, 1 to (\d+)", text)
    return (1.0, float(m[1]), False) if m else None


def probes(kind, low, high, exclusive):
    """(value, accepted) pairs at and just past the limits."""
    step = 1 if kind in ("INT", "UINT", "TEXT") else 1e-3
    cast = int if step == 1 else float
    at = [] if exclusive else [low] + ([high] if high is not None else [])
    past = [low - step if not exclusive else low] + (
        [high + step if not exclusive else high] if high is not None else [])
    return [(cast(v), True) for v in at] + [(cast(v), False) for v in past]


def python_refuses(command, name, options, file):
    """The error message that names `name`, or '' when the call got past the options."""
    try:
        if command == "bake":
            shprt.bake(np.zeros((0, 3), np.float32), **options)
        else:
            size = dict(width=8, height=8) if command == "render" else {}
            getattr(shprt, command)(file, np.zeros((3, 1), np.float32), **size, **options)
    except (shprt.Error, TypeError, ValueError, OverflowError) as e:
        message = str(e)
        return message if re.search(rf"\b{name}\b", message) else ""
    return ""


@pytest.fixture(scope="module")
def empty_file(tmp_path_factory, cli):
    path = tmp_path_factory.mktemp("f") / "f.shprt"
    cli("bake", "builtin:box_on_plane", "-o", str(path), "--bands", "1", "--samples", "4")
    return shprt.load(str(path))


@pytest.mark.parametrize("command", ["bake", "shade", "render"])
def test_python_takes_the_command_lines_limits(cli_process, command, empty_file):
    cli, _, names = shared(cli_process, command, command)
    tried = []
    for name in sorted(names):
        kind, text, _ = cli[name]
        limits = limits_of(text) if text else None
        if limits is None:
            continue
        for value, accepted in probes(kind, *limits):
            options: dict[str, object] = {**CONTEXT.get(name, {}), name: value}
            if name == "bounces":
                options[name] = int(value)
            if command != "bake":
                options.pop("transfer", None)
            message = python_refuses(command, name, options, empty_file)
            assert bool(message) != accepted, (
                f"{command}: {name}={value!r}: the command line's limits are [{text}], Python "
                f"{'refused' if message else 'accepted'} it {message}")
            tried.append(name)
    assert len(set(tried)) >= (8 if command == "bake" else 3), tried
