"""A GNSS/INS run on a user's log, as ``quatnav ins run`` makes it: read the inputs, check them,
coast the IMU's gaps, align, run :class:`quatnav.GpsInsFilter` (and smooth), and return the
result with its alignment, warnings and per-aid diagnostics (:class:`InsRun`)."""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._command import InputError
from ..core.earth import radii
from ..plausibility import (check_heading_aids, check_imu_times, check_overlap, checked_by_caller,
                            plausibility_warnings)
from ..plausibility.gnss import gnss_speed, gnss_velocity_ne
from .coasting import coast_gaps
from .config import load_config
from .inputs import InsInputs, mag_at_imu_rows, read_ins_inputs
from .outputs import diagnostics_table, ins_table
from .recording import PipelineWarning, issue, recorded

__all__ = ["InsRun", "run_ins"]


@dataclass(repr=False, eq=False)
class InsRun:
    """What :func:`run_ins` returns.

    Attributes
    ----------
    result : quatnav.GpsInsResult
        The filter's (with ``smooth``: the smoothed) result over the IMU record, coasting steps
        inserted into its gaps included.
    rows : (N,) bool ndarray
        The samples of ``result`` that are output rows: navigating, and samples of the input (not
        coasting steps).
    inputs : InsInputs
        What was read.
    params : dict
        The filter's parameters as run (the declination and ``gps_time_offset`` the run chose
        included).
    warnings : list of Warning
        Every warning of the run, each once, as objects of quatnav's categories
        (:class:`quatnav.PlausibilityWarning` and its kinds, :class:`quatnav.AidWarning`,
        :class:`PipelineWarning`); they were also issued with :func:`warnings.warn`.
    notes : list of str
        What the run did that is no warning: the declination's source, the magnetometer
        calibration it fitted.
    gaps : list of (int, float)
        The IMU gaps longer than ``max_dt`` that were coasted: (row, seconds).
    overlap : bool
        Whether the GNSS times overlap the IMU's.
    mag_calibration : MagAttitudeFit or None
        With ``mag_calibrate``: the fit; ``mag_offset`` its offset in the magnetometer's axes.
    time_offset : TimeOffsetEstimate or None
        With ``time_offset``: the estimate of ``gps_time_offset`` the run used.
    utc_offset : float or None
        UTC minus the IMU's clock, s, from the GNSS fixes' UTC times (a log's, a CSV's ``utc``
        column read with ``utc=True``); None where they give none.
    """

    result: object
    rows: np.ndarray
    inputs: InsInputs
    params: dict
    warnings: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    gaps: list = field(default_factory=list)
    overlap: bool = True
    mag_calibration: object = None
    mag_offset: np.ndarray | None = None
    time_offset: object = None
    utc_offset: float | None = None

    @property
    def navigated(self) -> bool:
        """Whether navigation started (there are output rows)."""
        return bool(self.rows.any())

    @property
    def alignment(self) -> dict:
        """How the filter aligned: ``method``, ``heading`` (its source), ``level_t``,
        ``navigation_t`` and, when it never navigated, the ``reason``."""
        return self.result.alignment

    @property
    def nhc_start(self) -> float | None:
        """The time of the first accepted non-holonomic update (forced by ``nhc``, or learned:
        ``nhc_auto``), s; None where there was none."""
        a = self.result.aids.get("nhc")
        ok = np.flatnonzero(a.accepted) if a is not None else []
        return float(a.t[ok[0]]) if len(ok) else None

    @property
    def gnss_rate(self) -> float | None:
        """The GNSS's rate, Hz (the median interval of its fixes); None with fewer than two."""
        t = np.asarray(self.inputs.gnss["time"], float)
        return float(1.0 / np.median(np.diff(t))) if len(t) > 1 and np.median(np.diff(t)) > 0 else None

    def utc(self, t) -> np.ndarray | None:
        """UTC (s since 1970) of IMU times ``t``, from :attr:`utc_offset`; None without it."""
        return None if self.utc_offset is None else np.asarray(t, float) + self.utc_offset

    @property
    def smoother_restarts(self) -> list:
        """Where the smoothed solution restarts (``smooth=True``): the samples where the forward
        pass inflated the covariance before a fix or reset the state to it; the backward pass
        does not cross them, so the smoothed estimate may jump there. One dict each: ``t`` (s),
        ``aid``, ``decision`` (inflated, reset), and the jump of the smoothed solution from the
        sample before: ``position_m`` (horizontal), ``gyro_bias_deg_h`` (norm)."""
        r = self.result
        if not r.smoothed or not len(r.t):
            return []
        out = []
        for name, a in r.aids.items():
            d = getattr(a, "decision_names", None)
            if d is None:
                continue
            for i in np.flatnonzero(np.isin(d, ("inflated", "reset"))):
                k = int(np.clip(np.searchsorted(r.t, a.t[i], side="left"), 1, len(r.t) - 1))
                r_m, r_n = radii(r.lat[k])
                dn = (r.lat[k] - r.lat[k - 1]) * (r_m + r.h[k])
                de = (r.lon[k] - r.lon[k - 1]) * (r_n + r.h[k]) * np.cos(r.lat[k])
                db = np.degrees(np.linalg.norm(r.bias[k] - r.bias[k - 1])) * 3600.0
                out.append({"t": float(a.t[i]), "aid": name, "decision": str(d[i]),
                            "position_m": float(np.hypot(dn, de)), "gyro_bias_deg_h": float(db)})
        return sorted(out, key=lambda x: x["t"])

    def table(self) -> tuple:
        """The output table: ``(names, columns, formats)`` (:func:`quatnav.pipeline.ins_table`)."""
        return ins_table(self)

    def diagnostics(self) -> list:
        """One row per aiding sample: aid, time, innovation, NIS, status, decision, inflation,
        process-noise scale (:data:`quatnav.pipeline.DIAGNOSTICS_COLUMNS`)."""
        return diagnostics_table(self.result)

    def summary_line(self) -> str:
        """The run in one line: rows, the start of navigation (or why it never started), gaps,
        gated-out samples, the alignment, the non-holonomic constraint."""
        r, nav = self.result, self.rows
        n = len(self.inputs.t)
        if nav.any():
            msg = f"{int(nav.sum())} rows ({n} IMU samples, navigation from t = {r.t[nav][0]:.3f} s)"
        elif not self.overlap:
            msg = "0 rows (navigation never started: the GNSS and IMU times do not overlap)"
        else:
            a = r.alignment
            fix = ("; give --mag or --compass (or a log with a magnetometer), move faster than min_speed_for_heading, "
                   "or the attitude as [initial] euler in --config" if a["method"] != "none" and a["heading"] == "none"
                   else "")
            msg = f"0 rows (navigation never started: {a['reason']}{fix})"
        if self.gaps:
            msg += f"; {len(self.gaps)} IMU gap{'s' if len(self.gaps) > 1 else ''} coasted"
        rej = {k: v for k, v in r.rejections.items() if v}
        if rej:
            msg += "; gated out: " + ", ".join(f"{k} {v}" for k, v in rej.items())
        if nav.any():
            msg += f"; alignment {r.alignment['method']}, heading from {r.alignment['heading']}"
        nhc_t = self.nhc_start
        if nhc_t is not None:
            msg += f"; non-holonomic constraint from t = {nhc_t:.1f} s"
        if r.smoothed and nav.any():
            msg += "; smoothed"
            restarts = self.smoother_restarts
            if restarts:
                shown = ", ".join(f"{x['aid']} {x['decision']} at t = {x['t']:.1f} s" for x in restarts[:3])
                more = f" and {len(restarts) - 3} more" if len(restarts) > 3 else ""
                msg += (f", restarted at {len(restarts)} covariance inflation{'s' if len(restarts) > 1 else ''} or "
                        f"reset{'s' if len(restarts) > 1 else ''} ({shown}{more}): the smoothed solution may jump there "
                        f"(up to {max(x['position_m'] for x in restarts):.3g} m, "
                        f"{max(x['gyro_bias_deg_h'] for x in restarts):.4g} deg/h of gyro bias)")
        return msg

    def summary(self) -> dict:
        """The run as a dict of plain values (``quatnav ins run --json``): rows, navigation start,
        coasted gaps, gated-out counts, counters, alignment, decisions per aid, warnings (text),
        notes, the declination, and the magnetometer calibration and time-offset estimate where
        made."""
        r, nav = self.result, self.rows
        lines = self.inputs.imu_lines
        out = {"rows": int(nav.sum()), "imu_samples": int(len(self.inputs.t)),
               "navigation_start_s": float(r.t[nav][0]) if nav.any() else None,
               "coasted_gaps": [{"lines": [int(lines[k - 1]), int(lines[k])], "seconds": step}
                                for k, step in self.gaps],
               "gated_out": {k: v for k, v in r.rejections.items() if v}, "counters": r.counters,
               "alignment": r.alignment, "decisions": {k: a.decisions() for k, a in r.aids.items()},
               "warnings": [str(w) for w in self.warnings], "smoothed": r.smoothed, "nhc_start_s": self.nhc_start,
               "declination_rad": float(self.params["declination"])}
        if r.smoothed:
            out["smoother_restarts"] = self.smoother_restarts
        if self.utc_offset is not None:
            out["utc_minus_imu_clock_s"] = self.utc_offset
        fit = self.mag_calibration
        if fit is not None:
            out["mag_calibration"] = {
                "offset_imu_axes": self.mag_offset.tolist(), "offset_sigma_body": fit.offset_sigma.tolist(),
                "field_n": fit.field_n.tolist(), "declination_rad": fit.declination,
                "inclination_rad": fit.inclination, "residual_rms": fit.residual_rms, "samples": fit.samples}
        for text in self.notes:
            out.setdefault("notes", []).append(text)
            if text.startswith("declination"):
                out["declination_note"] = text
        e = self.time_offset
        if e is not None:
            out["gps_time_offset_estimate"] = {
                "offset_s": e.offset, "sigma_s": e.sigma if np.isfinite(e.sigma) else None,
                "at_bound": e.at_bound, "bounds_s": list(e.bounds), "runs": e.runs}
        return out

    def __repr__(self) -> str:
        n = int(self.rows.sum())
        what = (f"{n} rows from t = {self.result.t[self.rows][0]:.3f} s" if n else
                f"never navigated ({self.alignment['reason']})")
        return f"<InsRun of {self.inputs.imu_source!r}: {what}; {len(self.warnings)} warnings>"


