"""The type stubs (python/shprt/_shprt.pyi) cannot drift from the bindings (python/src/*.cpp):
every name the extension binds — functions (each overload), classes with their methods and
properties, enums with their members, constants — has a stub, and every stub a bound name; each
function and method has the same parameters as pybind11's signature says: names, order, the
keyword-only marker and defaults. Whether the stubs are well-typed is mypy's job (the CTest test
`python_mypy`).

pybind11 writes each signature as the first line of __doc__ (an overloaded function: one line per
overload, numbered), with defaults as their repr. Its argument types are checked here only for what
the stubs' reader would miss: none may be a bare "handle" or "object" (convert.hpp, Loose).
"""
import ast
import pathlib
import re

import pytest

import shprt
from shprt import _shprt

STUB = pathlib.Path(__file__).resolve().parents[1] / "shprt" / "_shprt.pyi"
RENDER_ONLY = {"render"}  # bound only when shprt.HAS_RENDER (shade and save_image need no GL)
UNTYPED = {"handle", "object"}


# ---------------------------------------------------------------------------------------------
# pybind11's side

def split_top(text, sep):
    """text split at `sep` outside brackets and quotes."""
    parts, depth, current = [], 0, ""
    quote: str | None = None
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == sep and depth == 0:
            parts.append(current.strip())
            current = ""
            continue
        current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def value_of(text):
    """A default as a comparable value: a literal (tuples as lists), else its text."""
    try:
        value = ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text
    return list(value) if isinstance(value, tuple) else value


def parse_signature(line, name):
    """'name(a: int, *, b: str = 'x') -> T' as [(param, type, default or NO_DEFAULT), ...]."""
    assert line.startswith(name + "("), f"{name}: not a signature: {line!r}"
    body, depth = "", 0
    for ch in line[len(name):]:
        depth += ch == "("
        depth -= ch == ")"
        body += ch
        if depth == 0:
            break
    params = []
    for part in split_top(body[1:-1], ","):
        if part in ("*", "/"):
            params.append((part, None, NO_DEFAULT))
            continue
        head = split_top(part, "=")
        pname, _, ptype = head[0].partition(":")
        default = value_of(head[1].strip()) if len(head) > 1 else NO_DEFAULT
        params.append((pname.strip(), ptype.strip(), default))
    return params


NO_DEFAULT = object()


def bound_signatures(func, name):
    """The signatures pybind11 gives `func` (one per overload)."""
    doc = func.__doc__ or ""
    lines = doc.splitlines()
    assert lines, f"{name}: no docstring, no signature"
    if len(lines) > 1 and lines[1].strip() == "Overloaded function.":
        overloads = [re.sub(r"^\d+\. ", "", line) for line in lines
                     if re.match(rf"^\d+\. {re.escape(name)}\(", line)]
        return [parse_signature(line, name) for line in overloads]
    return [parse_signature(lines[0], name)]


def is_bound_function(value):
    return type(value).__name__ in ("builtin_function_or_method", "instancemethod")


def bound_members(cls):
    """A class's own bound names: methods (with __init__ and other dunders it binds), properties
    and, for an enum, its members."""
    methods, properties = {}, set()
    for name, value in vars(cls).items():
        if isinstance(value, property):
            properties.add(name)
        elif is_bound_function(value) and not name.startswith("_pybind11"):
            methods[name] = getattr(cls, name)
    members = set(getattr(cls, "__members__", {}))
    return methods, properties, members


def bound_names():
    names = {n: getattr(_shprt, n) for n in dir(_shprt) if not n.startswith("_")}
    names["__version__"] = _shprt.__version__
    return names


# ---------------------------------------------------------------------------------------------
# The stubs' side

