"""Named scenarios, reproducibility, save/load, plot and the command line."""
import json

import numpy as np
import pytest

from quatnav.core import earth
from quatnav.sim import list_scenarios, load_csv, load_npz, make_scenario, save_csv, save_npz
from quatnav.sim import units
from quatnav.sim.io import csv_columns
from quatnav.sim.scenarios import PAPER002_NOISE_RATE_HZ

NAMES = ["paper002_straight_then_circle", "paper004_static", "paper004_turntable",
         "paper004_walk", "paper001_constant_turn", "handheld_marg", "handheld_marg_disturbed"]


def test_list():
    assert set(NAMES) <= set(list_scenarios())


@pytest.fixture(scope="module")
def scen():
    return {n: make_scenario(n, seed=3) for n in NAMES}


def test_every_scenario_is_sane(scen):
    for name, s in scen.items():
        tr = s.truth
        assert s.name == name.replace("_disturbed", "") or s.name == name
        assert np.all(np.isfinite(tr.q_nb)) and np.all(np.isfinite(s.imu.gyro))
        assert np.allclose(np.linalg.norm(tr.q_nb, axis=1), 1.0)
        assert not s.imu.saturated.any(), name
        json.dumps(s.params, default=lambda o: o.tolist() if hasattr(o, "tolist") else float(o))


def test_reproducible_by_seed(scen):
    a = make_scenario("paper004_walk", seed=3)
    b = scen["paper004_walk"]
    c = make_scenario("paper004_walk", seed=4)
    for g in ("imu", "gps", "baro", "compass"):
        for f in ("t",):
            assert np.array_equal(getattr(getattr(a, g), f), getattr(getattr(b, g), f))
    assert np.array_equal(a.imu.gyro, b.imu.gyro) and np.array_equal(a.gps.pos_n, b.gps.pos_n)
    assert not np.allclose(a.imu.gyro, c.imu.gyro)
    assert np.array_equal(a.truth.q_nb, c.truth.q_nb)  # truth does not depend on the seed


def test_paper002_parameters(scen):
    s = scen["paper002_straight_then_circle"]
    tr = s.truth
    assert tr.t[-1] == pytest.approx(200.0) and tr.rate_hz == PAPER002_NOISE_RATE_HZ
    assert np.allclose(tr.omega_nb_b[tr.t < 99.0], 0.0, atol=1e-12)
    assert np.all(tr.omega_nb_b[tr.t > 101.5, 2] > 0.09)
    err = s.imu.accel - tr.f_mean_b
    assert np.mean(err[1:], axis=0) == pytest.approx([units.ug(1000.0)] * 3, abs=units.ug(3.0))
    assert np.std(err[1:], axis=0) == pytest.approx([units.ug(30.0)] * 3, rel=0.05)
    err = s.imu.gyro - tr.omega_mean_b
    assert np.std(err[1:], axis=0) == pytest.approx([units.deg_per_h(0.3)] * 3, rel=0.05)
    assert np.mean(err[1:], axis=0) == pytest.approx([units.deg_per_h(1.0)] * 3,
                                                     abs=units.deg_per_h(0.01))
    assert np.std(s.gps.v_n - tr.v_n[s.gps.index_valid]) == pytest.approx(0.03048, rel=0.1)
    assert s.params["initial_errors"]["yaw_deg"] == 20.0


