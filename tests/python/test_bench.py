"""`quatnav bench` runs end to end on a small N and reports consistent figures (no timing asserts)."""
import json

import numpy as np
import pytest

from quatnav.evaluation import bench


def test_marg_data_is_consistent():
    d = bench.marg_data(2000, seed=0)
    assert d.gyr.shape == (2000, 3) and d.acc.shape == (2000, 3) and d.mag.shape == (2000, 3)
    assert np.all(np.isfinite(d.gyr)) and np.all(np.isfinite(d.acc))
    # the accelerometer sees gravity on average
    assert abs(np.linalg.norm(d.acc, axis=1).mean() - 9.81) < 0.5


def test_cli_small_run_writes_json(tmp_path, capsys):
    out = tmp_path / "b.json"
    from quatnav.cli import main
    rc = main(["bench", "-n", "3000", "--repeat", "1", "--filters", "QuaternionEKF,VQF", "--json", str(out)])
    assert rc == 0
    res = json.loads(out.read_text())
    rows = res["throughput"]["results"]
    names = {r["name"] for r in rows}
    assert "QuaternionEKF f64" in names and "QuaternionEKF f32" in names
    for r in rows:
        assert r["samples_per_s"] > 0 and np.isfinite(r["samples_per_s"])
    assert "quatnav bench -n 3000" in res["command"]
    assert "QuaternionEKF f64" in capsys.readouterr().out


@pytest.mark.parametrize("entry", bench.entries(), ids=lambda e: e.name)
def test_every_registered_entry_runs(entry):
    """Every filter and peer of `quatnav bench` runs on a short record (the peers whose package is
    installed); a quaternion output is finite and of unit norm."""
    if not bench._available(entry):
        pytest.skip(f"{entry.requires} not installed")
    d = bench.marg_data(300, seed=1).astype(entry.dtype)
    out = entry.make(d)()
    if isinstance(out, np.ndarray) and out.ndim == 2 and out.shape[1] == 4:
        assert out.shape[0] == 300
        assert np.all(np.isfinite(out))
        np.testing.assert_allclose(np.linalg.norm(out, axis=1), 1.0, atol=1e-3)
