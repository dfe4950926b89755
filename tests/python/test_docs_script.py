"""tools/docs.sh with a relative interpreter (PYTHON=.venv/bin/python, as tools/setup_env.sh
documents it): the script's checks run it from other folders, where a relative path named
nothing. Run up to Sphinx, which ``--version`` stops before it builds anything."""
import importlib.machinery
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_docs_script_takes_a_relative_python():
    if importlib.util.find_spec("sphinx") is None or shutil.which("bash") is None:
        pytest.skip("sphinx or bash absent")
    if not any((ROOT / "python" / "quatnav").glob("_core*" + s) for s in importlib.machinery.EXTENSION_SUFFIXES):
        pytest.skip("no in-tree compiled module (docs/DEVELOPING.md)")
    rel = os.path.relpath(sys.executable, ROOT)
    env = dict(os.environ, PYTHON=rel, QUATNAV_DOCS_FROM="tree")
    p = subprocess.run(["bash", "tools/docs.sh", "--version"], cwd=ROOT, env=env, capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "documenting quatnav from" in p.stdout and "No such file" not in p.stderr