def test_paper004_and_paper001(scen):
    tt = scen["paper004_turntable"].truth
    assert np.max(np.abs(np.degrees(tt.rpy[:, 0]))) == pytest.approx(30.0, abs=0.01)
    assert np.max(np.abs(np.degrees(tt.rpy[:, 1]))) == pytest.approx(30.0, abs=0.01)
    w = scen["paper004_walk"].truth
    moving = np.linalg.norm(w.v_n, axis=1) > 1.0
    assert np.median(np.linalg.norm(w.v_n[moving], axis=1)) == pytest.approx(1.4, abs=0.05)
    assert w.pos_n[-1, :2] == pytest.approx([60.0, 52.8], abs=0.5)
    p1 = scen["paper001_constant_turn"]
    assert p1.params["gps"]["lever_arm_b_m"] == (0.8, 0.3, -0.9) or \
        list(p1.params["gps"]["lever_arm_b_m"]) == [0.8, 0.3, -0.9]
    assert p1.gps.t[1] - p1.gps.t[0] == pytest.approx(0.05)
    hm = scen["handheld_marg_disturbed"]
    assert hm.mag.disturbed.any() and not scen["handheld_marg"].mag.disturbed.any()


def test_scenario_options():
    s = make_scenario("paper004_static", seed=1, duration=10.0, gps_rate_hz=1.0)
    assert s.truth.t[-1] == pytest.approx(10.0) and len(s.gps.t) == 10
    assert s.params["choices"]["gps_rate_hz"] == 1.0
    h = make_scenario("handheld_marg", seed=1, rate_hz=100.0, duration=10.0)
    assert h.imu.rate_hz == 100.0 and h.mag.t.shape == h.imu.t.shape


def test_bad_scenario_arguments():
    with pytest.raises(ValueError, match="unknown scenario name"):
        make_scenario("nope")
    with pytest.raises(ValueError, match="seed"):
        make_scenario("paper004_static", seed=-1)


def _same(a, b):
    for f in ("t", "pos_n", "q_nb", "f_ib_b", "dtheta_b"):
        assert np.array_equal(getattr(a.truth, f), getattr(b.truth, f))
    for g in a.SENSORS:
        ga, gb = getattr(a, g), getattr(b, g)
        assert (ga is None) == (gb is None)
        if ga is not None:
            for k, v in vars(ga).items():
                assert np.array_equal(np.asarray(v), np.asarray(getattr(gb, k))), (g, k)
    assert a.params == b.params or json.dumps(a.params, default=str) == json.dumps(b.params, default=str)


def test_save_load_npz_csv(tmp_path, scen):
    s = scen["paper004_walk"]
    save_npz(s, tmp_path / "w.npz")
    r = load_npz(tmp_path / "w.npz")
    _same(s, r)
    assert r.truth.rate_hz == s.truth.rate_hz and r.seed == 3
    save_csv(s, tmp_path / "w.csv")
    c = load_csv(tmp_path / "w.csv")
    _same(s, c)
    header = (tmp_path / "w.csv").read_text().splitlines()[0].split(",")
    assert header == csv_columns("truth") and header[:4] == ["t", "lat", "lon", "h"]
    assert "q_nb_w" in header and "f_ib_b_z" in header and "pos_n_D" in header
    m = scen["handheld_marg_disturbed"]
    save_csv(m, tmp_path / "m.csv")
    _same(m, load_csv(tmp_path / "m.csv"))


def test_plot(tmp_path, scen):
    pytest.importorskip("matplotlib")
    from quatnav.sim import plot_scenario
    import matplotlib.pyplot as plt
    fig = plot_scenario(scen["handheld_marg_disturbed"], tmp_path / "h.png")
    assert len(fig.axes) == 6 and (tmp_path / "h.png").stat().st_size > 10000
    plt.close(fig)


def test_cli(tmp_path, capsys):
    from quatnav.cli import main as quatnav_main

    def main(argv):
        return quatnav_main(["simulate", *argv])
    assert main(["--list"]) == 0
    out = capsys.readouterr().out
    assert all(n in out for n in NAMES)
    assert main(["paper004_static", "--seed", "5", "--out", str(tmp_path / "s.npz")]) == 0
    s = load_npz(tmp_path / "s.npz")
    assert s.seed == 5 and s.name == "paper004_static"
    assert main(["nope", "--out", str(tmp_path / "x.npz")]) == 2
    assert "unknown scenario name" in capsys.readouterr().err