def run_ins(log=None, *, imu=None, gnss=None, baro=None, compass=None, mag=None, odometer=None, no_mag: bool = False,
            fmt: str = "auto", config=None, params: dict | None = None, initial: dict | None = None,
            declination=None, date: float | None = None, calibration=None, mag_calibrate: bool = False,
            time_offset=None, executor=None, smooth: bool = False, progress=None, utc: bool = False,
            noise_from_log: bool = True) -> InsRun:
    """Run :class:`quatnav.GpsInsFilter` on a log as ``quatnav ins run`` does.

    Parameters
    ----------
    log : quatnav.io.Log, optional
        The log (:func:`quatnav.io.read`, or made of arrays: ``io.Log(imu=io.Imu(t, gyr, acc),
        gnss=io.Gnss(t, lat, lon, h, vel_n=...))``); files given below replace its streams.
    imu, gnss, baro, compass, mag, odometer : str or Path, optional
        Input files (:func:`read_ins_inputs`); ``no_mag`` leaves the log's magnetometer out;
        ``fmt`` is their format (``"auto"``: detected).
    config : str or Path, optional
        A TOML file with ``[filter]`` (parameters) and ``[initial]`` (:func:`load_config`).
    params : dict, optional
        Parameters of :class:`quatnav.GpsInsFilter`, over the config's.
    initial : dict, optional
        A given initial state instead of the alignment (over the config's ``[initial]``):
        ``euler`` (rad) or ``q_nb``, ``v_n``, ``acc_bias``, ``gyro_bias``.
    declination : float or "auto", optional
        Magnetic declination, rad east (replaces the configured one), or ``"auto"``: the World
        Magnetic Model at the first GNSS fix on the date ``date`` (a decimal year), else the
        GNSS's UTC date, else today's (:func:`quatnav.core.magnetic.first_fix_declination`).
    calibration : str, Path or quatnav.calibration.Calibration, optional
        A sensor calibration applied to the gyro and accelerometer samples first.
    mag_calibrate : bool
        Run once without the magnetometer, fit its offset and the Earth field to that run's
        attitude (:func:`quatnav.calibration.mag_attitude_fit`), then run with the corrected
        samples and the fitted declination.
    time_offset : (float, float), optional
        Estimate ``gps_time_offset`` within these bounds, s, first
        (:func:`quatnav.calibration.gps_time_offset`, its runs through ``executor``; default:
        a thread per core) and run with it.
    smooth : bool
        The Rauch-Tung-Striebel smoothed solution (``GpsInsFilter.run(smooth=True)``).
    noise_from_log : bool
        Raise ``gyro_noise`` and ``acc_noise`` to the white noise the log's IMU shows, vibration
        included (:func:`quatnav.calibration.noise.noise_in_motion`), where they are more than
        1.2x below it, and lower them to 3x it where they are more than 3x above it
        (:func:`quatnav.calibration.noise.lowered_noise`); the notes say what the log showed and
        what was changed. False: the values as given.
    utc : bool
        Also read a CSV GNSS file's ``utc`` column (UTC s since 1970; logs give it always), for
        :attr:`InsRun.utc_offset`.
    progress : callable, optional
        ``progress(done, total)``: called before the filter runs (``done = 0``) and after (``done``
        its steps), with ``total`` twice the steps (the other half: writing the rows).

    Returns
    -------
    InsRun
        The result, the output rows, the alignment, the warnings (also issued with
        :func:`warnings.warn`: filter them by category) and the diagnostics of every aid.

    Raises
    ------
    InputError
        A file or parameter that cannot be used (a ``ValueError``; the message names the file,
        line and column, or the parameter).
    """
    from ..filters.gpsins import NavigationWarning
    # The alignment says why it never navigated; the inputs are checked here, with their files' names.
    with recorded(ignore=(NavigationWarning,)) as kept, checked_by_caller():
        run = _run(log, imu, gnss, baro, compass, mag, odometer, no_mag, fmt, config, params, initial, declination,
                   date, calibration, mag_calibrate, time_offset, executor, smooth, progress, utc, noise_from_log)
    run.warnings = kept
    issue(kept)
    return run


