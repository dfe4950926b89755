"""``quatnav demo``: both filters of paper 000 on a built-in simulated rotation.

The scenario: smooth random rotation (up to ~2 rad/s) with a magnetometer, constant gyro bias,
white sensor noise; exact truth. Prints RMSE of roll, pitch and yaw and the final gyro-bias
error of :class:`~quatnav.QuaternionEKF` and :class:`~quatnav.EulerEKF`; ``--plot`` writes a
figure.
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
                      start_still: float = 1.0, pitch_limit: float | None = 1.2) -> RotationData:
    """A smooth random rotation sampled at ``rate`` Hz, consistent by construction.

    The body rate is a sum of random sinusoids (zero for the first ``start_still`` s); the true
    attitude is integrated exactly for a rate held over each sample interval, so
    ``q[k] = q[k-1] * exp(omega[k] dt)``. Noise values are standard deviations per sample
    (gyro_noise in rad/s, acc_noise in m/s^2, mag_noise in uT). With ``pitch_limit`` the pitch
    rate is steered so that |pitch| stays below that value (rad).
    """
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    t = np.arange(n) * dt
    freqs = rng.uniform(0.05, 0.6, size=(3, 4))
    phases = rng.uniform(0, 2 * np.pi, size=(3, 4))
    amps = rng.uniform(0.3, 1.0, size=(3, 4))
    omega = np.einsum("ij,ijn->ni", amps, np.sin(2 * np.pi * freqs[..., None] * t + phases[..., None]))
    omega *= max_rate / np.max(np.abs(omega))
    ramp = np.clip((t - start_still) / 1.0, 0.0, 1.0)
    omega *= ramp[:, None]
    q = np.empty((n, 4))
    q[0] = Q.identity()
    for k in range(1, n):
        qk = Q.mul(q[k - 1], Q.from_rotvec(omega[k] * dt))
        if pitch_limit is not None:
            pitch = Q.to_euler(qk)[1]
            if abs(pitch) > pitch_limit:
                # Reverse the body rate so the attitude turns back.
                omega[k:] *= -1.0
                qk = Q.mul(q[k - 1], Q.from_rotvec(omega[k] * dt))
        q[k] = qk / np.linalg.norm(qk)
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
    from . import EulerEKF, QuaternionEKF

    d = rotation_scenario(seed=seed)
    results = {}
    for name, cls in (("QuaternionEKF", QuaternionEKF), ("EulerEKF", EulerEKF)):
        f = cls()
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
        print(f"{'filter':<15}{'roll':>9}{'pitch':>9}{'yaw':>9}   {'|bias err|':>12}{'samples/s':>12}")
        print(f"{'':<15}{'[deg]':>9}{'[deg]':>9}{'[deg]':>9}   {'[deg/h]':>12}")
        for name, v in results.items():
            print(f"{name:<15}{v['roll_rmse_deg']:9.3f}{v['pitch_rmse_deg']:9.3f}{v['yaw_rmse_deg']:9.3f}   "
                  f"{v['bias_err_deg_h']:12.1f}{v['samples_per_s']:12.3g}")
    if plot:
        _plot(d, results, plot)
        if not quiet:
            print(f"figure written to {plot}")
    return results


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
    fig.suptitle("quatnav demo: paper 000 filters on a simulated rotation")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="run both attitude filters on a simulated rotation and print a table")
    p.add_argument("--plot", metavar="FILE.png", help="write a figure of the errors")
    p.add_argument("--seed", type=int, default=0)
    p.set_defaults(func=lambda a: run_demo(plot=a.plot, seed=a.seed) and 0)
