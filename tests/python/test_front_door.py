"""The README's two commands: tools/setup_env.sh (sourced by tools/demo.sh and tools/test.sh)
chooses a virtual environment, and .ci/run runs both commands."""
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def _source(env_extra, tmp_path):
    script = f'source "{REPO}/tools/setup_env.sh" && echo "PY=$PY"'
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "CONDA_PREFIX", "PYTHON")}
    env.update(env_extra)
    return subprocess.run(["bash", "-c", script], env=env, capture_output=True, text=True, cwd=tmp_path,
                          timeout=300)


@pytest.mark.skipif(not Path("/usr/bin/python3").exists() or shutil.which("bash") is None,
                    reason="needs a system /usr/bin/python3")
def test_outside_a_virtual_environment_one_is_created_in_the_given_folder(tmp_path):
    venv = tmp_path / "venv"
    # PATH with the system interpreter first: not a virtual environment (on Debian an
    # externally managed one, where pip install is refused).
    r = _source({"PATH": "/usr/bin:/bin", "QUATNAV_VENV": str(venv)}, tmp_path)
    assert r.returncode == 0, r.stderr
    assert "creating a virtual environment" in r.stdout
    py = r.stdout.strip().splitlines()[-1].removeprefix("PY=")
    assert py == str(venv / "bin" / "python")
    out = subprocess.run([py, "-c", "import sys; print(sys.prefix != sys.base_prefix)"], capture_output=True,
                         text=True)
    assert out.stdout.strip() == "True"
    # a second call reuses it
    r2 = _source({"PATH": "/usr/bin:/bin", "QUATNAV_VENV": str(venv)}, tmp_path)
    assert r2.returncode == 0 and "using the virtual environment" in r2.stdout


def test_python_given_is_used_as_it_is(tmp_path):
    import sys
    r = _source({"PYTHON": sys.executable, "QUATNAV_VENV": str(tmp_path / "never")}, tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().splitlines()[-1] == f"PY={sys.executable}"
    assert not (tmp_path / "never").exists()


def test_ci_runs_both_readme_commands():
    readme = (REPO / "README.md").read_text()
    ci = (REPO / ".ci" / "run").read_text()
    for cmd in ("bash tools/demo.sh", "bash tools/test.sh"):
        assert cmd in readme.split("## ")[0], f"{cmd} is not among the README's first commands"
        assert cmd in ci, f".ci/run does not run {cmd}"
    assert ci.index("bash tools/demo.sh") < ci.index("bash tools/test.sh")
