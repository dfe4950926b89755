"""tools/mutate.py stays usable: every mutation's text is found exactly once in its file (a code
change that moves it fails here, loudly, instead of silently dropping the mutation), and every
consistency test (a test file that uses _consistency's checks) is run by its variance-scale
mutations. The mutations themselves run with ``python3 tools/mutate.py`` (docs/DEVELOPING.md)."""
import importlib.util
import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def _tool():
    name = "quatnav_mutate_tool"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, REPO / "tools" / "mutate.py")
        mod = importlib.util.module_from_spec(spec)
        sys.modules[name] = mod
        spec.loader.exec_module(mod)
    return sys.modules[name]


M = _tool()


def test_every_pattern_matches_its_file_exactly_once():
    assert M.check_patterns(M.MUTATIONS) == []


def test_a_pattern_that_moved_is_reported(tmp_path):
    m = M.MUTATIONS[0]
    (tmp_path / m.path).parent.mkdir(parents=True)
    (tmp_path / m.path).write_text((REPO / m.path).read_text().replace(m.find, m.find + "\n" + m.find))
    assert [p for p in M.check_patterns([m], tmp_path) if "2 times" in p]
    (tmp_path / m.path).write_text("")
    assert [p for p in M.check_patterns([m], tmp_path) if "0 times" in p]


def test_every_consistency_test_is_run_scaled_both_ways():
    users = {p.name for p in (REPO / "tests" / "python").glob("test_*.py")
             if re.search(r"\bcheck_mean_nees\b|\bscaled\(", p.read_text())} - {"test_consistency_helper.py"}
    cpp_users = {p.stem for p in (REPO / "tests" / "cpp").glob("test_*.cpp")
                 if "consistency.hpp" in p.read_text()}
    for scale in (M.OVER, M.UNDER):
        runs = [m for m in M.MUTATIONS if dict(m.env).get("QUATNAV_TEST_VARIANCE_SCALE") == scale]
        assert {Path(p.split("::")[0]).name for m in runs for p in m.py} >= users
        assert {c.split(":")[0] for m in runs for c in m.cpp} >= cpp_users


def test_every_area_has_mutations_and_no_mutation_runs_the_regression_test():
    assert {m.area for m in M.MUTATIONS} >= {"nav13", "core", "attitude", "marg", "strapdown", "gpsins", "consistency"}
    for m in M.MUTATIONS:
        assert m.cpp or m.py, m.name
        assert not any("test_regression" in p for p in m.py), m.name


def test_area_selects_exactly_one_area(capsys):
    # "-k attitude" also matches nav13's "velocity-attitude" slips; --area must not.
    assert M.main(["--area", "attitude", "--list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == sum(1 for m in M.MUTATIONS if m.area == "attitude") > 0
    assert all(line.split()[0] == "attitude" for line in lines)


def test_a_second_run_on_the_same_copy_is_refused(tmp_path):
    import fcntl
    import pytest
    with open(tmp_path / "lock", "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(SystemExit, match="another run uses"):
            M.main(["--area", "core", "--scratch", str(tmp_path)])
