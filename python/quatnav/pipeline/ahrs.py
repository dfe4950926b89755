"""An attitude run on a user's log, as ``quatnav ahrs run`` makes it: read the IMU and the
magnetometer, check them, average to a rate, run QuaternionEKF, EulerEKF or MargFilter (and
smooth), and return the result with its warnings (:class:`AhrsRun`)."""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._command import InputError
from ..plausibility import check_imu, check_imu_times, checked_by_caller
from .recording import PipelineWarning, issue, recorded

__all__ = ["AhrsRun", "run_ahrs", "read_ahrs_log", "decimate", "FILTERS"]

#: The attitude filters by their command-line name.
FILTERS = {"qekf": "QuaternionEKF", "euler-ekf": "EulerEKF", "marg": "MargFilter"}


@dataclass(repr=False, eq=False)
class AhrsRun:
    """What :func:`run_ahrs` returns.

    Attributes
    ----------
    result : quatnav.FilterResult
        The filter's (with ``smooth``: the smoothed) result, one row per (averaged) IMU sample.
    log : quatnav.io.Log
        The log it ran on (calibrated where a calibration was given; its notes say what the
        readers and the run did, the declination's source among them).
    filter : str
        The filter's class name.
    declination : float
        The magnetic declination applied, rad east (0: the yaw is magnetic).
    rate : float or None
        The rate the IMU was averaged to, Hz (None: every sample).
    warnings : list of Warning
        Every warning of the run, each once (also issued with :func:`warnings.warn`).
    """

    result: object
    log: object
    filter: str
    declination: float = 0.0
    rate: float | None = None
    warnings: list = field(default_factory=list)

    @property
    def magnetometer(self) -> dict:
        """What the filter made of the magnetometer: ``rows`` (rows with a sample: the
        magnetometer's own rate), ``used`` (of those, the updates it applied: not rejected by its
        disturbance tests, nor skipped as invalid), ``rejected``, ``skipped``."""
        r = self.result
        if self.log.mag is None:
            return {"rows": 0, "used": 0, "rejected": 0, "skipped": 0}
        rows = ~r.flag("no_mag")
        rejected = int(np.count_nonzero(rows & r.flag("mag_rejected")))
        skipped = int(np.count_nonzero(rows & r.flag("mag_skipped") & ~r.flag("mag_rejected")))
        n = int(np.count_nonzero(rows))
        return {"rows": n, "used": n - rejected - skipped, "rejected": rejected, "skipped": skipped}

    def summary(self) -> dict:
        """The run as a dict of plain values (``quatnav ahrs run --json``)."""
        res = self.result
        out = {"rows": int(len(res.t)), "imu_samples": int(len(self.log.imu.t)), "filter": self.filter,
               "smoothed": res.smoothed, "magnetometer": self.magnetometer["used"] > 0,
               "magnetometer_rows": self.magnetometer,
               "declination_rad": self.declination, "rate_hz": self.rate,
               "flags": {n: int(np.count_nonzero(res.flag(n))) for n in res.flags_seen()},
               "skipped_rows": {k: int(len(v)) for k, v in res.skipped_rows.items()},
               "warnings": [str(w) for w in self.warnings]}
        for text in self.log.notes:
            out.setdefault("notes", []).append(text)
            if text.startswith("declination"):
                out["declination_note"] = text
        return out

    def __repr__(self) -> str:
        return (f"<AhrsRun of {self.log.source!r}: {self.filter}, {len(self.result.t)} rows"
                f"{', smoothed' if self.result.smoothed else ''}; {len(self.warnings)} warnings>")


def read_ahrs_log(log=None, *, imu=None, mag=None, no_mag: bool = False):
    """The log of an attitude run: ``log`` (a :class:`quatnav.io.Log`), or an IMU CSV file
    ``imu`` (time, gyro_x..z, accel_x..z, optional mag_x..z) with an optional magnetometer CSV
    ``mag`` (time, mag_x..z, any unit); ``no_mag`` drops the magnetometer."""
    from .. import io
    if log is None:
        if imu is None:
            raise InputError("give a log or an IMU file")
        log = io.read(imu, format="csv", kind="imu")
        if mag:
            from ..io.table import CsvError, read_table
            try:
                c = read_table(mag, ("time", "mag_x", "mag_y", "mag_z"), what="MAG").columns
            except CsvError as e:
                raise InputError(str(e)) from None
            log.mag = io.Mag(t=c["time"], values=np.column_stack([c["mag_x"], c["mag_y"], c["mag_z"]]),
                             unit="as in the file")
    log.require("imu")
    if no_mag:
        # nor say where the magnetometer was read from (ULog: "magnetometer from vehicle_magnetometer")
        log.mag = None
        log.notes = [n for n in log.notes if not n.startswith("magnetometer")]
    return log