def stub_params(fn):
    """A stub's def as [(param, default or NO_DEFAULT), ...] with '/' and '*' markers."""
    a = fn.args
    positional = a.posonlyargs + a.args
    defaults = [NO_DEFAULT] * (len(positional) - len(a.defaults)) + list(a.defaults)
    params = []
    for i, (arg, default) in enumerate(zip(positional, defaults)):
        params.append((arg.arg, default))
        if a.posonlyargs and i == len(a.posonlyargs) - 1:
            params.append(("/", NO_DEFAULT))
    if a.vararg:
        params.append(("*" + a.vararg.arg, NO_DEFAULT))
    elif a.kwonlyargs:
        params.append(("*", NO_DEFAULT))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        params.append((arg.arg, NO_DEFAULT if default is None else default))
    if a.kwarg:
        params.append(("**" + a.kwarg.arg, NO_DEFAULT))
    return [(n, d if not isinstance(d, ast.AST) else value_of(ast.unparse(d))) for n, d in params]


def is_overload(fn):
    return any(isinstance(d, ast.Name) and d.id == "overload" for d in fn.decorator_list)


def is_property(fn):
    return any(isinstance(d, ast.Name) and d.id == "property" for d in fn.decorator_list)


class Scope:
    """The functions (name -> [defs]), classes, properties and variables of a module or class."""

    def __init__(self, body):
        self.functions: dict[str, list[ast.FunctionDef]] = {}
        self.classes: dict[str, ast.ClassDef] = {}
        self.properties: set[str] = set()
        self.variables: dict[str, str | None] = {}
        for node in body:
            if isinstance(node, ast.FunctionDef):
                if is_property(node):
                    self.properties.add(node.name)
                else:
                    self.functions.setdefault(node.name, []).append(node)
            elif isinstance(node, ast.ClassDef):
                self.classes[node.name] = node
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                self.variables[node.target.id] = ast.unparse(node.annotation)
            elif isinstance(node, ast.Assign):
                for target in node.targets:
                    if isinstance(target, ast.Name):
                        self.variables[target.id] = None  # an enum member, or an alias

    def public(self):
        names = set(self.functions) | set(self.classes) | set(self.variables)
        return {n for n in names if not n.startswith("_") or n == "__version__"}


@pytest.fixture(scope="module")
def stubs():
    return Scope(ast.parse(STUB.read_text(encoding="utf-8"), str(STUB)).body)


# ---------------------------------------------------------------------------------------------
# The comparison

def check_function(where, func, name, defs):
    """Compares the bound signatures of `func` with the stub's defs; returns the differences."""
    problems = []
    bound = bound_signatures(func, name)
    overloads = [d for d in defs if is_overload(d)]
    if len(bound) > 1 and len(overloads) != len(bound):
        return [f"{where}: {len(bound)} bound overloads, {len(overloads)} @overload stubs"]
    if len(bound) == 1 and len(defs) > 1 and len(overloads) != len(defs):
        return [f"{where}: {len(defs)} stubs, not all @overload"]
    for i, d in enumerate(defs):
        sig = bound[i] if len(bound) > 1 else bound[0]
        label = f"{where} (overload {i + 1})" if len(defs) > 1 else where
        want = [p for p, _, _ in sig]
        got = [p for p, _ in stub_params(d)]
        if want != got:
            lacks, extra = [p for p in want if p not in got], [p for p in got if p not in want]
            problems.append(f"{label}: the stub lacks {lacks} and has {extra} more than bound"
                            if lacks or extra else f"{label}: parameters {got}, bound {want}")
            continue
        for (p, ptype, bdefault), (_, sdefault) in zip(sig, stub_params(d)):
            if ptype in UNTYPED:
                problems.append(f"{label}: {p} is bound as '{ptype}' (give it a type: Loose)")
            # One overload of one bound function may leave a default out (it narrows the call:
            # bake(..., output=PATH) returns a dict); otherwise the defaults agree.
            narrowed = len(bound) == 1 and len(defs) > 1 and sdefault is NO_DEFAULT
            if sdefault != bdefault and not narrowed and not (
                    bdefault is not NO_DEFAULT and sdefault is not NO_DEFAULT
                    and repr(sdefault) == repr(bdefault)):
                show = lambda v: "none" if v is NO_DEFAULT else repr(v)  # noqa: E731
                problems.append(f"{label}: {p} defaults to {show(sdefault)} in the stub, "
                                f"{show(bdefault)} bound")
    return problems


