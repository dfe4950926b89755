"""The type stubs of quatnav._core (python/quatnav/_core/*.pyi) list every public name of the
compiled module; regenerate them with tools/stubgen.sh after changing a binding."""
import ast
from pathlib import Path

from quatnav import _core

STUBS = Path(__file__).resolve().parents[2] / "python" / "quatnav" / "_core"  # the repository's stubs


def _stub_names(path: Path) -> set:
    tree = ast.parse(path.read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)  # constants
        elif isinstance(node, ast.ImportFrom) and node.module is None:
            names.update(a.name for a in node.names)  # submodules: from . import quat
    return names


def test_stubs_cover_the_compiled_module():
    stub = STUBS / "__init__.pyi"
    assert stub.exists(), "python/quatnav/_core/__init__.pyi missing: run tools/stubgen.sh"
    public = {n for n in dir(_core) if not n.startswith("_")}
    missing = public - _stub_names(stub)
    assert not missing, f"names of quatnav._core without a stub (run tools/stubgen.sh): {sorted(missing)}"


def test_submodule_stubs_cover_their_modules():
    for sub in ("quat", "earth", "strapdown"):
        mod = getattr(_core, sub)
        public = {n for n in dir(mod) if not n.startswith("_")}
        missing = public - _stub_names(STUBS / f"{sub}.pyi")
        assert not missing, f"quatnav._core.{sub}: no stub for {sorted(missing)}"
