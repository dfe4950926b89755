"""GPS/INS (paper 004) on NaveGo's synthetic run: ``quatnav experiment navego [--data DIR]
--json FILE [--plot FILE.png] [--seconds S]``.

Third-party evidence: :class:`quatnav.GpsInsFilter` on NaveGo's ADIS16405 IMU (200 Hz) with its
5 Hz GNSS (position one-sigma 5/5/10 m, velocity and lever arm as given), against ``ref.mat``.

* Initial alignment: the vehicle accelerates at 4 m/s^2 from t = 0, so the filter's own static
  alignment (accelerometer levelling at rest) does not apply; the filter is started as NaveGo's
  own ``ins_gnss`` starts: attitude from the dataset's ``ini_align``, one-sigma
  ``ini_align_err``, position and velocity from the first GNSS fix.
* Noise from the ADIS16405 profile (already SI in the file): ``gyro_noise = arw``
  (rad/s/sqrt(Hz)), ``acc_noise = vrw`` (m/s^2/sqrt(Hz)); the biases are a constant turn-on
  part (``gb_sta``/``ab_sta``, used as initial one-sigma, as NaveGo does) plus a Gauss-Markov
  part (``gb_dyn``/``ab_dyn``, correlation ``gb_corr``/``ab_corr``); they are modelled as one
  random walk with the Gauss-Markov driving noise ``sigma sqrt(2 / tau)`` (a decaying
  Gauss-Markov state would pull the constant turn-on bias back to zero).

Reported: RMSE of N/E/D position (m), N/E/D velocity (m/s), roll/pitch/yaw (deg) over the whole
run, the same for the GNSS fixes alone (position and velocity), and the gate rejections.

Two more runs go through the pipeline of ``quatnav ins run`` (:func:`quatnav.pipeline.run_ins`
on the arrays as a :class:`quatnav.io.Log`) with the filter's own alignment, **without**
``ini_align``: ``cli_in_motion`` (GNSS position and velocity: the alignment in motion from the
GNSS velocity change against the specific force) and ``cli_position_only`` (the velocity left
out: the course between fixes). Their errors are scored from the output rows (from the start of
navigation) against ``ref.mat`` the same way, and the attitude's also from 60 s after the
start of navigation (once the alignment's errors have settled); a run that navigates less than
60 s (``--seconds``) has no such figure (``None``), and the report says why; a run too short to
align has no figures at all (``rows`` 0).
"""
from __future__ import annotations

import numpy as np

_A, _E2 = 6378137.0, 6.69437999014e-3  # WGS-84


#: One line for ``quatnav experiment -h``.
SUMMARY = "GpsInsFilter on NaveGo's synthetic ADIS16405 INS/GNSS run against its truth (paper 004; navego_synthetic data)"


def add_arguments(parser) -> None:
    parser.add_argument("--data", default=None, metavar="DIR",
                        help="navego_synthetic folder (default $QUATNAV_DATA/navego_synthetic)")
    parser.add_argument("--json", metavar="FILE", help="write the results here ('-': stdout)")
    parser.add_argument("--plot", default=None, metavar="FILE.png", help="plot the errors here")
    parser.add_argument("--seconds", type=float, default=None, help="run only the first S seconds")


def ned_error(llh, llh_ref) -> np.ndarray:
    """(N, 3) NED position error (m) of ``llh`` about ``llh_ref`` (rows [lat rad, lon rad, h m])."""
    llh, llh_ref = np.atleast_2d(llh), np.atleast_2d(llh_ref)
    lat, h = llh_ref[:, 0], llh_ref[:, 2]
    sl2 = np.sin(lat) ** 2
    rm = _A * (1 - _E2) / (1 - _E2 * sl2) ** 1.5
    rn = _A / np.sqrt(1 - _E2 * sl2)
    dlon = np.angle(np.exp(1j * (llh[:, 1] - llh_ref[:, 1])))
    return np.column_stack([(llh[:, 0] - lat) * (rm + h), dlon * (rn + h) * np.cos(lat), -(llh[:, 2] - h)])


def _rms(x):
    return np.sqrt(np.nanmean(np.asarray(x) ** 2, axis=0))


