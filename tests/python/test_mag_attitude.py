"""quatnav.calibration.mag_attitude: the magnetometer's offset and the Earth field fitted against
known attitudes (a GNSS/INS run without it), and `ins run --mag-calibrate` on the simulated car."""
from __future__ import annotations

import json

import numpy as np
import pytest

from quatnav.calibration.mag_attitude import mag_attitude_fit
from quatnav.core import quaternion as Q

FIELD = 50.0 * np.array([np.cos(np.radians(53.0)) * np.cos(np.radians(-8.5)),
                         np.cos(np.radians(53.0)) * np.sin(np.radians(-8.5)), np.sin(np.radians(53.0))])
OFFSET = np.array([8.0, -5.0, 3.0])


def _samples(n=3000, tilt_deg=3.0, seed=0):
    """Attitudes of a vehicle turning in yaw (and tilting by about tilt_deg), the magnetometer's
    samples in its body axes with the offset and 0.3 uT noise."""
    rng = np.random.default_rng(seed)
    yaw = np.cumsum(rng.normal(0.0, 0.05, n))
    tilt = np.radians(tilt_deg) * np.sin(np.arange(n)[:, None] * np.array([[0.013, 0.021]]))
    q = Q.from_euler(np.column_stack([tilt, yaw]))
    m = np.einsum("kji,j->ki", Q.to_rotmat(q), FIELD) + OFFSET + 0.3 * rng.standard_normal((n, 3))
    return q, m


def test_fit_on_a_drive_finds_the_horizontal_offset_and_the_declination():
    """Turning in yaw with a few degrees of tilt: the horizontal offset within 0.05 uT and the
    declination within 0.1 deg; the vertical offset is left to the prior (it trades with the
    field's down component), and its sigma says so."""
    q, m = _samples()
    fit = mag_attitude_fit(q, m)
    np.testing.assert_allclose(fit.offset[:2], OFFSET[:2], atol=0.05)
    assert abs(np.degrees(fit.declination) + 8.5) < 0.1
    assert fit.offset_sigma[2] > 10 * fit.offset_sigma[0]
    assert 0.25 < fit.residual_rms < 0.35 and fit.samples == fit.given == len(q)


def test_fit_with_full_rotations_finds_the_whole_offset_and_drops_a_disturbance():
    """Tumbling (tilts of 60 deg): the whole offset and the field; a disturbed stretch (a 20 uT
    magnet for 200 samples) is dropped as outliers."""
    q, m = _samples(tilt_deg=60.0, seed=1)
    m[1000:1200] += np.array([20.0, 0.0, -10.0])
    fit = mag_attitude_fit(q, m)
    np.testing.assert_allclose(fit.offset, OFFSET, atol=0.1)
    np.testing.assert_allclose(fit.field_n, FIELD, atol=0.1)
    assert abs(np.degrees(fit.inclination) - 53.0) < 0.1
    assert fit.samples <= fit.given - 200


def test_fit_needs_samples_and_shapes():
    q, m = _samples(n=150)
    m[60:] = np.nan
    assert mag_attitude_fit(q, m) is None  # 60 usable rows
    with pytest.raises(ValueError, match="q_nb must be"):
        mag_attitude_fit(q[:, :3], m)


def test_ins_run_mag_calibrate_on_the_car(tmp_path):
    """car_city told its mounting and latency: the magnetometer's 8/-5/3 uT of hard iron and -8.5 deg
    declination, uncalibrated, spoil the heading; --mag-calibrate finds the horizontal offset and the
    declination from a run without it and brings the heading within 0.3 deg RMS of the truth, with
    no warning. Without a magnetometer the option is a user's mistake."""
    import tomllib
    from quatnav import cli
    d = tmp_path / "car"
    assert cli.main(["simulate", "car_city", "--seed", "3", "--csv", str(d)]) == 0
    sc = tomllib.loads((d / "scenario.toml").read_text())
    (d / "m.toml").write_text((d / "config.toml").read_text().replace(
        "[filter]\n", f"[filter]\nimu_rotation = {sc['imu']['C_b_imu']}\ngps_time_offset = {-sc['gnss']['latency_s']}\n"))
    base = ["ins", "run", "--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"), "--mag", str(d / "mag.csv"),
            "--config", str(d / "m.toml")]
    heading = {}
    for name, extra in (("raw", []), ("calibrated", ["--mag-calibrate"])):
        out, js, cj = tmp_path / f"{name}.csv", tmp_path / f"{name}.json", tmp_path / f"{name}_c.json"
        assert cli.main(base + ["--out", str(out), "--json", str(js)] + extra) == 0
        assert cli.main(["compare", str(out), str(d / "truth.csv"), "--json", str(cj)]) == 0
        heading[name] = json.loads(cj.read_text())["attitude_heading_deg"]["rms"]
        s = json.loads(js.read_text())
    cal = s["mag_calibration"]
    np.testing.assert_allclose(cal["offset_imu_axes"][:2], sc["mag"]["hard_iron_uT"][:2], atol=0.5)
    assert abs(np.degrees(cal["declination_rad"]) - sc["mag"]["declination_deg"]) < 0.5
    assert not any("gated out (" in w for w in s["warnings"]), s["warnings"]
    assert heading["calibrated"] < 0.3 < 1.0 < heading["raw"], heading
    assert cli.main(["ins", "run", "--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"), "--config",
                     str(d / "m.toml"), "--out", str(tmp_path / "x.csv"), "--mag-calibrate"]) == 2