def _run(log, imu, gnss, baro, compass, mag, odometer, no_mag, fmt, config, params, initial, declination, date,
         calibration, mag_calibrate, time_offset, executor, smooth, progress, utc, noise_from_log) -> InsRun:
    import quatnav

    given = dict(initial or {})
    initial = {}
    params = dict(load_config(config, initial) if config else {}, **(params or {}))
    initial.update(given)
    where = f"config {config}" if config else "params"
    notes = []

    def make_filter():
        try:
            f = quatnav.GpsInsFilter(**params)
            if initial:
                f.set_initial(initial.get("q_nb"), euler=initial.get("euler"), v_n=initial.get("v_n"),
                              acc_bias=initial.get("acc_bias", (0.0, 0.0, 0.0)),
                              gyro_bias=initial.get("gyro_bias", (0.0, 0.0, 0.0)))
        except (TypeError, ValueError) as e:
            raise InputError(f"{where}: {e}") from None
        return f

    auto = isinstance(declination, str)
    if auto and declination != "auto":
        raise InputError(f"declination: expected rad east or 'auto', got {declination!r}")
    if date is not None and not auto:
        raise InputError("date: the date of the World Magnetic Model goes with declination='auto'")
    if declination is not None and not auto:
        params["declination"] = float(declination)
    f = make_filter()
    max_dt, align_time = float(f.params["max_dt"]), float(f.params["align_time"])
    inp = read_ins_inputs(log, imu=imu, gnss=gnss, baro=baro, compass=compass, mag=mag, odometer=odometer,
                          no_mag=no_mag, fmt=fmt, utc=auto or utc)
    d_g = inp.gnss
    if auto:  # the World Magnetic Model at the first fix
        from ..core.magnetic import first_fix_declination
        params["declination"], texts = first_fix_declination(
            np.radians(d_g["lat"]), np.radians(d_g["lon"]), d_g["h"], f"GNSS {inp.gnss_source}", utc=d_g.get("utc"),
            date=date, warn=lambda text: warnings.warn(text, PipelineWarning))
        f = make_filter()
        notes.extend(texts)
    kw = dict(gps_pos=quatnav.Aid(d_g["time"], np.column_stack([np.radians(d_g["lat"]), np.radians(d_g["lon"]), d_g["h"]]),
                                  np.column_stack([d_g[c] for c in ("sigma_n", "sigma_e", "sigma_d")])),
              gps_vel=quatnav.Aid(d_g["time"], np.column_stack([d_g[c] for c in ("v_n", "v_e", "v_d")]),
                                  np.column_stack([d_g[c] for c in ("sigma_vn", "sigma_ve", "sigma_vd")])))
    if "solution" in d_g:
        kw.update(gps_solution=d_g["solution"])
        notes.append("GNSS solution kinds from the receiver's quality codes (each kind's sigma floor): "
                     + solution_counts(d_g["solution"]))
    if inp.baro is not None:
        kw.update(baro=quatnav.Aid(inp.baro["time"], inp.baro["h"]))
    if inp.compass is not None:
        heading = np.radians(inp.compass["heading"])
        if inp.compass.get("north") == "true":  # a GNSS heading: the filter adds the declination to a magnetic one
            heading = heading - float(f.params["declination"])
        kw.update(compass=quatnav.Aid(inp.compass["time"], heading))
    if inp.odometer is not None:
        kw.update(odometer=quatnav.Aid(inp.odometer["time"], inp.odometer["speed"]))
    t, gyro, accel, increments = inp.t, inp.gyro, inp.accel, inp.increments
    if calibration:
        gyro, accel = _calibrated(calibration, gyro, accel)
    source = f"IMU {inp.imu_source}"
    gaps, wt = check_imu_times(t, inp.imu_lines, max_dt, where=source)
    for w in wt:
        warnings.warn(w)
    step = np.diff(t)[:, None] if increments else 1.0
    rot = np.asarray(f.params["imu_rotation"], float)
    rates = np.vstack([gyro[:1] * 0, gyro[1:] / step]) if increments else gyro
    forces = np.vstack([accel[:1] * 0, accel[1:] / step]) if increments else accel
    if not np.array_equal(rot, np.eye(3)):  # the checks look at the body axes
        rates, forces = rates @ rot.T, forces @ rot.T
    for w in plausibility_warnings(t, rates, forces, d_g["time"], d_g["lat"], d_g["lon"], align_time,
                                   imu=source, gnss=f"GNSS {inp.gnss_source}", gnss_speed=gnss_speed(d_g),
                                   gnss_vel=gnss_velocity_ne(d_g)):
        warnings.warn(w)
    overlap = check_overlap(t, d_g["time"]) is None
    if noise_from_log:
        from ..calibration.noise import lowered_noise, noise_in_motion, noise_note, raised_noise
        measured = noise_in_motion(t, rates, forces)
        if measured["blocks"]:
            raised, lowered = raised_noise(f.params, measured), lowered_noise(f.params, measured)
            notes.append(noise_note(f.params, measured, raised, lowered))
            if raised or lowered:
                params.update(raised, **lowered)
                f = make_filter()
    tt, gg, aa, original = coast_gaps(t, gyro, accel, gaps, max_dt, inp.imu_lines, where=source)
    if increments and not original.all():  # a coasted gap shares its increments between its steps
        row = np.cumsum(original) - original  # the input row each step belongs to (it ends the group)
        share = 1.0 / np.bincount(row)[row]
        gg, aa = gg * share[:, None], aa * share[:, None]
    if inp.mag is not None:
        kw["mag"] = mag_at_imu_rows(tt, inp.mag["time"], np.column_stack([inp.mag[f"mag_{c}"] for c in "xyz"]))
    imu_input = "increment" if increments else "rate"
    mag_fit = offset = None
    if mag_calibrate:
        if "mag" not in kw:
            raise InputError("--mag-calibrate needs a magnetometer (--mag MAG.csv, or a log with one)")
        mag_fit = _calibrate_mag(make_filter(), gg, aa, tt, imu_input, kw)
        if mag_fit is None:
            warnings.warn("--mag-calibrate: fewer than 100 magnetometer samples with a settled heading (yaw one-sigma "
                          "below 1 deg) in the run without it: the magnetometer is used as it is", PipelineWarning)
        else:
            offset = np.asarray(f.params["imu_rotation"], float).T @ mag_fit.offset  # in the IMU axes of the samples
            kw["mag"] = kw["mag"] - offset
            if declination is not None:
                warnings.warn(f"--mag-calibrate: the magnetometer's fitted declination "
                              f"({math.degrees(mag_fit.declination):+.2f} deg) replaces the one given", PipelineWarning)
            params["declination"] = mag_fit.declination
            f = make_filter()
            b = offset
            notes.append(f"magnetometer calibrated against the GNSS/INS attitude of a run without it: offset "
                         f"({b[0]:.4g}, {b[1]:.4g}, {b[2]:.4g}) in its axes, declination "
                         f"{math.degrees(mag_fit.declination):+.2f} deg, inclination "
                         f"{math.degrees(mag_fit.inclination):.2f} deg, residual {mag_fit.residual_rms:.3g} RMS "
                         f"({mag_fit.samples} samples)")
    estimate = None
    if time_offset is not None:
        f, estimate = _estimate_time_offset(f, params, gg, aa, tt, imu_input, kw, time_offset, executor)
    if progress is not None:
        progress(0, 2 * len(tt))
    r = f.run(gg, aa, t=tt, imu_input=imu_input, smooth=smooth, **kw)
    if progress is not None:
        progress(len(tt), 2 * len(tt))
    run = InsRun(result=r, rows=r.navigating & original, inputs=inp, params=f.params, notes=notes, gaps=gaps,
                 overlap=overlap, mag_calibration=mag_fit, mag_offset=offset, time_offset=estimate,
                 utc_offset=_utc_offset(d_g, float(f.params["gps_time_offset"])))
    for w in check_heading_aids(r):
        warnings.warn(w)
    return run