def filter_params(d) -> dict:
    """GpsInsFilter parameters from the dataset's ADIS16405 profile and GNSS settings."""
    from ..datasets.navego import gm_driving_noise
    p = d.imu_profile
    return dict(
        gyro_noise=float(np.mean(p["arw"])), acc_noise=float(np.mean(p["vrw"])),
        gyro_bias_noise=gm_driving_noise(np.mean(p["gb_dyn"]), np.mean(p["gb_corr"])),
        acc_bias_noise=gm_driving_noise(np.mean(p["ab_dyn"]), np.mean(p["ab_corr"])),
        gyro_bias_tau=0.0, acc_bias_tau=0.0,
        init_gyro_bias_sigma=float(np.mean(p["gb_sta"])), init_acc_bias_sigma=float(np.mean(p["ab_sta"])),
        init_level_sigma=float(max(d.ini_align_err[0], d.ini_align_err[1])),
        init_yaw_sigma=float(d.ini_align_err[2]),
        gps_pos_sigma_h=float(d.gnss_pos_sigma[0]), gps_pos_sigma_v=float(d.gnss_pos_sigma[2]),
        gps_vel_sigma=float(np.mean(d.gnss_vel_sigma)), lever_arm_b=tuple(float(x) for x in d.lever_arm_b))


def run_navego(directory=None, seconds=None, params=None, smooth=False):
    """Run the filter on the NaveGo data; returns (summary dict, arrays dict). ``params``
    overrides entries of :func:`filter_params` (parameter tuning). ``smooth``: also the
    Rauch-Tung-Striebel smoothed run's RMSE (``summary["ins_gnss_smoothed"]``)."""
    import quatnav
    from ..core import quaternion as Q
    from ..datasets import navego

    d = navego.load(directory)
    n = len(d.imu_t) if seconds is None else int(np.searchsorted(d.imu_t, d.imu_t[0] + seconds, "right"))
    t, gyro, accel = d.imu_t[:n], d.gyro[:n], d.accel[:n]
    gm = d.gnss_t <= t[-1]
    params = dict(filter_params(d), **(params or {}))
    f = quatnav.GpsInsFilter(**params)
    sig = np.array([d.gnss_pos_sigma[0], d.gnss_pos_sigma[1], d.gnss_pos_sigma[2]] + [params["gps_vel_sigma"]] * 3
                   + [params["init_level_sigma"]] * 2 + [params["init_yaw_sigma"]]
                   + [params["init_acc_bias_sigma"]] * 3 + [params["init_gyro_bias_sigma"]] * 3 + [0.0])
    # Start at the first fix (t = 0), as NaveGo does: attitude from ini_align, the IMU position
    # from the antenna fix less the lever arm (zero here).
    q0 = Q.from_euler(d.ini_align)
    llh0 = d.gnss_llh[0].copy()
    l_n = Q.rotate(q0, d.lever_arm_b) if np.any(d.lever_arm_b) else np.zeros(3)
    llh0 = llh0 + ned_to_dllh(-l_n, llh0)
    f.reset(q0, d.gnss_vel[0], llh0, P=np.diag(sig ** 2))
    r = f.run(gyro, accel, t=t, gps_pos=quatnav.Aid(d.gnss_t[gm], d.gnss_llh[gm]),
              gps_vel=quatnav.Aid(d.gnss_t[gm], d.gnss_vel[gm]), smooth=smooth)
    i = np.searchsorted(d.ref_t, t)
    names = ("n", "e", "d")

    def errors(r):
        return (ned_error(r.position, d.ref_llh[i]), r.velocity - d.ref_vel[i],
                np.degrees(np.angle(np.exp(1j * (r.euler - d.ref_rpy[i])))))

    def rmse(dp, dv, de):
        return {"position_rmse_m": dict(zip(names, map(float, _rms(dp)))),
                "horizontal_rmse_m": float(_rms(np.hypot(dp[:, 0], dp[:, 1]))),
                "velocity_rmse_mps": dict(zip(names, map(float, _rms(dv)))),
                "attitude_rmse_deg": dict(zip(("roll", "pitch", "yaw"), map(float, _rms(de))))}

    smoothed = None
    if smooth:
        smoothed = rmse(*errors(r))
        r = r.forward
    dp, dv, de = errors(r)
    j = np.searchsorted(d.ref_t, d.gnss_t[gm] - 1e-9)
    gdp = ned_error(d.gnss_llh[gm], d.ref_llh[j])
    gdv = d.gnss_vel[gm] - d.ref_vel[j]
    # The gyro bias in the data: measured rate minus the reference rate from successive
    # reference DCMs (C_k^T C_k+1 = I + [w dt x]; Earth rate, 0.004 deg/s, left in).
    Cr = d.ref_C_nb[i]
    Rk = np.einsum("nji,njk->nik", Cr[:-1], Cr[1:])
    w_ref = np.column_stack([Rk[:, 2, 1] - Rk[:, 1, 2], Rk[:, 0, 2] - Rk[:, 2, 0],
                             Rk[:, 1, 0] - Rk[:, 0, 1]]) / (2 * np.diff(t))[:, None]
    bg_true = np.mean(gyro[1:] - w_ref, axis=0)
    out = {
        "dataset": "NaveGo synthetic (ADIS16405 IMU 200 Hz, GNSS 5 Hz)", "duration_s": float(t[-1] - t[0]),
        "alignment": "dataset ini_align (NaveGo's own start); position and velocity from the first fix",
        "params": {k: (list(v) if isinstance(v, tuple) else v) for k, v in params.items()},
        "ins_gnss": {
            **rmse(dp, dv, de),
            "position_max_m": dict(zip(names, map(float, np.max(np.abs(dp), axis=0)))),
            "attitude_max_deg": dict(zip(("roll", "pitch", "yaw"), map(float, np.max(np.abs(de), axis=0)))),
        },
        "gnss_only": {
            "position_rmse_m": dict(zip(names, map(float, _rms(gdp)))),
            "horizontal_rmse_m": float(_rms(np.hypot(gdp[:, 0], gdp[:, 1]))),
            "velocity_rmse_mps": dict(zip(names, map(float, _rms(gdv)))),
        },
        "within_3sigma_fraction": {
            k: float(np.mean(np.abs(e) <= 3 * r.sigma[:, c]))
            for k, e, c in (("pos_n", dp[:, 0], 0), ("pos_e", dp[:, 1], 1), ("pos_d", dp[:, 2], 2),
                            ("vel_n", dv[:, 0], 3), ("vel_e", dv[:, 1], 4), ("vel_d", dv[:, 2], 5))},
        "final_bias": {"gyro_dps": list(map(float, np.degrees(r.bias[-1]))),
                       "gyro_in_data_dps": list(map(float, np.degrees(bg_true))),
                       "accel_mps2": list(map(float, r.acc_bias[-1]))},
        "rejections": {k: int(v) for k, v in r.rejections.items()},
        "gate_lockout_resets": {k: int(r.counters[k].get("resets", 0)) for k in ("gps_pos", "gps_vel")},
        "accepted": {k: int(v["accepted"]) for k, v in r.counters.items()},
    }
    if smoothed is not None:
        out["ins_gnss_smoothed"] = smoothed
    arrays = dict(t=t, dp=dp, dv=dv, deul=de, sigma=r.sigma, gnss_t=d.gnss_t[gm], gnss_dp=gdp)
    return out, arrays


