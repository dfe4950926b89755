"""``quatnav demo``: the attitude filters on a built-in simulated rotation.

The scenario: smooth random rotation (up to ~2 rad/s) with a magnetometer, constant gyro bias,
white sensor noise; exact truth. Prints RMSE of roll, pitch and yaw and the final gyro-bias
error of :class:`~quatnav.QuaternionEKF` (defaults, tuned for real data, and ``paper=True``:
the plain filter of paper 000), :class:`~quatnav.EulerEKF` and
:class:`~quatnav.MargFilter` (paper defaults, which estimate no gyro bias, and with its bias
integrator on); then :class:`~quatnav.NavFilter13` with its three time updates on paper
002's simulated run, and :class:`~quatnav.GpsInsFilter` on paper 004's simulated runs. ``--plot`` writes a figure of the attitude errors.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from . import quaternion as Q

GRAVITY = 9.80665


@dataclass
class RotationData:
    t: np.ndarray          #: (N,) s
    q_nb: np.ndarray       #: (N, 4) true attitude
    omega_b: np.ndarray    #: (N, 3) true body rate, rad/s
    gyr: np.ndarray        #: (N, 3) measured rate, rad/s
    acc: np.ndarray        #: (N, 3) measured specific force, m/s^2
    mag: np.ndarray        #: (N, 3) measured field, uT
    gyro_bias: np.ndarray  #: (3,) rad/s
    mag_n: np.ndarray      #: (3,) field in NED, uT
    dt: float


def rotation_scenario(n: int = 6000, rate: float = 100.0, seed: int = 0, max_rate: float = 2.0,
                      gyro_bias=(0.02, -0.015, 0.01), gyro_noise: float = 0.005,
                      acc_noise: float = 0.05, mag_noise: float = 0.5, dip_deg: float = 60.0,
                      start_still: float = 1.0, pitch_limit: float = 1.2) -> RotationData:
    """A smooth random rotation sampled at ``rate`` Hz, consistent by construction.

    Roll, pitch and yaw are sums of random sinusoids (|pitch| below ``pitch_limit`` rad, still
    for the first ``start_still`` s), scaled so the body rate peaks near ``max_rate`` rad/s. The
    body rate of sample k is the constant rate that turns ``q[k-1]`` into ``q[k]`` over one
    interval, ``q[k] = q[k-1] * exp(omega[k] dt)``, so a filter that integrates the gyro that
    way sees exact data. Noise values are standard deviations per sample (gyro_noise rad/s,
    acc_noise m/s^2, mag_noise uT); the field has intensity 50 uT and the given dip.
    """
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    t = np.arange(n) * dt
    freqs = rng.uniform(0.03, 0.3, size=(3, 4))
    phases = rng.uniform(0, 2 * np.pi, size=(3, 4))
    amps = rng.uniform(0.3, 1.0, size=(3, 4))
    ramp = np.clip((t - start_still) / 2.0, 0.0, 1.0)
    ramp = ramp * ramp * (3 - 2 * ramp)  # smooth start
    ang = np.einsum("ij,ijn->ni", amps, np.sin(2 * np.pi * freqs[..., None] * t + phases[..., None])
                    - np.sin(phases[..., None]))
    ang[:, 1] = pitch_limit * np.tanh(ang[:, 1])
    rpy = ang * ramp[:, None]

    def rates(scale):
        q = Q.from_euler(rpy * [scale, 1.0, scale])
        w = np.zeros((n, 3))
        w[1:] = Q.to_rotvec(Q.mul(Q.conj(q[:-1]), q[1:])) / dt
        return q, w

    q, omega = rates(1.0)
    peak = np.max(np.linalg.norm(omega, axis=1))
    if peak > 0:
        # Scale roll and yaw excursions (pitch is bounded) until the peak rate is max_rate.
        for _ in range(3):
            rpy[:, [0, 2]] *= max_rate / peak
            rpy[:, 1] *= min(1.0, max_rate / peak)
            q, omega = rates(1.0)
            peak = np.max(np.linalg.norm(omega, axis=1))
    dip = np.radians(dip_deg)
    mag_n = 50.0 * np.array([np.cos(dip), 0.0, np.sin(dip)])
    bias = np.asarray(gyro_bias, float)
    gyr = omega + bias + gyro_noise * rng.standard_normal((n, 3))
    acc = Q.rotate_inv(q, np.array([0.0, 0.0, -GRAVITY])) + acc_noise * rng.standard_normal((n, 3))
    mag = Q.rotate_inv(q, mag_n) + mag_noise * rng.standard_normal((n, 3))
    return RotationData(t, q, omega, gyr, acc, mag, bias, mag_n, dt)


def euler_errors_deg(q_est, q_true) -> np.ndarray:
    """(N, 3) roll, pitch, yaw errors in degrees, wrapped to (-180, 180]."""
    return np.degrees(Q.wrap_pi(Q.to_euler(q_est) - Q.to_euler(q_true)))


def run_demo(plot: str | None = None, seed: int = 0, quiet: bool = False) -> dict:
    from . import EulerEKF, MargFilter, QuaternionEKF

    d = rotation_scenario(seed=seed)
    results = {}
    filters = (("QuaternionEKF", QuaternionEKF, {}),
               ("QuaternionEKF paper", QuaternionEKF, {"paper": True}), ("EulerEKF", EulerEKF, {}),
               ("MargFilter", MargFilter, {}),
               ("MargFilter+bias", MargFilter, {"bias_gain": 0.05}))
    for name, cls, params in filters:
        f = cls(**params)
        t0 = time.perf_counter()
        r = f.run(d.gyr, d.acc, d.mag, dt=d.dt)
        elapsed = time.perf_counter() - t0
        err = euler_errors_deg(r.quat, d.q_nb)
        settle = d.t >= 5.0
        rmse = np.sqrt(np.mean(err[settle] ** 2, axis=0))
        bias_err = np.degrees(np.linalg.norm(r.bias[-1] - d.gyro_bias)) * 3600
        results[name] = dict(roll_rmse_deg=rmse[0], pitch_rmse_deg=rmse[1], yaw_rmse_deg=rmse[2],
                             bias_err_deg_h=bias_err, samples_per_s=len(d.t) / elapsed, result=r)
    if not quiet:
        print(f"quatnav demo: simulated rotation, {len(d.t)} samples at {1 / d.dt:.0f} Hz, "
              f"gyro bias {np.degrees(d.gyro_bias) * 3600} deg/h (RMSE after 5 s)")
        print(f"{'filter':<21}{'roll':>9}{'pitch':>9}{'yaw':>9}   {'|bias err|':>12}{'samples/s':>12}")
        print(f"{'':<21}{'[deg]':>9}{'[deg]':>9}{'[deg]':>9}   {'[deg/h]':>12}")
        for name, v in results.items():
            print(f"{name:<21}{v['roll_rmse_deg']:9.3f}{v['pitch_rmse_deg']:9.3f}{v['yaw_rmse_deg']:9.3f}   "
                  f"{v['bias_err_deg_h']:12.1f}{v['samples_per_s']:12.3g}")
    nav = _navigation_demo(seed, quiet)
    if nav:
        results["navigation"] = nav
    ins = _gpsins_demo(seed, quiet)
    if ins:
        results["gpsins"] = ins
    if plot:
        _plot(d, {k: v for k, v in results.items() if k != "navigation"}, plot)
        if not quiet:
            print(f"figure written to {plot}")
    return results


def _navigation_demo(seed: int, quiet: bool) -> dict:
    """NavFilter13 (paper 002) with its three time updates on the paper's simulated run."""
    try:
        from .experiments import nav13 as X
        from .sim import make_scenario
        scn = make_scenario(X.SCENARIO, seed=seed)
    except ImportError as exc:  # quatnav.sim needs scipy (extra [sim])
        if not quiet:
            print(f"(navigation demo skipped: {exc})")
        return {}
    start = X.initial_state(scn, "paper", np.random.default_rng(seed))
    out = {}
    for tu in X.TIME_UPDATES:
        t0 = time.perf_counter()
        res = X.run_filter(scn, tu, start)
        elapsed = time.perf_counter() - t0
        err = X.errors(scn, res)
        late = err["t"] >= err["t"][0] + 100.0
        rpy = np.degrees(np.sqrt(np.mean(err["rpy"][late] ** 2, axis=0)))
        vel = np.sqrt(np.mean(np.sum(err["state"][late, 0:3] ** 2, axis=1)))
        out[tu] = dict(roll_rmse_deg=rpy[0], pitch_rmse_deg=rpy[1], yaw_rmse_deg=rpy[2],
                       vel_rmse_m_s=vel, samples_per_s=len(res.t) / elapsed)
    if not quiet:
        print()
        print(f"NavFilter13 (paper 002): {X.SCENARIO}, seed {seed}, the paper's initial errors "
              f"(RMSE over 100-200 s)")
        print(f"{'time update':<21}{'roll':>9}{'pitch':>9}{'yaw':>9}   {'|v| err':>12}{'samples/s':>12}")
        print(f"{'':<21}{'[deg]':>9}{'[deg]':>9}{'[deg]':>9}   {'[m/s]':>12}")
        for name, v in out.items():
            print(f"{name:<21}{v['roll_rmse_deg']:9.3f}{v['pitch_rmse_deg']:9.3f}{v['yaw_rmse_deg']:9.3f}   "
                  f"{v['vel_rmse_m_s']:12.3f}{v['samples_per_s']:12.3g}")
    return out


