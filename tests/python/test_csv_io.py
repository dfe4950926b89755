"""quatnav.io.table.read_table: delimiters, byte-order mark, header case, decimal comma, and errors
that name the file, its line number and the column."""
import sys

import numpy as np
import pytest

pytest.importorskip("pandas")

from quatnav.io.table import CsvError, read_table, sniff_delimiter  # noqa: E402

COLS = ("time", "gyro_x", "accel_z")


@pytest.fixture(params=["pyarrow", "pandas"])
def reader(request, monkeypatch):
    """Each reading test twice: pyarrow's parser (the fast path, taken when pyarrow is installed
    and the file parses) and pandas' (the fallback that also words the errors)."""
    import quatnav.io.table as table
    if request.param == "pyarrow":
        pytest.importorskip("pyarrow")
        calls = []
        fast = table._read_fast
        monkeypatch.setattr(table, "_read_fast", lambda *a: calls.append(1) or fast(*a))
        yield request.param
        assert calls, "the pyarrow path was not tried"
    else:
        monkeypatch.setattr(table, "_read_fast", lambda *a: None)
        yield request.param


def _write(tmp_path, text, name="f.csv", encoding="utf-8"):
    p = tmp_path / name
    p.write_bytes(text.encode(encoding))
    return p


def _err(path, required=COLS, optional=(), match=None):
    with pytest.raises(CsvError) as e:
        read_table(path, required, optional, what="IMU")
    msg = str(e.value)
    assert str(path) in msg and msg.startswith("IMU ") and "\n" not in msg
    if match:
        assert match in msg, msg
    return msg


@pytest.mark.parametrize("sep", [",", ";", "\t", " ", "  "])
def test_delimiters(tmp_path, reader, sep):
    text = sep.join(COLS) + "\n" + "\n".join(sep.join(f"{v:g}" for v in (k * 0.01, 0.1 * k, -9.8))
                                            for k in range(5)) + "\n"
    t = read_table(_write(tmp_path, text), COLS)
    np.testing.assert_allclose(t["time"], np.arange(5) * 0.01)
    np.testing.assert_allclose(t["accel_z"], -9.8)
    assert list(t.lines) == [2, 3, 4, 5, 6]


def test_bom_header_case_spaces_comments_and_line_numbers(tmp_path, reader):
    text = "# exported by a logger\n\n  Time , GYRO_X ,Accel_Z, Temp \n1.0,0.5,-9.8,20\n# pause\n\n2.0, 0.25 ,-9.7,21\n"
    t = read_table(_write(tmp_path, text, encoding="utf-8-sig"), COLS, optional=("accel_x",))
    assert t.header == ["time", "gyro_x", "accel_z", "temp"]
    assert list(t.lines) == [4, 7]
    np.testing.assert_allclose(t["gyro_x"], [0.5, 0.25])
    assert np.isnan(t["accel_x"]).all()  # an absent optional column
    assert t.delimiter == ","


def test_decimal_comma_with_semicolons(tmp_path, reader):
    text = "time;gyro_x;accel_z\n0,01;1,5e-3;-9,81\n0,02;-2,0;-9,80\n"
    t = read_table(_write(tmp_path, text), COLS)
    assert t.decimal == ","
    np.testing.assert_allclose(t["time"], [0.01, 0.02])
    np.testing.assert_allclose(t["gyro_x"], [1.5e-3, -2.0])


def test_optional_cells_may_be_empty(tmp_path, reader):
    t = read_table(_write(tmp_path, "time,gyro_x,accel_z,v_n\n0,0,-9.8,\n1,0,-9.8,2.5\n"), COLS, optional=("v_n",))
    assert np.isnan(t["v_n"][0]) and t["v_n"][1] == 2.5


def test_sniffer():
    assert sniff_delimiter("a,b;c,d") == ","
    assert sniff_delimiter("a;b;c") == ";"
    assert sniff_delimiter("a\tb") == "\t"
    assert sniff_delimiter("a  b c") == r"\s+"
    assert sniff_delimiter("time") == ","


def test_missing_and_duplicate_columns(tmp_path):
    msg = _err(_write(tmp_path, "\n# c\ntime,gyro_y,accel_z\n0,0,0\n"), match="line 3: missing column 'gyro_x'")
    assert "found time, gyro_y, accel_z" in msg
    _err(_write(tmp_path, "time,gyro_x,Time,accel_z\n0,0,0,0\n"), match="line 1: column 'time' appears twice")


