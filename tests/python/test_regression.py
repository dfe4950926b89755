"""Committed reference outputs (tests/regression/*.csv): every filter and time update on fixed
seeded scenarios and one BROAD trial must give the same numbers, bit for bit.

On a difference the failure names the file, the columns, the first differing row and the largest
difference. If the change is intended, regenerate with ``python3 tools/regression.py --update``
and say in the commit message why the numbers moved (docs/DEVELOPING.md).
"""
import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]


def _load_tool():
    name = "quatnav_regression_tool"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, REPO / "tools" / "regression.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod  # dataclasses look their module up here
    spec.loader.exec_module(mod)
    return mod


R = _load_tool()


def _compare(case, path=None):
    if case.scenario != "broad":
        pytest.importorskip("quatnav.sim")  # the simulator needs scipy
    else:
        pytest.importorskip("scipy.io")
    try:
        return R.compare(case, path)
    except R.DataMissing as e:
        pytest.skip(str(e))


@pytest.mark.parametrize("case", R.CASES, ids=[c.name for c in R.CASES])
def test_reference_outputs(case):
    cmp = _compare(case)
    if not cmp["ok"]:
        env = R.environment_differences()
        if env:  # not necessarily a change of quatnav: the inputs or libm may differ here
            pytest.skip(R.report(case, cmp) + "\n  this environment differs from the one the files were written in "
                        f"({R.ENV_FILE.name}): " + "; ".join(env))
        if cmp["inputs_changed"] and case.scenario != "broad":
            # numpy's vectorized sin/cos can differ in the last bit between two CPUs with the same
            # recorded features (seen on AMD EPYC against the machine the files were written on):
            # the simulated inputs then differ and the file cannot judge the filter. A change of
            # the simulator itself shows in tools/regression.py (exit 1) and in the sim tests.
            pytest.skip(R.report(case, cmp) + "\n  the simulated inputs differ on this machine")
        pytest.fail(R.report(case, cmp), pytrace=False)


def test_environment_is_recorded():
    assert R.ENV_FILE.is_file(), f"run {R.REGENERATE}"
    keys = {line.split(": ", 1)[0] for line in R.ENV_FILE.read_text().splitlines() if not line.startswith("#")}
    assert keys == set(R.environment())


def test_every_file_is_a_case_and_every_case_has_a_file():
    files = {p.stem for p in R.OUT_DIR.glob("*.csv")}
    names = {c.name for c in R.CASES}
    assert files - names == set(), f"files of no case in {R.OUT_DIR} (remove them or run {R.REGENERATE})"
    assert names - files == set(), f"cases without a file (run {R.REGENERATE})"
    size = sum(p.stat().st_size for p in R.OUT_DIR.glob("*.csv"))
    assert size < 2.5e6, f"tests/regression holds {size / 1e6:.2f} MB: write fewer rows"


def test_every_filter_and_time_update_is_covered():
    calls = " ".join(c.call for c in R.CASES)
    for what in ("QuaternionEKF()", "QuaternionEKF(paper=True)", "no magnetometer", "float32", "EulerEKF(",
                 "MargFilter(bias_gain", "GPS velocity", "NavFilter13('ekf'", "NavFilter13('second_order'",
                 "NavFilter13('ukf'", "GPS, altimeter, compass", "GPS only", "outage", "strapdown_run_cpp"):
        assert what in calls, what
    assert {c.scenario for c in R.CASES} == set(R.SCENARIOS)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_written_floats_read_back_bit_for_bit(dtype):
    rng = np.random.default_rng(1)
    ints = np.uint64 if dtype == np.float64 else np.uint32
    bits = rng.integers(0, np.iinfo(ints).max, size=20000, dtype=ints, endpoint=True)
    x = bits.view(dtype)
    x = np.concatenate([x[np.isfinite(x)], np.array([0.0, -0.0, np.inf, -np.inf, 1e-45, 5e-324, 0.1, 1 / 3,
                                                     np.finfo(dtype).max, np.finfo(dtype).tiny], dtype)])
    back = np.array([R.parse_value(R.format_value(v, dtype), dtype) for v in x], dtype)
    assert np.array_equal(back.view(ints), x.view(ints))
    assert R.parse_value(R.format_value(np.nan, dtype), dtype) != R.parse_value(R.format_value(np.nan, dtype), dtype)
    assert R.format_value(np.uint32(1 << 31), np.uint32) == "2147483648"


def _holding(name):
    """The case ``name``, skipping when its file does not hold here (another environment)."""
    case = R.CASES_BY_NAME[name]
    if not _compare(case)["ok"]:
        pytest.skip(f"{name}: the reference does not hold in this environment")
    return case


