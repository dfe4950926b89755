"""The clocks of the streams: overlapping time ranges, offsets that name the clocks (leap seconds,
the GPS epoch, a time of week), and the start of the motion as the IMU and the GNSS see it."""
from __future__ import annotations

import numpy as np

from ._signals import box_mean, row_dots, row_norms, still_run
from .categories import ClockWarning

__all__ = ["check_overlap", "check_clock", "motion_start", "check_motion_start"]


def check_overlap(t_imu, t_gnss, where="GNSS"):
    """A warning when the GNSS and IMU time ranges do not overlap (or None)."""
    if len(t_gnss) and (t_gnss[-1] < t_imu[0] or t_gnss[0] > t_imu[-1]):
        return ClockWarning(
            f"{where} times {t_gnss[0]:g} to {t_gnss[-1]:g} s and IMU times {t_imu[0]:g} to {t_imu[-1]:g} s "
            "do not overlap: the files must share one clock, in seconds")
    return None


#: Clock offsets that say which clocks two time columns are on: (seconds, what).
_CLOCKS = ((18.0, "GPS time against UTC (18 leap seconds)"),
           (315964800.0, "Unix time against GPS time (the GPS epoch, 1980-01-06)"),
           (315964782.0, "Unix time against GPS time less the leap seconds"))


def check_clock(t_imu, gnss_t, where="GNSS"):
    """A warning naming the likely clocks when the GNSS times do not overlap the IMU's (or None):
    a difference of 18 s (GPS time against UTC), of the GPS epoch in Unix time, a time of week
    against a time since boot."""
    gnss_t = np.asarray(gnss_t, float)
    if not len(gnss_t) or not (gnss_t[-1] < t_imu[0] or gnss_t[0] > t_imu[-1]):
        return None
    d = float(np.median(gnss_t) - np.median(t_imu))
    for off, what in _CLOCKS:
        if abs(abs(d) - off) < 0.5 * (t_imu[-1] - t_imu[0]) + 1.0:
            return ClockWarning(
                f"{where} times are {d:+.6g} s from the IMU's: {what}? give gps_time_offset = {-round(d):g} in "
                "[filter], or convert the times")
    if 0.0 <= gnss_t[0] <= 604800.0 and t_imu[0] > 1e8:
        return ClockWarning(
            f"{where} times look like a GPS time of week ({gnss_t[0]:.6g} s) and the IMU's like an absolute time "
            f"({t_imu[0]:.6g} s): put both on one clock (gps_time_offset shifts the GNSS times)")
    return None


def motion_start(t, speed_or_rate, threshold):
    """The first time the signal exceeds ``threshold`` after having been below it (or None)."""
    x = np.asarray(speed_or_rate, float)
    below = np.flatnonzero(x < threshold)
    if not below.size:
        return None
    above = np.flatnonzero((x > threshold) & (np.arange(len(x)) > below[0]))
    return float(t[above[0]]) if above.size else None