def _gpsins_demo(seed: int, quiet: bool) -> dict:
    """GpsInsFilter (paper 004) on its three simulated scenarios, with a 10 s GPS outage."""
    try:
        from .experiments import gpsins as G
        out = {name: G.run_scenario(name, seed=seed) for name in ("static", "turntable", "walk")}
    except ImportError as exc:  # quatnav.sim needs scipy (extra [sim])
        if not quiet:
            print(f"(GPS/INS demo skipped: {exc})")
        return {}
    if not quiet:
        print()
        print(f"GpsInsFilter (paper 004): simulated runs, seed {seed}; a 10 s GPS outage mid-run")
        print(f"{'scenario':<21}{'horiz RMS':>10}{'max':>8}{'roll':>8}{'pitch':>8}{'yaw':>8}"
              f"{'outage drift':>14}{'1-sigma':>9}")
        print(f"{'':<21}{'[m]':>10}{'[m]':>8}{'[deg]':>8}{'[deg]':>8}{'[deg]':>8}{'[m]':>14}{'[m]':>9}")
        for name, r in out.items():
            e, o = r["euler_deg"], r["outage"]
            print(f"{name:<21}{r['horizontal_m']['rms']:10.2f}{r['horizontal_m']['max']:8.2f}"
                  f"{e['roll']['rms']:8.2f}{e['pitch']['rms']:8.2f}{e['yaw']['rms']:8.2f}"
                  f"{o['horizontal_error_at_end_m']:14.2f}{o['horizontal_sigma_at_end_m']:9.2f}")
    return out


def _plot(d: RotationData, results: dict, path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(4, 1, figsize=(9, 9), sharex=True)
    for i, lab in enumerate(("roll", "pitch", "yaw")):
        for name, v in results.items():
            axes[i].plot(d.t, euler_errors_deg(v["result"].quat, d.q_nb)[:, i], lw=0.8, label=name)
        axes[i].set_ylabel(f"{lab} error [deg]")
        axes[i].grid(alpha=0.3)
    for name, v in results.items():
        axes[3].plot(d.t, np.degrees(np.linalg.norm(v["result"].bias - d.gyro_bias, axis=1)) * 3600, lw=0.8,
                     label=name)
    axes[3].set_ylabel("|bias error| [deg/h]")
    axes[3].set_yscale("log")
    axes[3].set_xlabel("time [s]")
    axes[0].legend(loc="upper right")
    fig.suptitle("quatnav demo: attitude filters on a simulated rotation")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="run the filters on built-in simulated scenarios and print a table")
    p.add_argument("--plot", metavar="FILE.png", help="write a figure of the errors")
    p.add_argument("--seed", type=int, default=0)
    p.set_defaults(func=lambda a: run_demo(plot=a.plot, seed=a.seed) and 0)
