"""Committed reference outputs (tests/regression/*.csv): every filter and time update on fixed
inputs must give the same numbers, bit for bit where the arithmetic environment is the one the
files were written in (tests/regression/environment.txt), else within a stated tolerance derived
from float rounding (tools/regression.py, TOLERANCE_ULPS). Nothing here skips for the
environment: the inputs are stored in the repository (tests/regression/inputs/), so they cannot
drift with numpy or the CPU; only the cases of the BROAD trial skip when its data is absent.

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


def _compare(case, path=None, mode=None):
    if case.scenario == "broad":
        pytest.importorskip("scipy.io")
    try:
        return R.compare(case, path, mode=mode)
    except R.DataMissing as e:
        pytest.skip(str(e))


@pytest.mark.parametrize("case", R.CASES, ids=[c.name for c in R.CASES])
def test_reference_outputs(case):
    cmp = _compare(case)
    assert cmp["ok"], R.report(case, cmp) + (
        "\n  this arithmetic environment differs from the recorded one: " + "; ".join(R.environment_differences())
        if cmp["mode"] == "tolerance" else "")


def test_environment_is_recorded():
    assert R.ENV_FILE.is_file(), f"run {R.REGENERATE}"
    assert set(R.recorded_environment()) == set(R.environment())


def test_every_file_is_a_case_and_every_case_has_a_file():
    files = {p.stem for p in R.OUT_DIR.glob("*.csv") if p.name != R.TOL_FILE.name}
    names = {c.name for c in R.CASES}
    assert files - names == set(), f"files of no case in {R.OUT_DIR} (remove them or run {R.REGENERATE})"
    assert names - files == set(), f"cases without a file (run {R.REGENERATE})"
    size = sum(p.stat().st_size for p in R.OUT_DIR.glob("*.csv") if p.name != R.TOL_FILE.name)
    assert size < 2.5e6, f"tests/regression holds {size / 1e6:.2f} MB: write fewer rows"
    stored = {p.stem for p in R.INPUT_DIR.glob("*.npz")}
    assert stored == set(R.STORED), f"tests/regression/inputs: {sorted(stored)} (run {R.UPDATE_INPUTS})"
    size = sum(p.stat().st_size for p in R.INPUT_DIR.glob("*.npz"))
    assert size < 0.6e6, f"tests/regression/inputs holds {size / 1e6:.2f} MB"


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


# ------------------------------------------------------------------------------------------------
# Stored inputs.
# ------------------------------------------------------------------------------------------------
def test_stored_inputs_read_back_exactly_and_the_rounding_is_below_the_noise(tmp_path):
    """The storage of the inputs: time stamps on the simulator's grid (t = k * 0.5/rate) and a
    signal already on a grid come back bit for bit; a noisy signal is rounded to a power-of-two
    step of at most 1/16 of its noise (error at most 1/32 of the noise of its quietest column);
    NaN rows, scalars and small arrays come back as they were; the same inputs give the same file
    bytes."""
    rng = np.random.default_rng(3)
    n = 3001
    t = np.arange(2 * n - 1)[::2] * (0.5 * (1.0 / 100.0))  # the simulator's time grid
    sigma = np.array([1e-6, 3e-4, 0.05])
    smooth = np.column_stack([0.1 * np.sin(t), 9.8 + 0.2 * np.cos(0.3 * t), np.sin(2 * t)])
    x = smooth + sigma * rng.standard_normal((n, 3))
    x[7] = np.nan
    q = 0.00128 * np.round(rng.normal(size=(n, 3)) / 0.00128 * 40)  # a quantized sensor
    d = {"t": t, "gps_t": t[::20].copy(), "x": x, "q": q, "dt": 0.01, "P0": np.diag(rng.uniform(size=13)),
         "flags": np.arange(n, dtype=np.uint32)}
    path = tmp_path / "s.npz"
    R.write_inputs(path, d)
    back = R.read_inputs(path)
    assert set(back) == set(d)
    for key in ("t", "gps_t", "q", "P0", "flags"):
        assert back[key].dtype == np.asarray(d[key]).dtype
        assert np.array_equal(np.asarray(back[key]).view(np.uint8), np.asarray(d[key]).view(np.uint8)), key
    assert back["dt"] == 0.01 and isinstance(back["dt"], float)
    assert np.array_equal(np.isnan(back["x"]), np.isnan(x))
    err = np.nanmax(np.abs(back["x"] - x), axis=0)
    # one step for the array: at most 1/16 of its smallest column noise
    assert np.all(err <= sigma.min() / 32) and np.all(err > 0), err / sigma
    first = path.read_bytes()
    R.write_inputs(path, d)
    assert path.read_bytes() == first


def test_every_stored_scenario_reads_back_as_its_recorded_sha256():
    """The inputs a case runs on are the stored ones, whose sha256 every file records: reading
    them needs nothing but numpy (no simulator, no libm)."""
    for case in R.CASES:
        if case.scenario not in R.STORED:
            continue
        d = R.scenario(case.scenario)
        header, _, _ = R.read(R.OUT_DIR / f"{case.name}.csv")
        assert R._header_field(header, "inputs sha256") == R._digest(sorted((k, np.asarray(v)) for k, v in d.items()))


# ------------------------------------------------------------------------------------------------
# The comparison in its two modes. Each test writes the current result as the reference and
# edits it, so that it judges the comparison whatever the environment.
# ------------------------------------------------------------------------------------------------
def _edit(path, out, row, column, fn):
    """Copy the reference file ``path`` to ``out`` with one cell (data row ``row``, ``column``) replaced;
    returns the sample index k of that row."""
    lines = path.read_text().splitlines()
    first = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    names = lines[first].split(",")
    cells = lines[first + 1 + row].split(",")
    j = names.index(column)
    cells[j] = fn(cells[j])
    lines[first + 1 + row] = ",".join(cells)
    out.write_text("\n".join(lines) + "\n")
    return int(cells[0])


def _current(name, tmp_path):
    """(case, path of a reference file written from the current code)."""
    case = R.CASES_BY_NAME[name]
    ref = tmp_path / f"{name}.ref.csv"
    ref.write_text(R.compute(case).text)
    return case, ref


def _cell(path, row, column):
    header, names, cols = R.read(path)
    return float(cols[names.index(column)][row])


def test_the_current_code_agrees_with_itself_in_both_modes(tmp_path):
    case, ref = _current("qekf_rotation", tmp_path)
    for mode in ("exact", "tolerance"):
        cmp = R.compare(case, ref, mode=mode)
        assert cmp["ok"] and cmp["differences"] == [], mode


def test_one_percent_in_one_cell_fails_in_both_modes(tmp_path):
    """q_w of euler-6d_rotation at k = 950 times 0.99, in the committed file as in a current one."""
    case = R.CASES_BY_NAME["euler-6d_rotation"]
    row = 950 // case.stride
    committed, current = R.OUT_DIR / f"{case.name}.csv", _current(case.name, tmp_path)[1]
    for ref in (committed, current):
        f = tmp_path / "x.csv"
        k = _edit(ref, f, row, "q_w", lambda s: repr(float(s) * 0.99))
        assert k == 950
        for mode in ("exact", "tolerance", None):
            cmp = R.compare(case, f, mode=mode)
            assert not cmp["ok"], mode
            if ref == committed and R.default_mode() == "tolerance" and mode == "exact":
                continue  # elsewhere the committed file differs bit for bit anyway
            assert [(d.column, d.first_row, d.n_rows) for d in cmp["differences"]] == [("q_w", 950, 1)]


def test_one_ulp_fails_bit_for_bit_and_passes_within_the_tolerance(tmp_path):
    case, ref = _current("qekf_rotation", tmp_path)
    f = tmp_path / "x.csv"
    k = _edit(ref, f, 7, "q_x", lambda s: repr(float(np.nextafter(float(s), np.inf))))
    cmp = R.compare(case, f, mode="exact")
    assert not cmp["ok"]
    assert [(d.column, d.first_row, d.n_rows) for d in cmp["differences"]] == [("q_x", k, 1)]
    assert 0 < cmp["differences"][0].max_abs < 1e-15
    text = R.report(case, cmp)
    assert "q_x" in text and f"k={k}" in text and "tools/regression.py --update" in text
    assert R.compare(case, f, mode="tolerance")["ok"]


@pytest.mark.parametrize("name,column,dtype", [("qekf_rotation", "sigma_bx", np.float64),
                                               ("nav13-ukf_paper002", "v_n", np.float64),
                                               ("qekf-f32_rotation", "q_y", np.float32)])
def test_a_change_at_the_tolerance_scale_is_caught(tmp_path, name, column, dtype):
    """A change of twice the column's tolerance fails, one of half of it passes (in float32 too)."""
    case, ref = _current(name, tmp_path)
    _, names, cols = R.read(ref)
    old = np.array([R.parse_value(s, dtype) for s in cols[names.index(column)]], dtype)
    tol = R.column_tolerance(case, column, old)
    row = len(old) // 2
    assert tol > 0 and abs(float(old[row])) > 0
    f = tmp_path / "x.csv"
    for factor, ok in ((2.0, False), (0.5, True)):
        _edit(ref, f, row, column, lambda s: R.format_value(dtype(float(s) + factor * tol), dtype))
        assert abs(_cell(f, row, column) - float(old[row])) == pytest.approx(factor * tol, rel=0.02)
        cmp = R.compare(case, f, mode="tolerance")
        assert cmp["ok"] is ok, (factor, R.report(case, cmp))
        assert not R.compare(case, f, mode="exact")["ok"]