def test_every_bound_name_has_a_stub_and_every_stub_a_bound_name(stubs):
    bound = bound_names()
    missing = sorted(set(bound) - stubs.public())
    extra = sorted(stubs.public() - set(bound) - (set() if shprt.HAS_RENDER else RENDER_ONLY))
    assert not missing, f"bound without a stub in {STUB.name}: {missing}"
    assert not extra, f"stubs without a bound name: {extra}"


def test_module_functions_have_the_bound_parameters(stubs):
    problems = []
    for name, value in sorted(bound_names().items()):
        if is_bound_function(value):
            assert name in stubs.functions, f"{name}: bound as a function, not one in the stubs"
            problems += check_function(name, value, name, stubs.functions[name])
    assert not problems, "\n".join(problems)


def test_classes_have_the_bound_methods_properties_and_members(stubs):
    problems = []
    for name, value in sorted(bound_names().items()):
        if not isinstance(value, type):
            continue
        assert name in stubs.classes, f"{name}: bound as a class, not one in the stubs"
        scope = Scope(stubs.classes[name].body)
        if issubclass(value, BaseException):  # shprt.Error: its .code
            assert "code" in scope.variables, f"{name}: the stub has no 'code'"
            continue
        methods, properties, members = bound_members(value)
        for method in sorted(set(methods) - set(scope.functions)):
            problems.append(f"{name}.{method}: bound, no stub")
        for method in sorted(set(scope.functions) - set(methods)):
            problems.append(f"{name}.{method}: a stub, not bound")
        if properties != scope.properties:
            problems.append(f"{name}: properties {sorted(scope.properties)} in the stub, "
                            f"{sorted(properties)} bound")
        if members - set(scope.variables):
            problems.append(f"{name}: members {sorted(members - set(scope.variables))} unstubbed")
        for method in sorted(set(methods) & set(scope.functions)):
            problems += check_function(f"{name}.{method}", methods[method], method,
                                       scope.functions[method])
    assert not problems, "\n".join(problems)


def test_constants_have_the_bound_type(stubs):
    for name, value in bound_names().items():
        if not callable(value):
            assert stubs.variables.get(name) == type(value).__name__, \
                f"{name}: {type(value).__name__} bound, {stubs.variables.get(name)} in the stub"


def test_the_checker_finds_a_drifted_stub():
    """The comparison itself: a parameter gone, renamed, reordered or with another default is
    found (so a passing run means something)."""
    def problems_with(stub_text):
        fn = ast.parse(stub_text).body[0]
        return check_function("sh_rotate", _shprt.sh_rotate, "sh_rotate", [fn])

    good = "def sh_rotate(coeffs: A, R: A, method: str = 'ivanic') -> B: ..."
    assert problems_with(good) == []
    for bad in ("def sh_rotate(coeffs: A, method: str = 'ivanic') -> B: ...",
                "def sh_rotate(coeffs: A, M: A, method: str = 'ivanic') -> B: ...",
                "def sh_rotate(R: A, coeffs: A, method: str = 'ivanic') -> B: ...",
                "def sh_rotate(coeffs: A, R: A, method: str = 'zh') -> B: ...",
                "def sh_rotate(coeffs: A, R: A, *, method: str = 'ivanic') -> B: ...",
                "def sh_rotate(coeffs: A, R: A, method: str) -> B: ..."):
        assert problems_with(bad), bad

    class Untyped:  # what a py::handle argument gives
        __doc__ = "f(a: handle, b: int = 1) -> None"

    fn = ast.parse("def f(a: A, b: int = 1) -> None: ...").body[0]
    assert check_function("f", Untyped, "f", [fn]) == [
        "f: a is bound as 'handle' (give it a type: Loose)"]