def decimate(t, gyr, acc, rate):
    """Block means of the IMU to about ``rate`` Hz: (t_end, gyr_mean, acc_mean, block length)."""
    med = float(np.median(np.diff(t)))
    k = max(1, int(round(1.0 / (rate * med))))
    n = (len(t) // k) * k
    if k == 1:
        return t, gyr, acc, k
    tb = t[k - 1:n:k]
    return tb, gyr[:n].reshape(-1, k, 3).mean(1), acc[:n].reshape(-1, k, 3).mean(1), k


def run_ahrs(log=None, *, imu=None, mag=None, no_mag: bool = False, filter: str = "qekf", declination=0.0,
             date: float | None = None, rate: float | None = None, smooth: bool = False,
             calibration=None) -> AhrsRun:
    """Run an attitude filter on a log as ``quatnav ahrs run`` does.

    Parameters
    ----------
    log : quatnav.io.Log, optional
        The log (:func:`quatnav.io.read`); or ``imu`` and ``mag``, CSV files (:func:`read_ahrs_log`).
    filter : {"qekf", "euler-ekf", "marg"}
        QuaternionEKF, EulerEKF or MargFilter.
    declination : float or "auto"
        Magnetic declination, rad east: the yaw is then relative to true north; ``"auto"``: the
        World Magnetic Model's at the log's first GNSS fix on ``date`` (a decimal year), else the
        log's UTC date, else today's.
    rate : float, optional
        Average the IMU over blocks to about this rate, Hz, first.
    smooth : bool
        The Rauch-Tung-Striebel smoothed attitude (qekf, euler-ekf).
    calibration : str, Path or quatnav.calibration.Calibration, optional
        A sensor calibration applied to the gyro, accelerometer and magnetometer first.

    Returns
    -------
    AhrsRun
    """
    with recorded() as kept, checked_by_caller():  # the inputs are checked here, with the log's name
        run = _run(log, imu, mag, no_mag, filter, declination, date, rate, smooth, calibration)
    run.warnings = kept
    issue(kept)
    return run


def _run(log, imu, mag, no_mag, name, declination, date, rate, smooth, calibration) -> AhrsRun:
    import quatnav
    if name not in FILTERS:
        raise InputError(f"filter: expected one of {', '.join(FILTERS)}, got {name!r}")
    log = read_ahrs_log(log, imu=imu, mag=mag, no_mag=no_mag)
    if calibration:
        from .. import calibration as cal
        try:
            c = calibration if isinstance(calibration, cal.Calibration) else cal.load_calibration(calibration)
        except (ValueError, FileNotFoundError) as e:
            raise InputError(str(e)) from None
        m = log.mag.values if log.mag is not None else None
        log.imu.gyr, log.imu.acc, m = cal.apply(c, gyr=log.imu.gyr, acc=log.imu.acc, mag=m)
        if log.mag is not None:
            log.mag.values = m
    if rate is not None and not rate > 0:
        raise InputError(f"--rate {rate:g}: must be > 0 Hz")
    if len(log.imu.t) < 2:
        raise InputError(f"{log.source}: fewer than 2 IMU samples")
    # times in ms, us or ns are refused as ins run refuses them (the filters' max_dt is 1 s)
    check_imu_times(log.imu.t, np.arange(1, len(log.imu.t) + 1), 1.0, where=f"IMU {log.source}")
    names = ("gyro_x/y/z", "accel_x/y/z") if log.format == "csv" else ("the gyro", "the accelerometer")
    for w in check_imu(log.imu.gyr, log.imu.acc, t=log.imu.t, where=f"IMU {log.source}", axes="up", names=names):
        warnings.warn(w)
    if smooth and name == "marg":
        raise InputError("--smooth: marg has no smoother; use --filter qekf or euler-ekf")
    if isinstance(declination, str):
        if declination != "auto":
            raise InputError(f"declination: expected rad east or 'auto', got {declination!r}")
        from ..core.magnetic import first_fix_declination
        g = log.gnss
        declination, texts = first_fix_declination(*((g.lat, g.lon, g.h) if g is not None else ([], [], [])),
                                                   log.source, utc=g.utc if g is not None else None, date=date,
                                                   warn=lambda text: warnings.warn(text, PipelineWarning))
        log.notes.extend(texts)
    elif date is not None:
        raise InputError("date: the date of the World Magnetic Model goes with declination='auto'")
    declination = float(declination)
    res = _filter_run(quatnav, log, name, declination, rate, smooth)
    return AhrsRun(result=res, log=log, filter=FILTERS[name], declination=declination, rate=rate)


def _filter_run(quatnav, log, name, declination, rate, smooth):
    """Run the attitude filter ``name`` on ``log`` (IMU averaged to ``rate`` Hz when given;
    ``smooth``: the smoothed result); returns its result."""
    from ..io import mag_on_imu_times
    t, gyr, acc = log.imu.t, log.imu.gyr, log.imu.acc
    mag = mag_on_imu_times(log)
    if rate:
        t, gyr, acc, k = decimate(t, gyr, acc, rate)
        if mag is not None and k > 1:
            n = len(t) * k
            m = mag[:n].reshape(-1, k, 3)
            with warnings.catch_warnings():  # a block without a magnetometer sample: NaN, no sample
                warnings.simplefilter("ignore", RuntimeWarning)
                mag = np.nanmean(m, axis=1) if np.isfinite(m).any() else None
    cls = getattr(quatnav, FILTERS[name])
    # QuaternionEKF refers its yaw to true north given the declination; MargFilter's declination
    # only turns GPS velocities into its magnetic frame and EulerEKF has none: their yaw is magnetic
    takes_decl = FILTERS[name] == "QuaternionEKF"
    f = cls(declination=declination) if takes_decl else cls()
    if mag is not None and not np.isfinite(mag[0]).all():
        first = np.flatnonzero(np.isfinite(mag).all(1))
        if first.size == 0:
            mag = None
        else:
            mag[0] = mag[first[0]]  # the initial heading from the first magnetometer sample
    res = f.run(gyr, acc, mag, t=t, on_invalid="skip", **({"smooth": True} if smooth else {}))
    if not takes_decl and declination and mag is not None:
        # a filter whose yaw is magnetic (EulerEKF, MargFilter): turn the navigation frame about
        # down by the declination (q_true_nb = q_z(decl) * q_mag_nb)
        from ..core import quaternion as Q
        res.quat[:] = Q.mul(np.array([math.cos(declination / 2), 0.0, 0.0, math.sin(declination / 2)]), res.quat)
    return res