def test_flags_and_nan_must_be_equal_in_both_modes(tmp_path):
    case, ref = _current("gpsins_walk", tmp_path)
    f = tmp_path / "x.csv"
    k = _edit(ref, f, 3, "flags", lambda s: str(int(s) ^ 4))
    for mode in ("exact", "tolerance"):
        cmp = R.compare(case, f, mode=mode)
        assert [(d.column, d.first_row, d.max_abs) for d in cmp["differences"]] == [("flags", k, 4.0)], mode
    # Row 0 is before navigation starts: NaN position; put a number there.
    _edit(ref, f, 0, "llh_lat", lambda s: "0.5" if s == "nan" else "nan")
    for mode in ("exact", "tolerance"):
        cmp = R.compare(case, f, mode=mode)
        assert [(d.column, d.max_abs) for d in cmp["differences"]] == [("llh_lat", np.inf)], mode
    case, ref = _current("qekf_rotation", tmp_path)
    _edit(ref, f, 0, "bias_x", lambda s: "-0.0" if s == "0.0" else s)
    assert [d.column for d in R.compare(case, f, mode="exact")["differences"]] == ["bias_x"]


def test_changed_inputs_fail_in_both_modes(tmp_path):
    case, ref = _current("gpsins_walk", tmp_path)
    f = tmp_path / "x.csv"
    f.write_text(ref.read_text().replace("# inputs sha256: ", "# inputs sha256: 0"))
    for mode in ("exact", "tolerance"):
        cmp = R.compare(case, f, mode=mode)
        assert not cmp["ok"] and cmp["inputs_changed"] and any("inputs changed" in m for m in cmp["messages"])


