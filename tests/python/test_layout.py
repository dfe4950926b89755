"""The layout rules of the C++ headers (cpp/include/quatnav/), read from their #include lines:

* core/ includes nothing from attitude/ or nav/ (it knows no filter);
* attitude/ and nav/ never include each other;
* every quatnav include resolves to a header that exists;
* every public header is reachable from quatnav.hpp.

That each header compiles on its own is checked by the C++ build (tests/cpp/CMakeLists.txt,
quatnav_self_contained_headers).

And the layout of the Python package (python/quatnav/): the command line is the package
``quatnav.cli`` (its ``main`` the ``quatnav`` script and ``python -m quatnav``), one module per tool
inside it; no command-line module sits at the package top; imports point down to it only: nothing
outside ``cli/`` imports from it (the ``__main__`` modules, entry points above it, aside); what a
command does is a library call of ``quatnav.pipeline``, ``quatnav.plausibility`` and the rest.

And no product file (the package's Python modules, the C++ headers) is over 900 lines."""
import ast
import re
from pathlib import Path

import pytest

INCLUDE = Path(__file__).resolve().parents[2] / "cpp" / "include"
ROOT = INCLUDE / "quatnav"
LAYERS = ("core", "attitude", "nav")
FORBIDDEN = {"core": {"attitude", "nav"}, "attitude": {"nav"}, "nav": {"attitude"}}
_INCLUDE_RE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def _headers():
    return sorted(ROOT.rglob("*.hpp"))