def cli_params(d) -> dict:
    """The run's parameters for the ``ins run`` pipeline: the sensor profile (:func:`filter_params`), the
    alignment's own initial sigmas (the defaults), not ``ini_align_err``."""
    p = filter_params(d)
    for k in ("init_level_sigma", "init_yaw_sigma"):
        p.pop(k)
    return p


def run_pipeline(d, velocity=True, seconds=None):
    """NaveGo through the pipeline of ``quatnav ins run`` (:func:`quatnav.pipeline.run_ins`) with
    the filter's own alignment (no ``ini_align``). Returns (summary dict, arrays)."""
    from .. import io
    from ..pipeline import run_ins
    n = len(d.imu_t) if seconds is None else int(np.searchsorted(d.imu_t, d.imu_t[0] + seconds, "right"))
    gm = d.gnss_t <= d.imu_t[n - 1]
    gnss = io.Gnss(t=d.gnss_t[gm], lat=d.gnss_llh[gm, 0], lon=d.gnss_llh[gm, 1], h=d.gnss_llh[gm, 2],
                   vel_n=d.gnss_vel[gm] if velocity else None)
    log = io.Log(source="NaveGo synthetic", imu=io.Imu(t=d.imu_t[:n], gyr=d.gyro[:n], acc=d.accel[:n]), gnss=gnss)
    run = run_ins(log, params=cli_params(d))
    if not run.navigated:  # a run too short to align (--seconds): nothing to score
        s = run.summary()
        return {"message": run.summary_line(), "alignment": s["alignment"], "navigation_start_s": None, "rows": 0,
                "decisions": s["decisions"]}, None
    nav, r = run.rows, run.result
    t = r.t[nav]
    i = np.searchsorted(d.ref_t, t - 1e-9)
    dp = ned_error(r.position[nav], d.ref_llh[i])
    dv = r.velocity[nav] - d.ref_vel[i]
    de = np.degrees(np.angle(np.exp(1j * (r.euler[nav] - d.ref_rpy[i]))))
    names = ("n", "e", "d")
    late = t >= t[0] + 60.0  # none in a run shorter than that: no figure rather than NaN
    out = {"message": run.summary_line(), "alignment": r.alignment, "navigation_start_s": float(t[0] - d.imu_t[0]),
           "rows": int(len(t)), "navigation_s": float(t[-1] - t[0]),
           "position_rmse_m": dict(zip(names, map(float, _rms(dp)))),
           "horizontal_rmse_m": float(_rms(np.hypot(dp[:, 0], dp[:, 1]))),
           "velocity_rmse_mps": dict(zip(names, map(float, _rms(dv)))),
           "attitude_rmse_deg": dict(zip(("roll", "pitch", "yaw"), map(float, _rms(de)))),
           "attitude_max_deg": dict(zip(("roll", "pitch", "yaw"), map(float, np.max(np.abs(de), axis=0)))),
           "attitude_rmse_after_60s_deg": dict(zip(("roll", "pitch", "yaw"), map(float, _rms(de[late]))))
           if late.any() else None,
           "attitude_at_start_deg": dict(zip(("roll", "pitch", "yaw"), map(float, de[0]))),
           "decisions": {k: a.decisions() for k, a in r.aids.items()}}
    return out, dict(t=t, dp=dp, dv=dv, deul=de)