def test_bad_cells_name_line_and_column(tmp_path, reader):
    head = "time,gyro_x,accel_z\n"
    _err(_write(tmp_path, head + "0,0,-9.8\n\n0.1,abc,-9.8\n"),
         match="line 4, column 'gyro_x': not a finite number ('abc')")
    _err(_write(tmp_path, head + "0,0,-9.8\n0.1,nan,-9.8\n"),
         match="line 3, column 'gyro_x': not a finite number ('nan')")
    _err(_write(tmp_path, head + "0,0,-9.8\n0.1,0,inf\n"),
         match="line 3, column 'accel_z': not a finite number ('inf')")
    _err(_write(tmp_path, head + "0,0,-9.8\n0.1,,-9.8\n"), match="line 3, column 'gyro_x': empty")
    _err(_write(tmp_path, head + "0,0,-9.8\n0.1,0\n"), match="line 3, column 'accel_z': empty (the line has 2 fields")
    _err(_write(tmp_path, head + "0,0,-9.8\n0.1,0,-9.8,7\n"), match="line 3: 4 fields, the header (line 1) has 3")
    # a non-finite value in an optional column is an error too; an empty one is not
    _err(_write(tmp_path, "time,gyro_x,accel_z,v_n\n0,0,-9.8,x\n"), optional=("v_n",), match="column 'v_n'")


def test_times_must_increase(tmp_path, reader):
    head = "time,gyro_x,accel_z\n"
    _err(_write(tmp_path, head + "0,0,0\n# x\n0.2,0,0\n0.1,0,0\n"),
         match="line 5, column 'time': time goes backwards (0.1 after 0.2 on line 4)")
    _err(_write(tmp_path, head + "0,0,0\n0,0,0\n"), match="line 3, column 'time': duplicate time")


def test_empty_files_and_encoding(tmp_path):
    _err(_write(tmp_path, ""), match="empty file")
    _err(_write(tmp_path, "# only a comment\n\n"), match="empty file")
    _err(_write(tmp_path, "time,gyro_x,accel_z\n"), match="no data rows")
    _err(_write(tmp_path, "time,gyro_x,accel_z\n0,0,0\n", encoding="utf-16"), match="not UTF-8")
    _err(tmp_path / "nope.csv", match="cannot open")


def test_without_pandas_names_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match=r"quatnav\[io\]"):
        read_table(_write(tmp_path, "time,gyro_x,accel_z\n0,0,0\n"), COLS)


def test_numpy_alone_imports_quatnav():
    import subprocess
    code = "import sys; sys.modules['pandas'] = None; import quatnav, quatnav.io.table, quatnav.cli.ins, quatnav.cli"
    import quatnav
    from pathlib import Path
    env = {"PYTHONPATH": str(Path(quatnav.__file__).resolve().parent.parent)}
    import os
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=dict(os.environ, **env))
    assert p.returncode == 0, p.stderr


def test_reader_paths_give_the_same_rows(tmp_path, reader):
    # one contiguous body (the fast path: one slice of the file) and bodies with comments, blank
    # lines, CRLF line ends, indented comments and no final newline (the bytes gathered by mask)
    rows = [(k * 0.01, 0.1 * k, -9.8 + k) for k in range(6)]
    plain = "time,gyro_x,accel_z\n" + "".join(f"{a:g},{b:g},{c:g}\n" for a, b, c in rows)
    t = read_table(_write(tmp_path, plain, "a.csv"), COLS)
    assert list(t.lines) == [2, 3, 4, 5, 6, 7]
    mixed = ("time,gyro_x,accel_z\r\n" + "".join(f"{a:g},{b:g},{c:g}\r\n" for a, b, c in rows[:2]) + "\r\n"
             + "   # indented comment\r\n" + f"{rows[2][0]:g},{rows[2][1]:g},{rows[2][2]:g}\r\n#x\n"
             + "".join(f"  {a:g},{b:g},{c:g}\n" for a, b, c in rows[3:5]) + "\t\n"
             + f"{rows[5][0]:g},{rows[5][1]:g},{rows[5][2]:g}")
    u = read_table(_write(tmp_path, mixed, "b.csv"), COLS)
    assert list(u.lines) == [2, 3, 6, 8, 9, 11]
    for c in COLS:
        np.testing.assert_array_equal(u[c], t[c])
    cr = read_table(_write(tmp_path, plain.replace("\n", "\r"), "cr.csv"), COLS)   # classic Mac line ends
    np.testing.assert_array_equal(cr["accel_z"], t["accel_z"])
    # a bad cell after skipped lines is reported on its own line of the file
    bad = mixed.replace("  0.04,0.4", "  0.04,x")
    _err(_write(tmp_path, bad, "c.csv"), match="line 9, column 'gyro_x'")