def _edit(path, out, row, column, fn):
    """Copy the reference file ``path`` to ``out`` with one cell (data row ``row``, ``column``) replaced."""
    lines = path.read_text().splitlines()
    first = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    names = lines[first].split(",")
    cells = lines[first + 1 + row].split(",")
    j = names.index(column)
    cells[j] = fn(cells[j])
    lines[first + 1 + row] = ",".join(cells)
    out.write_text("\n".join(lines) + "\n")
    return int(cells[0])


def test_one_ulp_in_one_cell_is_reported(tmp_path):
    case = _holding("qekf_rotation")
    f = tmp_path / "x.csv"
    k = _edit(R.OUT_DIR / f"{case.name}.csv", f, 7, "q_x", lambda s: repr(float(np.nextafter(float(s), np.inf))))
    cmp = _compare(case, f)
    assert not cmp["ok"]
    assert [(d.column, d.first_row, d.n_rows) for d in cmp["differences"]] == [("q_x", k, 1)]
    d = cmp["differences"][0]
    assert 0 < d.max_abs < 1e-15
    text = R.report(case, cmp)
    assert "q_x" in text and f"k={k}" in text and "tools/regression.py --update" in text


def test_a_changed_flag_and_changed_inputs_are_reported(tmp_path):
    case = _holding("gpsins_walk")
    f = tmp_path / "x.csv"
    k = _edit(R.OUT_DIR / f"{case.name}.csv", f, 3, "flags", lambda s: str(int(s) ^ 4))
    text = f.read_text().replace("# inputs sha256: ", "# inputs sha256: 0")
    f.write_text(text)
    cmp = _compare(case, f)
    assert [(d.column, d.first_row, d.max_abs) for d in cmp["differences"]] == [("flags", k, 4.0)]
    assert any("inputs changed" in m for m in cmp["messages"])


def test_nan_against_a_number_and_signed_zero_are_differences(tmp_path):
    case = _holding("gpsins_walk")
    f = tmp_path / "x.csv"
    # Row 0 is before navigation starts: NaN position; put a number there.
    _edit(R.OUT_DIR / f"{case.name}.csv", f, 0, "llh_lat", lambda s: "0.5" if s == "nan" else "nan")
    cmp = _compare(case, f)
    assert [(d.column, d.max_abs) for d in cmp["differences"]] == [("llh_lat", np.inf)]
    case = _holding("qekf_rotation")
    _edit(R.OUT_DIR / f"{case.name}.csv", f, 0, "bias_x", lambda s: "-0.0" if s == "0.0" else s)
    cmp = _compare(case, f)
    assert [d.column for d in cmp["differences"]] == ["bias_x"]


def test_command_line_update_then_compare(tmp_path, capsys):
    pytest.importorskip("quatnav.sim")
    name = _holding("marg-gps_turn").name
    assert R.main(["--update", "--dir", str(tmp_path), "-k", name]) == 0
    assert (tmp_path / f"{name}.csv").read_text() == (R.OUT_DIR / f"{name}.csv").read_text()
    assert R.main(["--dir", str(tmp_path), "-k", name]) == 0
    _edit(R.OUT_DIR / f"{name}.csv", tmp_path / f"{name}.csv", 2, "residual", lambda s: "nan" if s != "nan" else "1.0")
    capsys.readouterr()
    assert R.main(["--dir", str(tmp_path), "-k", name]) == 1
    out = capsys.readouterr().out
    assert "DIFFERS" in out and "residual" in out and R.REGENERATE in out


def test_recomputing_gives_the_same_text():
    pytest.importorskip("quatnav.sim")
    case = R.CASES_BY_NAME["nav13-ukf-f32_paper002"]
    first = R.compute(case).text
    R.scenario.cache_clear()  # the scenario is simulated again
    assert R.compute(case).text == first


def test_a_change_of_type_with_the_same_values_is_not_a_change_of_value(tmp_path):
    case = _holding("qekf-f32_rotation")
    lines = (R.OUT_DIR / f"{case.name}.csv").read_text().splitlines()
    first = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    j = lines[first].split(",").index("q_w")
    t = next(i for i, line in enumerate(lines) if line.startswith("# types: "))
    types = lines[t][len("# types: "):].split(",")
    assert types[j] == "f4"
    types[j] = "f8"
    lines[t] = "# types: " + ",".join(types)
    for i in range(first + 1, len(lines)):  # the same values written as float64
        cells = lines[i].split(",")
        cells[j] = repr(float(np.float32(float(cells[j]))))
        lines[i] = ",".join(cells)
    f = tmp_path / "x.csv"
    f.write_text("\n".join(lines) + "\n")
    cmp = _compare(case, f)
    assert not cmp["ok"] and cmp["differences"] == []
    assert any(m.startswith("types:") for m in cmp["messages"])