def test_a_summary_sum_within_the_tolerance_and_a_counter_exactly(tmp_path):
    case, ref = _current("nav13-ekf_paper002", tmp_path)
    text = ref.read_text()
    line = next(ln for ln in text.splitlines() if ln.startswith("# summary: vel_nis_sum="))
    v = float(line.split("=", 1)[1])
    ulps = R.read_tolerances()[case.name]["summary:vel_nis_sum"]
    f = tmp_path / "x.csv"
    for factor, ok in ((0.5, True), (2.0, False)):
        moved = float(v * (1 + factor * ulps * np.finfo(float).eps))
        f.write_text(text.replace(line, f"# summary: vel_nis_sum={moved!r}"))
        assert R.compare(case, f, mode="tolerance")["ok"] is ok, factor
        assert not R.compare(case, f, mode="exact")["ok"]
    line = next(ln for ln in text.splitlines() if ln.startswith("# summary: vel_status."))
    key, _, count = line.partition("=")
    f.write_text(text.replace(line, f"{key}={int(count) + 1}"))
    assert not R.compare(case, f, mode="tolerance")["ok"]


def test_the_mode_follows_the_recorded_environment(tmp_path):
    env = tmp_path / "environment.txt"
    R.write_environment(env)
    assert R.default_mode(env) == "exact" and R.environment_differences(env) == []
    env.write_text(env.read_text().replace("libm: ", "libm: other-"))
    assert R.default_mode(env) == "tolerance"
    assert any(d.startswith("libm:") for d in R.environment_differences(env))


def test_command_line_update_then_compare(tmp_path, capsys):
    name = "marg-gps_turn"
    assert R.main(["--update", "--dir", str(tmp_path), "-k", name]) == 0
    assert (tmp_path / f"{name}.csv").read_text() == R.compute(R.CASES_BY_NAME[name]).text
    assert R.main(["--dir", str(tmp_path), "-k", name]) == 0
    assert "mode: exact" in capsys.readouterr().out
    _edit(tmp_path / f"{name}.csv", tmp_path / f"{name}.csv", 2, "residual",
          lambda s: "nan" if s != "nan" else "1.0")
    for mode in ("auto", "tolerance"):
        capsys.readouterr()
        assert R.main(["--dir", str(tmp_path), "-k", name, "--mode", mode]) == 1
        out = capsys.readouterr().out
        assert "DIFFERS" in out and "residual" in out and R.REGENERATE in out


def test_recomputing_gives_the_same_text():
    case = R.CASES_BY_NAME["nav13-ukf-f32_paper002"]
    first = R.compute(case).text
    R.scenario.cache_clear()  # the inputs are read again
    assert R.compute(case).text == first


def test_a_change_of_type_with_the_same_values_is_not_a_change_of_value(tmp_path):
    case, ref = _current("qekf-f32_rotation", tmp_path)
    lines = ref.read_text().splitlines()
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
    cmp = R.compare(case, f, mode="exact")
    assert not cmp["ok"] and cmp["differences"] == []
    assert any(m.startswith("types:") for m in cmp["messages"])
