"""quatnav.csvio.read_table: delimiters, byte-order mark, header case, decimal comma, and errors
that name the file, its line number and the column."""
import sys

import numpy as np
import pytest

pytest.importorskip("pandas")

from quatnav.csvio import CsvError, read_table, sniff_delimiter  # noqa: E402

COLS = ("time", "gyro_x", "accel_z")


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
def test_delimiters(tmp_path, sep):
    text = sep.join(COLS) + "\n" + "\n".join(sep.join(f"{v:g}" for v in (k * 0.01, 0.1 * k, -9.8))
                                            for k in range(5)) + "\n"
    t = read_table(_write(tmp_path, text), COLS)
    np.testing.assert_allclose(t["time"], np.arange(5) * 0.01)
    np.testing.assert_allclose(t["accel_z"], -9.8)
    assert list(t.lines) == [2, 3, 4, 5, 6]


def test_bom_header_case_spaces_comments_and_line_numbers(tmp_path):
    text = "# exported by a logger\n\n  Time , GYRO_X ,Accel_Z, Temp \n1.0,0.5,-9.8,20\n# pause\n\n2.0, 0.25 ,-9.7,21\n"
    t = read_table(_write(tmp_path, text, encoding="utf-8-sig"), COLS, optional=("accel_x",))
    assert t.header == ["time", "gyro_x", "accel_z", "temp"]
    assert list(t.lines) == [4, 7]
    np.testing.assert_allclose(t["gyro_x"], [0.5, 0.25])
    assert np.isnan(t["accel_x"]).all()  # an absent optional column
    assert t.delimiter == ","


def test_decimal_comma_with_semicolons(tmp_path):
    text = "time;gyro_x;accel_z\n0,01;1,5e-3;-9,81\n0,02;-2,0;-9,80\n"
    t = read_table(_write(tmp_path, text), COLS)
    assert t.decimal == ","
    np.testing.assert_allclose(t["time"], [0.01, 0.02])
    np.testing.assert_allclose(t["gyro_x"], [1.5e-3, -2.0])


def test_optional_cells_may_be_empty(tmp_path):
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


def test_bad_cells_name_line_and_column(tmp_path):
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


def test_times_must_increase(tmp_path):
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
    code = "import sys; sys.modules['pandas'] = None; import quatnav, quatnav.csvio, quatnav.ins_cli, quatnav.cli"
    import quatnav
    from pathlib import Path
    env = {"PYTHONPATH": str(Path(quatnav.__file__).resolve().parent.parent)}
    import os
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=dict(os.environ, **env))
    assert p.returncode == 0, p.stderr