def ned_to_dllh(d_n, llh) -> np.ndarray:
    """[dlat, dlon, dh] of a small NED displacement d_n (m) at ``llh``."""
    lat, h = llh[0], llh[2]
    rm = _A * (1 - _E2) / (1 - _E2 * np.sin(lat) ** 2) ** 1.5
    rn = _A / np.sqrt(1 - _E2 * np.sin(lat) ** 2)
    return np.array([d_n[0] / (rm + h), d_n[1] / ((rn + h) * np.cos(lat)), -d_n[2]])


def plot(arrays, path):
    """Errors against ``ref.mat``: horizontal and vertical position (log axes, beside the GNSS
    fixes' own errors), NED velocity and roll/pitch/yaw with the filter's sigmas. The attitude
    axis holds the steady part (from when every attitude three-sigma has come within twice its
    median over the run); the initial alignment's larger errors leave it."""
    from matplotlib.lines import Line2D

    from .._plotting import figure, legend_right, robust_limits, save
    t = arrays["t"]
    sig = arrays["sigma"]
    fig = figure((11.0, 11.0))
    ax = [fig.add_subplot(4, 1, 1)]
    ax += [fig.add_subplot(4, 1, k, sharex=ax[0]) for k in (2, 3, 4)]
    gt, gdp = arrays["gnss_t"], arrays["gnss_dp"]
    dp = arrays["dp"]
    for a, e_ins, e_gnss, s1, what in (
            (ax[0], np.hypot(dp[:, 0], dp[:, 1]), np.hypot(gdp[:, 0], gdp[:, 1]), np.hypot(sig[:, 0], sig[:, 1]),
             "horizontal"),
            (ax[1], np.abs(dp[:, 2]), np.abs(gdp[:, 2]), sig[:, 2], "vertical")):
        a.plot(gt, e_gnss, ".", ms=1.5, color="0.6", alpha=0.5)
        a.plot(t, e_ins, color="C0", lw=0.9)
        a.plot(t, s1, color="C0", lw=0.8, ls="--")
        a.set_yscale("log")
        # Down to a fifth of the smallest one-sigma: the vertical error's zero crossings, which a
        # log axis would draw as spikes to nothing, leave the axis.
        a.set_ylim(bottom=max(1e-3, 0.2 * np.nanmin(s1)))
        a.set_ylabel(f"|{what} position\nerror| [m]")
    h = [Line2D([], [], color="0.6", ls="", marker=".", label="GNSS fixes (5 Hz)"),
         Line2D([], [], color="C0", lw=1.5, label="INS/GNSS"),
         Line2D([], [], color="C0", lw=0.8, ls="--", label="filter's 1-sigma")]
    legend_right(ax[0], h, [x.get_label() for x in h])
    for k, c in enumerate("NED"):
        ax[2].plot(t, arrays["dv"][:, k], lw=0.7, label=c)
    ax[2].axhline(0.0, color="k", lw=0.5)
    lim = robust_limits(arrays["dv"][t >= t[0] + 5.0], 0.05, 99.95)
    if lim:
        ax[2].set_ylim(*lim)
    ax[2].set_ylabel("velocity error [m/s]")
    legend_right(ax[2])
    colors = ("#1b9e77", "#d95f02", "#7570b3")
    s3 = 3 * np.degrees(sig[:, 6:9])
    steady = np.all(s3 <= 2 * np.median(s3, axis=0), axis=1)
    t_steady = t[np.argmax(steady)] if steady.any() else t[0]
    late = t >= t_steady
    for k, c in enumerate(("roll", "pitch", "yaw")):
        ax[3].plot(t, arrays["deul"][:, k], lw=0.8, color=colors[k], label=c)
        ax[3].plot(t, s3[:, k], "--", lw=0.6, color=colors[k])
        ax[3].plot(t, -s3[:, k], "--", lw=0.6, color=colors[k])
    ax[3].plot([], [], "--", lw=0.6, color="0.3", label="filter's 3-sigma")
    ax[3].axhline(0.0, color="k", lw=0.5)
    m = max(np.max(np.abs(arrays["deul"][late])), np.max(s3[late]))
    ax[3].set_ylim(-1.2 * m, 1.2 * m)
    ax[3].set_ylabel("attitude error [deg]")
    ax[3].set_title(f"attitude: the axis holds t >= {t_steady - t[0]:.0f} s; the initial alignment's larger "
                    "errors leave it", fontsize=8, loc="left")
    legend_right(ax[3])
    ax[3].set_xlabel("time [s]")
    for a in ax:
        a.grid(True, which="major", alpha=0.3)
        a.set_xlim(t[0], t[-1])
    for a in ax[:3]:
        a.tick_params(labelbottom=False)
    fig.suptitle("quatnav GpsInsFilter on NaveGo's synthetic run (ADIS16405 200 Hz, GNSS 5 Hz)", fontsize=11)
    save(fig, path)
    return fig


