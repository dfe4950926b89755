"""The batch run of the numpy GpsInsFilter (``quatnav.reference.gpsins``), the twin of
``quatnav::gpsins_batch`` (``cpp/include/quatnav/nav/gps_ins/batch.hpp``): ``run`` with the public
signature, ``batch_loop`` over arrays.
"""
from __future__ import annotations

import math

import numpy as np

from ..filters.tables import FLAGS
from .attitude import sample_times
from .gpsins_model import ALIGNING, _result
from .gpsins_smoother import run_smoothed


def run(f, gyr, acc, mag=None, *, t=None, dt=None, gps_pos=None, gps_vel=None, baro=None, compass=None,
        odometer=None, outages=(), imu_input="rate", smooth=False, observer=None, gps_solution=None):
    """The loop of ``quatnav::gpsins_batch`` in Python with the public ``run``'s signature
    (:meth:`quatnav.GpsInsFilter.run`): IMU first, times as ``t`` or ``dt``, the aids as
    ``Aid(t, value[, sigma])`` (anything with ``.t``, ``.value`` and optionally ``.sigma``),
    ``outages`` as ``(t_start, t_end)`` pairs that drop the fixes inside them, ``imu_input``
    "rate" or "increment". Returns a dict of the C++ batch's arrays (``llh``, ``v_n``,
    ``q_nb``, ``acc_bias``, ``gyro_bias``, ``sigma``, ``baro_offset``, ``q_scale``,
    ``flags``, ``t`` and one report per aid, statuses and decisions as names; with the
    scale factors also ``acc_scale`` and ``gyro_scale``, and ``sigma`` has 22 columns).
    ``smooth=True``: the smoothed values over the navigating samples
    (:func:`run_smoothed`), the forward dict in ``forward``. ``observer``:
    ``after_predict(k, f)`` after the time update of sample k (``f.sample_transition``: the
    product of its steps' transitions) and ``after_sample(k, f)`` after all its steps (the
    smoother's record)."""
    aids = dict(gps_pos=gps_pos, gps_vel=gps_vel, baro=baro, compass=compass, odometer=odometer,
                outages=outages, imu_input=imu_input, gps_solution=gps_solution)
    if smooth:
        out, sm = run_smoothed(f, gyr, acc, mag, t=t, dt=dt, observer=observer, **aids)
        return {**out, **sm, "forward": out}
    if imu_input not in ("rate", "increment"):
        raise ValueError(f"imu_input: expected 'rate' or 'increment', got {imu_input!r}")
    gyr, acc = np.asarray(gyr, float), np.asarray(acc, float)
    t, _ = sample_times(len(gyr), t, dt)
    if gps_vel is not None and gps_pos is None:
        raise ValueError("gps_vel: needs gps_pos (the filter takes a velocity with a position fix)")
    kw = {}
    if gps_pos is not None:
        kw["gps_t"] = np.asarray(gps_pos.t, float)
        kw["gps_llh"] = np.array(gps_pos.value, float)
        kw["gps_pos_sigma"] = getattr(gps_pos, "sigma", None)
        kw["gps_solution"] = gps_solution
        for o in outages:
            kw["gps_llh"][(kw["gps_t"] >= o[0]) & (kw["gps_t"] < o[1])] = np.nan
    if gps_vel is not None:
        if not np.array_equal(np.asarray(gps_vel.t, float), np.asarray(gps_pos.t, float)):
            raise ValueError("gps_vel.t: expected the times of gps_pos (give NaN rows where a fix has no velocity)")
        kw["gps_vel"], kw["gps_vel_sigma"] = gps_vel.value, getattr(gps_vel, "sigma", None)
    if baro is not None:
        kw["baro_t"], kw["baro_h"] = baro.t, baro.value
    if compass is not None:
        kw["compass_t"], kw["compass_yaw"] = compass.t, compass.value
    if odometer is not None:
        kw["odo_t"], kw["odo_speed"] = odometer.t, odometer.value
    out = batch_loop(f, t, gyr, acc, mag=None if mag is None else np.asarray(mag, float),
                     increments=imu_input == "increment", observer=observer, **kw)
    out["t"] = t
    return out

