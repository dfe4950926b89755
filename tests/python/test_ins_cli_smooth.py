"""``quatnav ins run --smooth``: the smoothed rows of the paper-004 walk's CSV files (the files of
test_ins_cli.py) against the filter's rows and the truth; ``-h`` documents the option."""
import json

import numpy as np
import pytest

from quatnav import cli
from quatnav.core import earth

pytest.importorskip("pandas")
from test_ins_cli import _args, _read, files, walk  # noqa: E402,F401  (the fixtures)


def _horizontal_rms(walk, c):
    i = np.searchsorted(walk.truth.t, c["time"])
    lat, h = walk.truth.lat[i], walk.truth.h[i]
    R_M, R_N = earth.radii(lat)
    dn = (np.radians(c["lat"]) - lat) * (R_M + h)
    de = (np.radians(c["lon"]) - walk.truth.lon[i]) * (R_N + h) * np.cos(lat)
    return np.sqrt(np.mean(dn ** 2 + de ** 2))


def test_smooth_writes_the_smoothed_rows(walk, files, capsys):
    out_f, out_s, js = files["dir"] / "fwd.csv", files["dir"] / "smooth.csv", files["dir"] / "smooth.json"
    assert cli.main(_args(files, out_f)) == 0
    assert cli.main(_args(files, out_s) + ["--smooth", "--json", str(js)]) == 0
    cap = capsys.readouterr()
    assert any(line.startswith("wrote") and line.endswith("; smoothed") for line in cap.out.splitlines())
    assert json.loads(js.read_text())["smoothed"] is True
    hf, a_f = _read(out_f)
    hs, a_s = _read(out_s)
    assert hf == hs and a_f.shape == a_s.shape
    f = {n: a_f[:, i] for i, n in enumerate(hf)}
    s = {n: a_s[:, i] for i, n in enumerate(hs)}
    np.testing.assert_array_equal(s["time"], f["time"])
    np.testing.assert_array_equal(a_s[-1], a_f[-1])  # the last row: the filter's
    assert not np.array_equal(s["lat"], f["lat"])
    for col in ("sigma_n", "sigma_e", "sigma_d", "sigma_vn", "sigma_psi_d_deg"):
        assert np.all(s[col] <= f[col] * (1 + 1e-5)), col  # the printed digits (%.6g)
    assert np.mean(s["sigma_n"]) < 0.9 * np.mean(f["sigma_n"])
    assert _horizontal_rms(walk, s) < _horizontal_rms(walk, f)


def test_help_mentions_smooth(capsys):
    with pytest.raises(SystemExit):
        cli.main(["ins", "run", "--help"])
    assert "--smooth" in capsys.readouterr().out