def run(args) -> int:
    from .._command import UsageError, write_json
    if args.seconds is not None and not args.seconds > 0:
        raise UsageError(f"--seconds: expected a positive number, got {args.seconds:g}")
    try:
        from ..datasets import navego
        out, arrays = run_navego(args.data, args.seconds, smooth=True)
        d = navego.load(args.data)
        out["cli_in_motion"], _ = run_pipeline(d, True, args.seconds)
        out["cli_position_only"], _ = run_pipeline(d, False, args.seconds)
    except FileNotFoundError as exc:
        raise UsageError(f"{exc} (use --data DIR or set QUATNAV_DATA to the folder that holds navego_synthetic/)") \
            from None
    write_json(out, args)
    if args.plot:
        plot(arrays, args.plot)
    a, g = out["ins_gnss"], out["gnss_only"]
    fmt = lambda d, p: ", ".join(f"{k} {v:.{p}f}" for k, v in d.items())  # noqa: E731
    print(f"NaveGo synthetic, {out['duration_s']:.1f} s")
    print(f"INS/GNSS RMSE: position (m) {fmt(a['position_rmse_m'], 2)}; velocity (m/s) "
          f"{fmt(a['velocity_rmse_mps'], 3)}; attitude (deg) {fmt(a['attitude_rmse_deg'], 2)}")
    if "ins_gnss_smoothed" in out:
        z = out["ins_gnss_smoothed"]
        print(f"INS/GNSS smoothed RMSE: position (m) {fmt(z['position_rmse_m'], 2)}; velocity (m/s) "
              f"{fmt(z['velocity_rmse_mps'], 3)}; attitude (deg) {fmt(z['attitude_rmse_deg'], 2)}")
    print(f"GNSS-only RMSE: position (m) {fmt(g['position_rmse_m'], 2)}; velocity (m/s) "
          f"{fmt(g['velocity_rmse_mps'], 3)}")
    print(f"gate rejections: {out['rejections']}")
    for name in ("cli_in_motion", "cli_position_only"):
        c = out[name]
        if not c["rows"]:
            print(f"{name} (ins run, no ini_align): navigation never started in the {out['duration_s']:.3g} s "
                  "run (the alignment needs more)")
            continue
        late = c["attitude_rmse_after_60s_deg"]
        late = (f"after 60 s {fmt(late, 2)}" if late is not None else
                f"none after 60 s (it navigated {c['navigation_s']:.1f} s)")
        print(f"{name} (ins run, no ini_align; alignment {c['alignment']['method']}, navigating from "
              f"{c['navigation_start_s']:.1f} s): horizontal RMSE {c['horizontal_rmse_m']:.2f} m; attitude (deg) "
              f"{fmt(c['attitude_rmse_deg'], 2)}; {late}")
    return 0