def solution_counts(codes) -> str:
    """``codes`` (GNSS_SOLUTIONS codes, one per fix) as "2,150 rtk_fixed, 40 rtk_float", most first."""
    from ..filters.gpsins import GNSS_SOLUTIONS
    n = np.bincount(np.asarray(codes, dtype=int), minlength=len(GNSS_SOLUTIONS))
    return ", ".join(f"{n[i]:,} {GNSS_SOLUTIONS[i]}" for i in np.argsort(-n, kind="stable") if n[i])


def _calibrated(calibration, gyro, accel):
    """The gyro and accelerometer samples through a calibration (a file: ``quatnav calibrate``)."""
    from .. import calibration as cal
    if not isinstance(calibration, cal.Calibration):
        try:
            calibration = cal.load_calibration(calibration)
        except (ValueError, FileNotFoundError) as e:
            raise InputError(str(e)) from None
    gyro, accel, _ = cal.apply(calibration, gyr=gyro, acc=accel)
    return gyro, accel


def _estimate_time_offset(f, params, gyro, accel, t, imu_input, kw, bounds, executor):
    """``gps_time_offset`` estimated within ``bounds`` (:func:`quatnav.calibration.gps_time_offset`)
    and a filter with it and ``f``'s state; returns ``(filter, estimate)``."""
    import contextlib
    import os
    from concurrent.futures import ThreadPoolExecutor

    import quatnav
    from ..calibration.time_offset import gps_time_offset
    # the runs release the GIL: without a given executor, threads keep every core busy
    pool = (contextlib.nullcontext(executor) if executor is not None
            else ThreadPoolExecutor(max_workers=os.cpu_count() or 1))
    with pool as ex:
        estimate = gps_time_offset(f, gyro, accel, t=t, imu_input=imu_input, bounds=bounds, executor=ex, **kw)
    if "gps_time_offset" in params:
        warnings.warn(f"the estimated gps_time_offset ({estimate.offset:+.4f} s) replaces the configured one "
                      f"({params['gps_time_offset']:+g} s)", PipelineWarning)
    state = f.get_state()
    f = quatnav.GpsInsFilter(**dict(params, gps_time_offset=estimate.offset))
    f.set_state(state)
    if estimate.at_bound:
        warnings.warn(f"the estimated gps_time_offset is at the end of the searched {bounds[0]:+g} .. "
                      f"{bounds[1]:+g} s: widen --estimate-time-offset LOW,HIGH", PipelineWarning)
    return f, estimate