def batch_loop(f, t, gyro, accel, gps_t=(), gps_llh=None, gps_vel=None, gps_pos_sigma=None,
          gps_vel_sigma=None, baro_t=(), baro_h=None, compass_t=(), compass_yaw=None, mag=None,
          odo_t=(), odo_speed=None, increments=False, observer=None, gps_solution=None):
    """The batch loop over arrays (:meth:`run` unpacks its aids into them)."""
    p = f.p
    t = np.asarray(t, float)
    n = len(t)
    gps_t = np.asarray(gps_t, float) + p.gps_time_offset
    baro_t = np.asarray(baro_t, float)
    compass_t = np.asarray(compass_t, float)
    odo_t = np.asarray(odo_t, float)
    ng, nb, nc, no = len(gps_t), len(baro_t), len(compass_t), len(odo_t)
    nan3 = np.full((ng, 3), np.nan)
    gps_vel = nan3 if gps_vel is None else np.asarray(gps_vel, float)
    gps_pos_sigma = nan3 if gps_pos_sigma is None else np.asarray(gps_pos_sigma, float)
    gps_vel_sigma = nan3 if gps_vel_sigma is None else np.asarray(gps_vel_sigma, float)
    gps_solution = np.zeros(ng, int) if gps_solution is None else np.asarray(gps_solution, int)

    def report(rows, cols, m):
        return {"innovation": np.full((rows, cols * m), np.nan), "nis": np.full((rows, cols), np.nan),
                "status": np.full((rows, cols), "not_initialized", dtype=object),
                "decision": np.full((rows, cols), "none", dtype=object), "inflation": np.ones((rows, cols))}

    def write(rep, i, c, r):
        m = len(r.innovation)
        if r.status in ("ok", "rejected"):
            rep["innovation"][i, c * m:(c + 1) * m] = r.innovation
            rep["nis"][i, c] = r.nis
        rep["status"][i, c], rep["decision"][i, c], rep["inflation"][i, c] = r.status, r.decision, r.inflation

    out = {"llh": np.full((n, 3), np.nan), "v_n": np.full((n, 3), np.nan),
           "q_nb": np.full((n, 4), np.nan), "acc_bias": np.zeros((n, 3)),
           "gyro_bias": np.zeros((n, 3)), "sigma": np.full((n, f.n_states), np.nan),
           "baro_offset": np.full(n, np.nan), "q_scale": np.ones(n), "flags": np.zeros(n, np.uint32),
           "gps": report(ng, 2, 3), "baro": report(nb, 2, 1), "compass": report(nc, 1, 1),
           "odometer": report(no, 1, 1), "mag": report(n if mag is not None else 0, 1, 1),
           "zupt": report(n, 1, 3), "zaru": report(n, 1, 3), "nhc": report(n, 1, 2)}
    if f.scale_factors:
        out["acc_scale"], out["gyro_scale"] = np.zeros((n, 3)), np.zeros((n, 3))
    if n == 0:
        return out
    ig = int(np.sum(gps_t <= t[0]))
    ib = int(np.sum(baro_t <= t[0]))
    ic = int(np.sum(compass_t <= t[0]))
    io = int(np.sum(odo_t <= t[0]))
    for k in range(n):
        was_nav = f.navigating
        if k > 0:
            step = t[k] - t[k - 1]
            w, a = np.asarray(gyro[k], float), np.asarray(accel[k], float)
            if increments:
                w, a = w / step, a / step
            m = 1
            if p.max_dt < step <= p.max_coast and p.max_dt > 0:
                m = int(math.ceil(step / (p.max_dt * (1 - 1e-9))))
            st = "ok"
            f.sample_transition = np.eye(f.n_states)
            for _ in range(m):
                if st == "ok":
                    st = f.predict(w, a, step / m)
                    if st == "ok" and f.navigating:
                        f.sample_transition = f.last_transition @ f.sample_transition
            if observer is not None:
                observer.after_predict(k, f)
            for name, r in zip(("zupt", "zaru", "nhc"), f.update_constraints()):
                write(out[name], k, 0, r)
            if mag is not None and not np.all(np.isnan(mag[k])):
                write(out["mag"], k, 0, f.update_mag(mag[k]))
            while ic < nc and compass_t[ic] <= t[k]:
                write(out["compass"], ic, 0, f.update_compass(float(compass_yaw[ic])))
                ic += 1
            while io < no and odo_t[io] <= t[k]:
                write(out["odometer"], io, 0, f.update_odometer(float(odo_speed[io])))
                io += 1
            while ib < nb and baro_t[ib] <= t[k]:
                for c, r in enumerate(f.update_baro(float(baro_h[ib]))):
                    write(out["baro"], ib, c, r)
                ib += 1
            while ig < ng and gps_t[ig] <= t[k]:
                llh = gps_llh[ig]
                if np.all(np.isnan(llh)):
                    write(out["gps"], ig, 0, _result("non_finite", 3, "skipped"))
                else:
                    rs = f.update_gps(float(llh[0]), float(llh[1]), float(llh[2]), gps_vel[ig],
                                         gps_pos_sigma[ig], gps_vel_sigma[ig], t[k] - gps_t[ig],
                                         int(gps_solution[ig]))
                    for c, r in enumerate(rs):
                        write(out["gps"], ig, c, r)
                ig += 1
        if f.navigating:
            out["llh"][k] = f.llh
            out["v_n"][k] = f.v_n
            out["sigma"][k] = np.sqrt(np.maximum(np.diag(f.s.P), 0.0))
            if f.s.baro_offset_valid:
                out["baro_offset"][k] = f.s.baro_offset
        if f.s.phase != ALIGNING:
            out["q_nb"][k] = f.q_nb
        out["acc_bias"][k] = f.s.acc_bias
        out["gyro_bias"][k] = f.s.gyro_bias
        if f.scale_factors:
            out["acc_scale"][k], out["gyro_scale"][k] = f.s.acc_scale, f.s.gyro_scale
        out["q_scale"][k] = f.s.q_scale
        out["flags"][k] = (FLAGS[("aligning", "levelled", "navigating")[f.s.phase]]
                           | (FLAGS["initialized"] if (not was_nav and f.navigating) else 0)
                           | (FLAGS["at_rest"] if f.at_rest else 0))
        if observer is not None:
            observer.after_sample(k, f)
    out["align_method"], out["heading_source"] = f.s.align_method, f.s.heading_source
    return out