def test_pyarrow_path_rounds_correctly_and_leaves_pandas_unimported(tmp_path):
    """The fast path parses every field to the nearest double (as Python's float() does) and,
    on a clean file, does not import pandas (about 0.7 s of a command's start), nor does writing
    CSV or Parquet through pyarrow."""
    pytest.importorskip("pyarrow")
    import os
    import subprocess
    import quatnav
    import quatnav.io.table as table
    rng = np.random.default_rng(11)
    v = rng.normal(size=(3000, 3)) * 10.0 ** rng.integers(-12, 12, (3000, 1))
    texts = [[f"{x:.17g}" for x in row] for row in v]
    texts[5][1] = "1.00000000000000011102230246251565404236316680908203125"  # a tie, rounded to even
    texts[6][1] = "  2.5e-3"
    body = "".join(f"{k * 0.01:.2f}," + ",".join(r[1:]) + "\n" for k, r in enumerate(texts))
    p = _write(tmp_path, "time,gyro_x,accel_z\n" + body)
    t = read_table(p, COLS)
    want = np.array([[float(x) for x in r[1:]] for r in texts])
    np.testing.assert_array_equal(t["gyro_x"], want[:, 0])
    np.testing.assert_array_equal(t["accel_z"], want[:, 1])
    code = ("import sys; from quatnav.io.table import read_table; "
            f"t = read_table({str(p)!r}, ('time', 'gyro_x', 'accel_z')); assert len(t) == 3000; "
            "from quatnav.io.table import write_table; "
            f"write_table({str(tmp_path / 'o.csv')!r}, ['a', 'b'], [t['time'], t['gyro_x']], '%.6f'); "
            f"write_table({str(tmp_path / 'o.parquet')!r}, ['a', 'b'], [t['time'], t['gyro_x']], '%.6f'); "
            "print('pandas' in sys.modules)")
    env = dict(os.environ, PYTHONPATH=str(os.path.dirname(os.path.dirname(quatnav.__file__))))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"
    assert table._read_fast(b"1,x,3\n", ",", ".", 3, [0, 1, 2], 1) is None  # text: the fallback words it


@pytest.mark.parametrize("block", [1 << 22, 4096])
def test_both_paths_agree_on_empty_optional_cells_across_blocks(tmp_path, monkeypatch, block):
    """Optional cells empty here and there, in a file parsed in many blocks (pyarrow's chunks,
    each with its own validity bitmap): the same values and NaNs as pandas' path."""
    pytest.importorskip("pyarrow")
    import quatnav.io.table as table
    rng = np.random.default_rng(2)
    rows = []
    for k in range(5000):
        v = "" if rng.random() < 0.3 else f"{rng.normal():.6f}"
        rows.append(f"{k * 0.005:.3f},{rng.normal():.9f},-9.81,{v},note{k}\n")
    p = _write(tmp_path, "time,gyro_x,accel_z,v_n,text\n" + "".join(rows))
    monkeypatch.setattr(table, "_BLOCK", block)
    fast = read_table(p, COLS, optional=("v_n", "v_e"))
    monkeypatch.setattr(table, "_read_fast", lambda *a: None)
    slow = read_table(p, COLS, optional=("v_n", "v_e"))
    for c in COLS + ("v_n", "v_e"):
        np.testing.assert_array_equal(fast[c], slow[c])
    assert 1000 < np.isnan(fast["v_n"]).sum() < 2000 and np.isnan(fast["v_e"]).all()


def _fmt_values():
    rng = np.random.default_rng(5)
    v = rng.normal(size=4000) * 10.0 ** rng.integers(-9, 9, 4000)
    return np.concatenate([v, [0.0, -0.0, 1e-4, 9.99995e-5, 123456.5, 1e6, 0.5, np.nan, np.inf, -np.inf]])


@pytest.mark.parametrize("fmt", ["%.6g", "%.10g", "%.3g", "%.6f", "%.10f"])
def test_round_to_format_gives_printf_numbers(fmt):
    from quatnav.io.table import round_to_format
    v = _fmt_values()
    if fmt.endswith("f"):
        v = v[~(np.abs(v) > (400.0 if fmt == "%.10f" else 1e5))]   # %.10f: latitudes, longitudes
    r = round_to_format(v, fmt)
    ref = np.array([float(fmt % x) for x in v])
    same = (r == ref) | (np.isnan(r) & np.isnan(ref))
    # only values within the double product's rounding error of a tie may differ, by one unit in
    # the last printed digit
    assert (~same).mean() < 2e-3, v[~same]
    assert np.all(np.abs(r[~same] - ref[~same]) <= 1.01 * np.abs(ref[~same]) * 10.0 ** (1 - int(fmt[2:-1]))
                  if fmt.endswith("g") else np.abs(r[~same] - ref[~same]) <= 1.01 * 10.0 ** -int(fmt[2:-1]))