def _calibrate_mag(f, gyro, accel, t, imu_input, kw):
    """Run ``f`` without the magnetometer and fit its offset and the Earth field to the attitudes
    whose yaw one-sigma is below 1 deg (:func:`quatnav.calibration.mag_attitude_fit`), or None."""
    from ..calibration.mag_attitude import mag_attitude_fit
    r0 = f.run(gyro, accel, t=t, imu_input=imu_input, **{k: v for k, v in kw.items() if k != "mag"})
    settled = np.isfinite(r0.sigma[:, 8]) & (r0.sigma[:, 8] < math.radians(1.0))
    q = np.where(settled[:, None], r0.quat, np.nan)
    rot = np.asarray(f.params["imu_rotation"], float)
    return mag_attitude_fit(q, kw["mag"] @ rot.T)


def _utc_offset(d_g, gps_time_offset):
    """UTC minus the IMU's clock, s: the median over the fixes with a UTC time of that time less
    the fix's time on the IMU's clock (its time plus ``gps_time_offset``); None without any."""
    u = np.asarray(d_g.get("utc", ()), float)
    if not u.size:
        return None
    d = u - (np.asarray(d_g["time"], float) + gps_time_offset)
    d = d[np.isfinite(d)]
    return float(np.median(d)) if d.size else None
