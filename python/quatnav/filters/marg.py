"""MARG attitude filter of paper 001: :class:`MargFilter`.

Gauss-Newton attitude from gravity and the magnetic field (eq. 1-5) blended with gyro
integration (eq. 6); the accelerometer is corrected for the vehicle's acceleration with the GPS
antenna acceleration and the lever-arm terms (eq. 7, corrected form in ``marg_filter.hpp``)::

    f_b + w_dot x d + w x (w x d) = C_bn (a_g_n - g_n)

Wraps the C++ class of ``quatnav._core`` (float64 or float32, chosen by ``dtype``); batch runs
execute in C++ with the GIL released. The plain numpy twin is :class:`quatnav.reference.MargFilter`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate as V
from ._compiled import compiled
from ._base import (Filter, FilterResult, aid_times, check_aid, check_run_inputs, marg_inputs, times_of,
                    warn_aid_outside)
from .tables import MARG_FLAGS, MARG_PARAMS

__all__ = ["MargFilter", "MargResult", "MARG_FLAGS"]


@dataclass(repr=False, eq=False)
class MargResult(FilterResult):
    """Output of :meth:`MargFilter.run`: the fields of :class:`~quatnav.FilterResult` (``bias`` is
    zero unless ``bias_gain > 0``; ``sigma`` is None, the filter has no covariance; no per-aid
    diagnostics, the GPS velocity is differentiated into an acceleration, not an update) and

    Attributes
    ----------
    gps_acc_n : (N, 3) ndarray
        GPS antenna acceleration used by eq. (7) at each sample, m/s^2 NED; NaN where the
        accelerometer was not corrected.
    residual : (N,) ndarray
        Norm of the Gauss-Newton error vector eq. (3) at the predicted attitude (dimensionless;
        NaN where no update was made).
    """

    FLAGS: ClassVar[dict] = MARG_FLAGS
    gps_acc_n: np.ndarray | None = None
    residual: np.ndarray | None = None

    def _columns(self) -> dict:
        cols = super()._columns()
        for i, c in enumerate("ned"):
            cols[f"gps_acc_{c}"] = self.gps_acc_n[:, i]
        cols["residual"] = self.residual
        return cols


class MargFilter(Filter):
    """Gauss-Newton MARG attitude filter with GPS acceleration correction (paper 001).

    Notes
    -----
    The accelerometer must be in m/s^2 when the correction is used (the GPS acceleration is
    compared with it); the magnetometer may be in any unit.

    The robustness parts of :class:`~quatnav.QuaternionEKF`, with the same names and defaults
    except ``gravity`` (9.80665, the g of eq. 7) and ``acc_lp_tau`` (1 s instead of 3 s: the
    filter has no gyro-bias covariance to shorten the low-pass with while the bias is unknown, and
    the low-pass frame drifts by the bias error over ``acc_lp_tau``): rest detection (``rest_*``; at rest the low-passed
    gyro is taken as the gyro bias, flag ``at_rest``), the accelerometer part (``acc_lp_tau``
    low-pass; ``acc_reject``: a rejected sample skips the update, flag ``acc_rejected``;
    ``acc_adapt`` lowers the gain to ``gain / (1 + acc_adapt ||a|-g|/g)``; not applied while eq. 7
    corrects the sample) and the magnetometer part (``mag_*``: a disturbed field is not used and
    the update runs on gravity alone, flag ``mag_rejected``). ``MargFilter(paper=True)`` switches
    them off: the plain filter of paper 001.
    """

    n_states = 7  # q and the gyro bias
    PARAMS = MARG_PARAMS
    FLAGS = MARG_FLAGS
    _core_params = "MargFilterParams"

    def _make(self, p):
        if self._opts.get("paper"):
            p = self._core_struct(compiled("MargFilterParams", self.dtype).paper())
        return compiled("MargFilter", self.dtype)(p)

    @property
    def at_rest(self) -> bool:
        """True while rest is detected."""
        return bool(self._f.at_rest)

    @property
    def quat(self) -> np.ndarray:
        """Current ``q_nb`` [w, x, y, z]."""
        return np.asarray(self._f.quat, dtype=float)

    @property
    def bias(self) -> np.ndarray:
        """Current gyro bias, rad/s."""
        return np.asarray(self._f.bias, dtype=float)

    @property
    def gps_acc_n(self) -> np.ndarray | None:
        """The GPS antenna acceleration eq. (7) would use now (m/s^2 NED), or None."""
        return np.asarray(self._f.gps_acc_n, dtype=float) if self._f.gps_acc_available else None

    def set_mag_dip(self, dip: float) -> None:
        """Fix the reference field ``[cos(dip), 0, sin(dip)]`` (dip positive down, rad)."""
        dip = float(dip)
        if not np.isfinite(dip) or abs(dip) > np.pi / 2:
            raise ValueError(f"dip: expected a finite angle in [-pi/2, pi/2] rad, got {dip!r}")
        self._f.set_mag_dip(dip)

    # -- single steps --------------------------------------------------------------------
    def initialize(self, acc, mag=None) -> None:
        """Tilt from one accelerometer sample, heading from one magnetometer sample."""
        a = V.vector(acc, "acc", dtype=self.dtype, nonzero=True)
        m = None if mag is None else V.vector(mag, "mag", dtype=self.dtype, nonzero=True)
        status = self._f.initialize(a, m)
        if status != "ok":
            raise ValueError(f"acc, mag: cannot initialize ({status})")

    def reset(self, quat, bias=None) -> None:
        """Start from a given ``q_nb`` and gyro bias (rad/s)."""
        q = V.vector(quat, "quat", 4, dtype=self.dtype, nonzero=True)
        b = np.zeros(3, self.dtype) if bias is None else V.vector(bias, "bias", dtype=self.dtype)
        status = self._f.reset(q, b)
        if status != "ok":
            raise ValueError(f"quat: refused ({status})")

    def predict(self, gyr, dt: float) -> str:
        """Gyro integration with one sample (rad/s) over ``dt`` seconds."""
        self._require_init("predict")
        g = V.vector(gyr, "gyr", dtype=self.dtype)
        d = V.positive(dt, "dt")
        status = self._f.predict(g, d)
        if status == "invalid_dt":
            raise ValueError(f"dt: {d} s exceeds max_dt={self._f.params.max_dt} s")
        return status

    def update_gps_velocity(self, v_n, t: float) -> str:
        """One GPS velocity fix ``v_n`` (antenna, true NED, m/s) valid at time ``t`` (s, increasing)."""
        v = V.vector(v_n, "v_n", dtype=self.dtype)
        tt = float(t)
        if not np.isfinite(tt):
            raise ValueError(f"t: expected a finite time, got {t!r}")
        status = self._f.update_gps_velocity(v, tt)
        if status == "invalid_dt":
            raise ValueError(f"t: {tt} s does not follow the previous fix's time")
        return status

    def update_acc(self, acc):
        """Gauss-Newton update with the accelerometer only (6D; m/s^2). Returns the C++ result
        (status, iterations, converged, gps_corrected, residual, residual_final, correction)."""
        self._require_init("update_acc")
        return self._f.update_acc(V.vector(acc, "acc", dtype=self.dtype, nonzero=True))

    def update_acc_mag(self, acc, mag):
        """Gauss-Newton update with accelerometer (m/s^2) and magnetometer, eq. (1)-(6)."""
        self._require_init("update_acc_mag")
        return self._f.update_acc_mag(V.vector(acc, "acc", dtype=self.dtype, nonzero=True),
                                      V.vector(mag, "mag", dtype=self.dtype, nonzero=True))

    def _require_init(self, what: str) -> None:
        if not self._f.initialized:
            raise ValueError(f"{what}: the filter is not initialized (call initialize or reset first)")

    # -- batch ---------------------------------------------------------------------------
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_vel=None, on_invalid: str = "raise") -> MargResult:
        """Run the filter over N IMU samples and M GPS velocity fixes (in C++, GIL released),
        continuing from the current state (a new filter initializes itself on the first sample;
        for an unrelated log use a new filter).

        Parameters
        ----------
        gyr : (N, 3) array_like
            Angular rate, rad/s, body frame.
        acc : (N, 3) array_like
            Specific force, m/s^2, body frame.
        mag : (N, 3) array_like, optional
            Magnetic field (any unit). All-NaN rows mean "no sample"; without ``mag`` the
            filter runs in 6D mode and heading is free.
        t : (N,) array_like, keyword
            Strictly increasing IMU timestamps, seconds; or
        dt : float or (N,) array_like, keyword
            Step length in seconds (sample k is then at time ``sum(dt[1:k+1])``, sample 0 at 0).
        gps_vel : Aid, optional
            ``Aid(t, v_n)``: strictly increasing times of validity (M,), s, on the IMU's clock, and
            the GPS antenna velocity (M, 3), true NED, m/s (rotated by ``declination`` into the
            filter's frame). A fix is used from the first IMU sample at or after its time and held
            until the next. No per-fix sigma.
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite or zero-norm row raises ``ValueError`` naming the
            argument and row. "skip": such samples skip the affected step (see ``flags``).

        Returns
        -------
        MargResult
        """
        mode = V.on_invalid(on_invalid)
        strict = mode == "raise"
        g, a, m = marg_inputs(gyr, acc, mag, self.dtype, strict)
        n = g.shape[0]
        steps = V.time_steps(n, dt=dt, t=t, dtype=np.float64,
                             max_dt=float(self._f.params.max_dt) if strict else None)
        check_run_inputs(self, g, a, steps=steps)
        times = times_of(n, t, steps)
        aid = check_aid(gps_vel, "gps_vel")
        if aid is not None:
            gt = aid_times(aid.t, "gps_vel.t")
            gv = V.vectors(aid.value, "gps_vel.value", n=gt.shape[0], dtype=self.dtype, finite=strict,
                           like="gps_vel.t")
            if n:
                warn_aid_outside("MargFilter", "gps_vel", gt, float(times[0] - steps[0]), float(times[-1]),
                                 "all are taken at the first sample, as if just measured")
        else:
            gv = np.zeros((0, 3), self.dtype)
            gt = np.zeros(0)
        quat, bias, gps_acc, resid, flags = self._f.run(
            np.ascontiguousarray(times, np.float64), np.ascontiguousarray(steps, self.dtype), g, a, m,
            gt, np.ascontiguousarray(gv, self.dtype))  # times in double (aid_times: contiguous float64)
        skipped = {}
        for name in ("predict_skipped", "acc_skipped", "mag_skipped"):
            rows = np.flatnonzero(flags & MARG_FLAGS[name])
            if rows.size:
                skipped[name] = rows
        return MargResult("MargFilter", times, quat, bias, None, flags, skipped_rows=skipped,
                          gps_acc_n=gps_acc, residual=resid)