def test_write_table_csv_and_parquet(tmp_path, monkeypatch):
    import pandas as pd
    from quatnav.io.table import write_table
    v = _fmt_values()
    v = v[np.isfinite(v)]
    t = np.arange(len(v)) * 0.005
    names, cols, fmts = ["time", "x", "y"], [t, v, v / 7.0], ["%.6f", "%.6g", "%.10g"]
    seen = []

    class P:
        def update(self, n):
            seen.append(n)
    write_table(tmp_path / "a.csv", names, cols, fmts, chunk_rows=1000, progress=P())
    assert sum(seen) == len(v) and len(seen) == -(-len(v) // 1000)
    # the chunks, formatted on threads, are written in order: the same bytes as one chunk
    write_table(tmp_path / "d.csv", names, cols, fmts, chunk_rows=len(v) + 1)
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "d.csv").read_bytes()
    df = pd.read_csv(tmp_path / "a.csv")
    assert list(df.columns) == names
    for c, col, f in zip(names, cols, fmts):
        ref = np.array([float(f % x) for x in col])
        assert np.mean(df[c].to_numpy() != ref) < 1e-3
        np.testing.assert_allclose(df[c].to_numpy(), ref, rtol=1e-5, atol=1e-6)
    pytest.importorskip("pyarrow.parquet")
    write_table(tmp_path / "c.parquet", names, cols, fmts)
    pq = pd.read_parquet(tmp_path / "c.parquet")
    np.testing.assert_array_equal(pq["x"].to_numpy(), v)   # Parquet keeps every bit
    # without pyarrow: numpy.savetxt with the formats, the same numbers (monkeypatch puts the
    # module back after the test)
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    write_table(tmp_path / "b.csv", names, cols, fmts)
    text = (tmp_path / "b.csv").read_text().splitlines()
    assert text[1] == ",".join(f % c[0] for f, c in zip(fmts, cols))
    np.testing.assert_allclose(pd.read_csv(tmp_path / "b.csv").to_numpy(), df.to_numpy(), rtol=2e-6, atol=1e-6)


def test_parquet_keeps_types_nans_and_strided_columns(tmp_path):
    """The pyarrow tables are built over the numpy columns (float64, as ``write_table`` takes
    them): NaN stays a number (not a null, as with ``pa.table``), integer, strided and
    big-endian columns come out with their values."""
    pq = pytest.importorskip("pyarrow.parquet")
    from quatnav.io.table import write_table
    x = np.arange(20.0)
    x[3] = np.nan
    flags = np.arange(10, dtype=np.uint32) * 3
    big = np.arange(10, dtype=">f8") / 4
    write_table(tmp_path / "a.parquet", ["x", "flags", "big"], [x[::2], flags, big], "%.3f")
    t = pq.read_table(tmp_path / "a.parquet")
    assert all(str(f.type) == "double" for f in t.schema) and t.column("x").null_count == 0
    np.testing.assert_array_equal(np.asarray(t.column("x")), x[::2])
    np.testing.assert_array_equal(np.asarray(t.column("flags")), flags)
    np.testing.assert_array_equal(np.asarray(t.column("big")), big)


def test_progress_bar_only_on_a_terminal_and_for_long_jobs(monkeypatch):
    import io as _io

    from quatnav.io.table import progress_bar
    pytest.importorskip("tqdm")
    short, off = progress_bar(1000), progress_bar(10 ** 6)   # pytest's stderr is no terminal
    for b in (short, off):
        b.update(10)
        b.close()
        assert type(b).__name__ == "_Null"

    class Tty(_io.StringIO):
        def isatty(self):
            return True
    err = Tty()
    monkeypatch.setattr(sys, "stderr", err)
    bar = progress_bar(10 ** 6, desc="ins run")
    bar.update(5 * 10 ** 5)
    bar.close()
    assert type(bar).__name__ == "tqdm" and "ins run" in err.getvalue()
    assert type(progress_bar(10)).__name__ == "_Null"          # short job: no bar even on a terminal