def check_motion_start(t, gyro, gnss_t, gnss_speed, where="GNSS", imu="IMU", accel=None):
    """A warning when the IMU and the GNSS see the start of the motion 1 to 10 s apart (their
    clocks differ: gps_time_offset), or None. Motion in the IMU (smoothed over 0.2 s, after at
    least 1 s still; the onset nearest the GNSS start): |gyro| above 0.3 rad/s or, given
    ``accel``, the
    specific force more than 0.5 m/s^2 from its mean over a steady second that ends 0.2 s
    before (steady: a spread below 0.2 m/s^2 and a magnitude within 0.25 m/s^2 of the log's
    median, i.e. gravity alone: a vehicle pulling away without turning, whatever its motion at
    the start of the log or the IMU's mounting); in the GNSS the speed above 0.5 m/s after being
    below it. Starts more than 10 s apart are taken for different events (a latency is below a
    second; a clock offset of seconds or more shows in check_clock).

    A threshold on the speed sees a start late and a stop early (a walker reaches 0.5 m/s about
    a second after the first step), the IMU's activity sees both when they happen. Where the
    motion that starts also stops (the GNSS speed below 0.5 m/s for a second, the IMU still for a
    second, the two within 10 s), and the start's difference exceeds the stop's by 0 to 4 s (twice
    the threshold's lag, within a GNSS interval), the offset is the mean of the two differences, in
    which the lag cancels. A stop the IMU sees earlier than that (a vehicle braking gently after its
    last turn looks still to it) is not used: the start alone gives the offset."""
    if gnss_speed is None or len(gnss_t) < 3 or len(t) < 10:
        return None
    dt = float(np.median(np.diff(t)))
    w = max(1, int(round(0.2 / dt)))
    activity = box_mean(row_norms(np.asarray(gyro, float)), w) / 0.3
    what = "|gyro| > 0.3 rad/s"
    steady = None
    if accel is not None and len(t) > 2 * w + 2:
        fs = box_mean(np.asarray(accel, float), w)
        n = len(fs)
        n1 = max(2, int(round(1.0 / dt)))  # the steady second, ending w samples before
        c1 = np.vstack([np.zeros(3), np.cumsum(fs, axis=0)])
        c2 = np.r_[0.0, np.cumsum(row_dots(fs, fs))]
        # row i: the second [i - w + 1 - n1, i - w + 1), past the smoothing's edge (from row w):
        # rows i0 = 2 w - 1 + n1 on, as slices of the cumulative sums
        i0 = min(n, 2 * w - 1 + n1)
        hi, lo = slice(i0 - w + 1, n - w + 1), slice(i0 - w + 1 - n1, n - w + 1 - n1)
        mean = np.zeros_like(fs)
        mean[i0:] = (c1[hi] - c1[lo]) / n1
        spread2 = np.zeros(n)
        spread2[i0:] = (c2[hi] - c2[lo]) / n1 - row_dots(mean[i0:], mean[i0:])
        g = float(np.median(row_norms(fs[w:-w])))
        steady = (np.arange(n) >= i0) & (spread2 < 0.2 ** 2) & (np.abs(row_norms(mean) - g) < 0.25)
        dev = np.where(steady, row_norms(fs - mean), 0.0)
        activity = np.maximum(activity, dev / 0.5)
        what += " or f 0.5 m/s^2 from a steady second before"
    gnss_t = np.asarray(gnss_t, float)
    tg = motion_start(gnss_t, gnss_speed, 0.5)
    # the IMU onsets: above the threshold after at least 1 s still (below it, and steady); the
    # stops: above it before at least 1 s still
    above = activity > 1.0
    still = ~above if steady is None else ~above & steady
    n1 = round(1.0 / dt)
    onsets = np.flatnonzero(above[1:] & (still_run(still)[:-1] >= n1)) + 1
    stops = np.flatnonzero(above[:-1] & (still_run(~above[::-1])[::-1][1:] >= n1))  # steady only later
    if tg is None or not onsets.size:
        return None
    ti = float(t[onsets[np.argmin(np.abs(t[onsets] - tg))]])
    if abs(tg - ti) > 10.0:
        return None
    d, seen = tg - ti, f"starts at {tg:.3f} s in the GNSS and at {ti:.3f} s in the {imu}"
    sg = _gnss_stop(gnss_t, np.asarray(gnss_speed, float), tg, 0.5, 1.0)
    if sg is not None and stops.size:
        si = float(t[stops[np.argmin(np.abs(t[stops] - sg))]])
        # the same offset seen with the threshold's lag added at the start and taken off at the
        # stop: (tg - ti) - (sg - si) = 2 lag >= 0, up to a GNSS interval of sampling. Over 4 s (a
        # lag over 2 s): different events; below: a stop the IMU saw early (gentle braking)
        lag2 = (tg - ti) - (sg - si)
        tol = max(0.5, float(np.median(np.diff(gnss_t))))
        if abs(sg - si) <= 10.0 and -tol <= lag2 <= 4.0:
            d = 0.5 * (tg - ti + sg - si)
            seen += f" and stops at {sg:.3f} s and {si:.3f} s"
    if not 1.0 < abs(d) <= 10.0:
        return None
    return ClockWarning(f"{where}: the motion {seen} ({what}): "
                        f"the clocks may differ by {d:+.2f} s; if so give gps_time_offset = {-d:.2f} in [filter]")


def _gnss_stop(t, speed, after, threshold, hold):
    """The first time after ``after`` that the speed falls below ``threshold`` and stays below
    it for ``hold`` seconds (or None)."""
    below = speed < threshold
    for k in np.flatnonzero(below[1:] & ~below[:-1] & (t[1:] > after)) + 1:
        end = np.searchsorted(t, t[k] + hold)
        if end < len(t) and below[k:end + 1].all():
            return float(t[k])
    return None
