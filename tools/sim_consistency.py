"""Measure the simulator's consistency figures: strapdown round trip of every vehicle scenario
(numpy and C++) and the Allan read-outs of simulated gyros and accelerometers.

    PYTHONPATH=python python tools/sim_consistency.py
"""
import numpy as np
from quatnav.core import earth, quaternion as quat
from quatnav.sim import make_scenario, allan_deviation, allan_readout, units
from quatnav.sim.sensors import GyroSpec, AccelSpec, _triad
from quatnav.core.strapdown import StrapdownState, strapdown_run
from quatnav.filters.strapdown import strapdown_run_cpp
for name in ["paper002_straight_then_circle", "paper001_constant_turn", "paper004_turntable", "paper004_walk", "handheld_marg_disturbed"]:
    tr = make_scenario(name, 0).truth
    s = StrapdownState(tr.q_nb[0], tr.v_n[0], tr.lat[0], tr.lon[0], tr.h[0])
    for label, fn in (("numpy", strapdown_run), ("C++", strapdown_run_cpp)):
        o = fn(s, tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt, tr.earth_rate)
        p = earth.geodetic_to_ned(o["lat"], o["lon"], o["h"], tr.lat[0], tr.lon[0], tr.h[0])
        pe = np.linalg.norm(p - tr.pos_n[1:], axis=1).max()
        ae = np.degrees(np.linalg.norm(quat.to_rotvec(quat.mul(quat.conj(o["q_nb"]), tr.q_nb[1:])), axis=1)).max()
        print(f"{name:30s} {tr.t[-1]:5.0f} s {tr.rate_hz:4.0f} Hz {label:5s} max pos err {pe:.2e} m, max att err {ae:.2e} deg")
rate = 10.0; n = int(4 * 3600 * rate)
g, _, _ = _triad(np.zeros((n, 3)), GyroSpec(arw_deg_per_sqrt_h=0.15, bias_instability_deg_per_h=10.0, bias_corr_time_s=20.0).si(), 0.1, np.random.default_rng(2024))
a, _, _ = _triad(np.zeros((n, 3)), AccelSpec(vrw_m_per_s_per_sqrt_h=0.02, bias_instability_ug=100.0, bias_corr_time_s=20.0).si(), 0.1, np.random.default_rng(2024))
tg, adg = allan_deviation(g, rate); ta, ada = allan_deviation(a, rate)
for ax in range(3):
    r = allan_readout(tg, adg[:, ax]); ra = allan_readout(ta, ada[:, ax])
    print(f"axis {ax}: ARW {units.to_arw_deg_per_sqrt_h(r.random_walk):.4f} deg/sqrt(h) (spec 0.15), BI {units.to_deg_per_h(r.bias_instability):.2f} deg/h (spec 10); VRW {units.to_vrw_m_per_s_per_sqrt_h(ra.random_walk):.4f} m/s/sqrt(h) (spec 0.02), BI {units.to_ug(ra.bias_instability):.1f} ug (spec 100)")