def _strip_comments(text: str) -> str:
    """The text without comments, every line kept where it was."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def quatnav_includes(header: Path):
    """(line number, spelled include, resolved path) of every include of a quatnav header."""
    code = _strip_comments(header.read_text())
    out = []
    for m in _INCLUDE_RE.finditer(code):
        kind, name = m.groups()
        if kind == '"':
            target = (header.parent / name).resolve()
            if not target.is_relative_to(ROOT.resolve()):
                continue
        elif name.startswith("quatnav/"):
            target = (INCLUDE / name).resolve()
        else:
            continue  # Eigen, the standard library
        line = code[: m.start(2)].count("\n") + 1
        out.append((line, m.group(0).strip(), target))
    return out


def _layer(path: Path) -> str:
    rel = path.resolve().relative_to(ROOT.resolve())
    return rel.parts[0] if len(rel.parts) > 1 else ""


def test_the_layers_exist_and_hold_every_header():
    for layer in LAYERS:
        assert (ROOT / layer).is_dir(), f"cpp/include/quatnav/{layer}/ missing"
    loose = [h.name for h in _headers() if _layer(h) == "" and h.name != "quatnav.hpp"]
    assert not loose, f"headers outside core/, attitude/, nav/: {loose}"
    strays = [str(h.relative_to(ROOT)) for h in _headers() if _layer(h) not in ("",) + LAYERS]
    assert not strays, f"headers in an unknown folder: {strays}"


@pytest.mark.parametrize("header", _headers(), ids=lambda h: str(h.relative_to(ROOT)))
def test_includes_follow_the_layers(header):
    src = _layer(header)
    bad = []
    for line, spelled, target in quatnav_includes(header):
        where = f"{header.relative_to(INCLUDE)}:{line}: {spelled}"
        if not target.exists():
            bad.append(f"{where} names no header")
            continue
        dst = _layer(target)
        if dst in FORBIDDEN.get(src, ()):
            bad.append(f"{where}: {src}/ must not include {dst}/")
        if src and dst == "":
            bad.append(f"{where}: only users include the umbrella header")
    assert not bad, "layout rule broken:\n" + "\n".join(bad)


def test_every_header_is_reachable_from_the_umbrella():
    seen, todo = set(), [ROOT / "quatnav.hpp"]
    while todo:
        h = todo.pop().resolve()
        if h in seen or not h.exists():
            continue
        seen.add(h)
        todo.extend(t for _, _, t in quatnav_includes(h))
    missing = [str(h.relative_to(ROOT)) for h in _headers() if h.resolve() not in seen]
    assert not missing, f"not reachable from quatnav.hpp (add them there): {missing}"


def test_the_rule_checker_sees_a_violation(tmp_path):
    """The parser finds a forbidden include written either way (so the rules above can fail)."""
    fake = tmp_path / "quatnav" / "core"
    fake.mkdir(parents=True)
    h = fake / "x.hpp"
    h.write_text('#pragma once\n// #include "../nav/gps_ins.hpp" (a comment: ignored)\n'
                 '#include "../attitude/attitude.hpp"\n#include <quatnav/nav/gps_ins.hpp>\n#include <cmath>\n')
    global INCLUDE, ROOT
    saved = INCLUDE, ROOT
    INCLUDE, ROOT = tmp_path, tmp_path / "quatnav"
    try:
        found = [(line, _layer(t)) for line, _, t in quatnav_includes(h)]
    finally:
        INCLUDE, ROOT = saved
    assert found == [(3, "attitude"), (4, "nav")]


PACKAGE = Path(__file__).resolve().parents[2] / "python" / "quatnav"


def test_the_command_line_is_one_package():
    cli = PACKAGE / "cli"
    assert (cli / "__init__.py").is_file() and (cli / "__main__.py").is_file()  # python -m quatnav.cli
    for name in ("util", "ins", "ahrs", "compare", "calibrate"):
        assert (cli / f"{name}.py").is_file(), f"python/quatnav/cli/{name}.py missing"
    loose = sorted(p.name for p in PACKAGE.glob("*.py") if "cli" in p.stem)
    assert not loose, f"command-line modules at the package top (they belong in quatnav/cli/): {loose}"
    text = (PACKAGE.parents[1] / "pyproject.toml").read_text()
    assert 'quatnav = "quatnav.cli:main"' in text
    assert "from .cli import main" in (PACKAGE / "__main__.py").read_text()
    init = (cli / "__init__.py").read_text()
    for name in ("ins", "ahrs", "compare", "calibrate"):
        assert f"from . import {name}\n" in init, f"quatnav.cli does not add the {name} subcommand"


def test_the_package_top_holds_only_its_face_and_private_helpers():
    """Everything else sits in a package by job (core, filters, reference, sim, io, datasets,
    calibration, evaluation, experiments, cli)."""
    top = sorted(p.stem for p in PACKAGE.glob("*.py") if not p.stem.startswith("_"))
    assert top == ["demo"], f"modules at the package top that belong in a package by job: {top}"
    jobs = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").is_file()}
    assert {"core", "filters", "reference", "sim", "io", "datasets", "calibration", "evaluation",
            "experiments", "cli"} <= jobs
    assert {"pipeline", "plausibility"} <= jobs


def cli_imports(path: Path, package: Path = PACKAGE) -> list:
    """(line, module) of every import of ``quatnav.cli`` (or a module in it) in a module of the
    package at ``path``: absolute, relative, and ``import quatnav.cli``."""
    rel = path.relative_to(package.parent).with_suffix("").parts  # ("quatnav", "sub", "mod")
    pkg = rel[:-1]
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = list(pkg[:len(pkg) - node.level + 1]) if node.level else []
            mod = ".".join(base + ([node.module] if node.module else []))
            names = [mod] + [f"{mod}.{a.name}" for a in node.names]
        for name in names:
            if name == "quatnav.cli" or name.startswith("quatnav.cli."):
                out.append((node.lineno, name))
                break
    return out


def test_nothing_outside_the_command_line_imports_it():
    """The arrows point down: the library (pipeline, plausibility, io, evaluation, experiments, ...)
    never imports the command line; only the entry points (``__main__``) do."""
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if "cli" in path.relative_to(PACKAGE).parts[:1] or path.name == "__main__.py":
            continue
        bad += [f"{path.relative_to(PACKAGE.parent)}:{line}: imports {mod}" for line, mod in cli_imports(path)]
    assert not bad, "the library imports the command line (move what it needs below quatnav/cli/):\n" + "\n".join(bad)


def test_the_import_checker_sees_every_spelling(tmp_path):
    pkg = tmp_path / "quatnav"
    (pkg / "io").mkdir(parents=True)
    f = pkg / "io" / "x.py"
    f.write_text("import numpy\nfrom ..cli.util import UsageError\nfrom .. import cli\nimport quatnav.cli.ins\n"
                 "from quatnav.cli import main\nfrom ..cliff import y\nfrom . import table\n")
    assert [line for line, _ in cli_imports(f, pkg)] == [2, 3, 4, 5]


def test_no_product_file_is_over_900_lines():
    """One file, one job: a module past about 800 lines is usually two."""
    root = PACKAGE.parents[1]
    files = sorted(PACKAGE.rglob("*.py")) + sorted((root / "cpp" / "include").rglob("*.hpp"))
    sizes = {str(f.relative_to(root)): len(f.read_text().splitlines()) for f in files}
    long = {f: n for f, n in sizes.items() if n > 900}
    assert not long, f"files over 900 lines (split them by job): {long}"


def test_compiled_classes_are_named_in_one_place():
    """The Python filters reach their compiled classes only through quatnav.filters._compiled,
    whose table writes every class out (no name built at run time elsewhere); every entry exists
    in the built module for both scalar types, and the two are the same class in float64 and
    float32."""
    pkg = ROOT.parents[2] / "python" / "quatnav"
    built = re.compile(r"getattr\(\s*(?:core\(\)|_core|core)\s*,|(?<![.\w])_core\.[A-Za-z0-9]+_f(?:32|64)\b")
    offenders = [str(p.relative_to(pkg)) for p in sorted(pkg.rglob("*.py"))
                 if p.name != "_compiled.py" and built.search(p.read_text())]
    assert offenders == [], f"compiled classes looked up outside filters/_compiled.py: {offenders}"
    np = pytest.importorskip("numpy")
    from quatnav.filters._compiled import _table, compiled
    for name, (f64, f32) in _table().items():
        assert f64.__name__.endswith("_f64") and f32.__name__.endswith("_f32"), name
        assert f64.__name__[:-4] == f32.__name__[:-4], name
        assert compiled(name, np.float32) is f32 and compiled(name, np.float64) is f64
