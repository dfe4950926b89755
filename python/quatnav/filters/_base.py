"""What the five filters share: the aid type, the result classes, the parameter declarations and
their checks, and the lazy load of the compiled module.

Every filter follows one shape::

    f = Filter(param=value, ..., dtype=np.float64)              # keyword-only, SI units
    r = f.run(gyr, acc, mag=None, *, t=None, dt=None, <aid>=Aid(t, value, sigma), on_invalid="raise")
    r.t, r.quat, r.bias, r.sigma, r.flags, r.flag("name"), r.aids["<aid>"], r.to_dataframe()

``run`` continues from the filter's current state (a fresh filter starts uninitialized); a second,
unrelated log needs a new filter object (or :meth:`Filter.set_state` with the state of one).
"""
from __future__ import annotations

import importlib
import inspect
import warnings
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .. import _validate as V
from ._compiled import compiled
from ..plausibility.categories import AidWarning
from ..plausibility.units import accel_unit  # noqa: F401  (GpsInsFilter's run names a unit with it)
from ..core import quaternion as Q
from .tables import STATUS_NAMES

__all__ = ["Aid", "AidResult", "AidWarning", "FilterResult", "NavResult", "Filter", "core"]


def warn_aid_outside(owner: str, name: str, aid_t: np.ndarray, start: float, end: float,
                     before: str = "none is used") -> None:
    """Warn (AidWarning) when every time of an aid is before ``start`` or after ``end`` (the IMU's
    span): ``before`` says what the filter does with aid samples that precede the span."""
    if aid_t.size == 0 or not (np.isfinite(start) and np.isfinite(end)):
        return
    if aid_t[-1] < start:
        side, what = "before", before
    elif aid_t[0] > end:
        side, what = "after", "none is used"
    else:
        return
    span = f"{aid_t[0]:.10g}..{aid_t[-1]:.10g}" if aid_t.size > 1 else f"{aid_t[0]:.10g}"
    warnings.warn(f"{owner}: all {aid_t.size} {name} times (t = {span} s) are {side} the IMU's "
                  f"(t = {start:.10g}..{end:.10g} s): {what}; give both on one clock", AidWarning, stacklevel=3)


def core():
    """The compiled module ``quatnav._core``, imported on first use."""
    return importlib.import_module("quatnav._core")


# ------------------------------------------------------------------------------------------------
# Aids
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Aid:
    """One aiding record: its own times, values and optional one-sigma values.

    Parameters
    ----------
    t : (K,) array_like
        Times of validity, s, on the IMU's clock.
    value : (K,) or (K, m) array_like
        The measurements, SI units (the filter's ``run`` names each aid's unit and frame).
    sigma : (K, m) array_like, optional
        Per-sample one-sigma in the unit of ``value``; NaN entries (and ``None``) take the filter's
        parameter. Only aids whose filter accepts per-sample sigmas take it (else ``ValueError``).

    Every aid of every filter is given this way, e.g. ``gps_vel=Aid(t_gps, v_n)``.
    """

    t: Any
    value: Any
    sigma: Any = None

    def __repr__(self) -> str:
        k = np.shape(self.t)
        return f"Aid({k[0] if k else '?'} samples{', with sigma' if self.sigma is not None else ''})"


def check_aid(x, name: str, sigma_ok: bool = False):
    """``x`` as an :class:`Aid` (or None); anything else is a TypeError naming ``name``."""
    if x is None:
        return None
    if not isinstance(x, Aid):
        raise TypeError(f"{name}: expected quatnav.Aid(t, value, sigma=None), got {type(x).__name__}")
    if x.sigma is not None and not sigma_ok:
        raise ValueError(f"{name}.sigma: this filter takes no per-sample sigma for {name} (set the parameter)")
    return x


def aid_times(x, name: str, strict_increasing: bool = True) -> np.ndarray:
    """Finite, ordered (K,) float64 times; the error names the row."""
    a = V._numeric(x, name)
    if a.ndim != 1:
        raise ValueError(f"{name}: expected shape (K,), got {a.shape}")
    a = np.ascontiguousarray(a, dtype=np.float64)
    r = V.first_bad_row(a)
    if r is not None:
        raise ValueError(f"{name}: non-finite value in row {r}")
    d = np.diff(a)
    bad = np.flatnonzero(~(d > 0) if strict_increasing else d < 0)
    if bad.size:
        k = int(bad[0]) + 1
        what = "strictly increasing" if strict_increasing else "non-decreasing"
        kind = "duplicate" if d[bad[0]] == 0 else "unsorted"
        raise ValueError(f"{name}: times must be {what} ({kind}); row {k} ({float(a[k])!r}) "
                         f"does not follow row {k - 1} ({float(a[k - 1])!r})")
    return a


@dataclass(repr=False, eq=False)
class AidResult:
    """Diagnostics of one aid, one row per aiding sample, the same fields for every aid.

    Attributes
    ----------
    t : (K,) ndarray
        Times of the aiding samples, s.
    innovation : (K, m) ndarray
        Measurement minus prediction, in the aid's unit (NaN where no update was made).
    nis : (K,) ndarray
        Normalized innovation squared (NaN where no update was made).
    status : (K,) uint8 ndarray
        ``quatnav::Status`` code of each update (names: :attr:`status_names`, :data:`STATUS_NAMES`).
    """

    t: np.ndarray
    innovation: np.ndarray
    nis: np.ndarray
    status: np.ndarray

    @property
    def status_names(self) -> np.ndarray:
        """(K,) the statuses as strings (``"ok"``, ``"rejected"``, ``"not_initialized"``, ...)."""
        return np.array([STATUS_NAMES[int(s)] for s in self.status], dtype=object)

    @property
    def accepted(self) -> np.ndarray:
        """(K,) bool: the update was applied."""
        return self.status == STATUS_NAMES.index("ok")

    @property
    def rejected(self) -> np.ndarray:
        """(K,) bool: the update was refused by its chi-square gate."""
        return self.status == STATUS_NAMES.index("rejected")

    def counts(self) -> dict:
        """Number of samples per status name (only the statuses that occur)."""
        codes, n = np.unique(self.status, return_counts=True)
        return {STATUS_NAMES[int(c)]: int(k) for c, k in zip(codes, n)}

    def to_dataframe(self):
        """pandas DataFrame indexed by ``t``: ``innovation_<i>``, ``nis``, ``status`` (names)."""
        pd = _pandas()
        inn = np.asarray(self.innovation).reshape(len(self.t), -1)
        cols = {f"innovation_{i}": inn[:, i] for i in range(inn.shape[1])}
        cols.update(nis=self.nis, status=self.status_names)
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))

    def __repr__(self) -> str:
        return f"AidResult({len(self.t)} samples, {self.counts()})"


def _pandas():
    try:
        import pandas as pd
    except ImportError:
        raise ImportError("to_dataframe needs pandas: pip install 'quatnav[io]'") from None
    return pd


# ------------------------------------------------------------------------------------------------
# Results
# ------------------------------------------------------------------------------------------------
@dataclass(repr=False, eq=False)
class FilterResult:
    """Output of every filter's ``run``.

    Attributes
    ----------
    filter : str
        Name of the filter that made it.
    t : (N,) ndarray
        Time of each IMU sample, s (with ``dt=``: ``t[0] = 0`` and the cumulated steps).
    quat : (N, 4) ndarray
        ``q_nb`` [w, x, y, z] after each sample (body to navigation frame, NED). NaN where the
        filter has no attitude yet (GpsInsFilter while aligning).
    bias : (N, 3) ndarray
        Gyro bias estimate, rad/s.
    sigma : (N, n) ndarray or None
        One-sigma of every state (square roots of the covariance diagonal; columns
        :attr:`sigma_names`); None for a filter without a covariance (MargFilter).
    flags : (N,) uint32 ndarray
        Bits of the filter's flag table (:attr:`FLAGS`); decode with :meth:`flag`.
    aids : dict of str to AidResult
        Per-aid diagnostics, keyed by the aid's ``run`` keyword (derived updates get their own
        key, e.g. ``"baro_vd"``).
    skipped_rows : dict of str to ndarray
        Rows skipped for invalid input or saturation, by kind.
    forward : FilterResult or None
        With ``run(..., smooth=True)``: the causal (forward) result, of the same type; the
        estimates and sigmas of this result are then the Rauch-Tung-Striebel smoothed ones (the
        flags and the aids' diagnostics are the forward pass's in both). None otherwise.
    smoother : dict or None
        With ``smooth=True``: what the backward pass held, ``bytes`` (the one allocation),
        ``records``, ``capacity``, ``segment``, ``record_bytes``, and its ``status``.
    """

    #: Flag table of the filter: name -> bit.
    FLAGS: ClassVar[dict] = {}

    filter: str
    t: np.ndarray
    quat: np.ndarray
    bias: np.ndarray
    sigma: np.ndarray | None
    flags: np.ndarray
    aids: dict = field(default_factory=dict)
    skipped_rows: dict = field(default_factory=dict)
    sigma_names: tuple = ()
    forward: FilterResult | None = None
    smoother: dict | None = None

    @property
    def smoothed(self) -> bool:
        """True when the estimates are the smoothed ones (``run(..., smooth=True)``)."""
        return self.forward is not None

    def __len__(self) -> int:
        return len(self.t)

    @property
    def euler(self) -> np.ndarray:
        """(N, 3) ZYX Euler angles [roll, pitch, yaw], rad (NaN where :attr:`quat` is NaN)."""
        out = np.full((len(self.quat), 3), np.nan)
        ok = np.isfinite(self.quat).all(axis=1)
        if ok.any():
            out[ok] = Q.to_euler(self.quat[ok])
        return out

    def flag(self, name: str) -> np.ndarray:
        """Boolean (N,) array: where flag ``name`` (a key of :attr:`FLAGS`) is set."""
        try:
            bit = self.FLAGS[name]
        except KeyError:
            raise KeyError(f"{name!r}: not a flag of {self.filter}{V.did_you_mean(name, self.FLAGS)}; "
                           f"known: {', '.join(self.FLAGS)}") from None
        return (self.flags & bit) != 0

    def flags_seen(self) -> list:
        """Names of the flags set in at least one sample."""
        any_ = int(np.bitwise_or.reduce(self.flags.astype(np.uint64))) if len(self.flags) else 0
        return [n for n, b in self.FLAGS.items() if any_ & b]

    def _columns(self) -> dict:
        cols = {}
        for i, c in enumerate("wxyz"):
            cols[f"q_{c}"] = self.quat[:, i]
        for i, c in enumerate(("roll", "pitch", "yaw")):
            cols[c] = self.euler[:, i]
        for i, c in enumerate("xyz"):
            cols[f"bias_{c}"] = self.bias[:, i]
        return cols

    def to_dataframe(self):
        """pandas DataFrame indexed by ``t``, one row per IMU sample: quaternion ``q_w..q_z``,
        ``roll, pitch, yaw`` (rad), ``bias_x..z`` (rad/s), the filter's further estimates,
        ``sigma_<state>`` and ``flags``. Needs pandas (``pip install 'quatnav[io]'``); the aids'
        tables: ``r.aids[name].to_dataframe()``."""
        pd = _pandas()
        cols = self._columns()
        if self.sigma is not None:
            for i, c in enumerate(self.sigma_names):
                cols[f"sigma_{c}"] = self.sigma[:, i]
        cols["flags"] = self.flags
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))

    def __repr__(self) -> str:
        n = len(self.t)
        span = _span(self.t) if n else "empty"
        aids = ", ".join(f"{k}: {len(v.t)}" for k, v in self.aids.items()) or "none"
        flags = ", ".join(self.flags_seen()) or "none"
        kind = "smoothed, " if self.smoothed else ""
        return (f"<{type(self).__name__} of {self.filter}: {kind}{n} samples, {span}; aids {aids}; "
                f"flags seen: {flags}>")


def _span(t) -> str:
    """``t 12.5..140 s`` for times from zero; for absolute times (a GPS or Unix epoch) to the
    millisecond with the duration: ``t 1756402000.000..1756402134.500 s (134.5 s)``."""
    t0, t1 = float(t[0]), float(t[-1])
    if max(abs(t0), abs(t1)) < 1e5:
        return f"t {t0:.6g}..{t1:.6g} s"
    return f"t {t0:.3f}..{t1:.3f} s ({t1 - t0:.6g} s)"


@dataclass(repr=False, eq=False)
class NavResult(FilterResult):
    """Output of a navigation filter's ``run``: the fields of :class:`FilterResult` and

    Attributes
    ----------
    velocity : (N, 3) ndarray
        NED velocity of the IMU, m/s.
    acc_bias : (N, 3) ndarray
        Accelerometer bias estimate, m/s^2.
    position : (N, 3) ndarray or None
        Geodetic position of the IMU ``[lat (rad), lon (rad), h (m)]`` where the filter estimates
        it (GpsInsFilter); None otherwise.
    att_sigma : (N, 3) ndarray or None
        One-sigma of the attitude error, rad (body-frame rotation vector for NavFilter13; the
        NED psi angles are the ``sigma`` columns of GpsInsFilter).
    """

    velocity: np.ndarray | None = None
    acc_bias: np.ndarray | None = None
    position: np.ndarray | None = None
    att_sigma: np.ndarray | None = None

    @property
    def lat(self) -> np.ndarray | None:
        """(N,) latitude, rad (None without :attr:`position`)."""
        return None if self.position is None else self.position[:, 0]

    @property
    def lon(self) -> np.ndarray | None:
        """(N,) longitude, rad."""
        return None if self.position is None else self.position[:, 1]

    @property
    def h(self) -> np.ndarray | None:
        """(N,) height above the ellipsoid, m."""
        return None if self.position is None else self.position[:, 2]

    def _columns(self) -> dict:
        cols = {}
        if self.position is not None:
            cols.update(lat=self.position[:, 0], lon=self.position[:, 1], h=self.position[:, 2])
        for i, c in enumerate("ned"):
            cols[f"v_{c}"] = self.velocity[:, i]
        cols.update(super()._columns())
        for i, c in enumerate("xyz"):
            cols[f"acc_bias_{c}"] = self.acc_bias[:, i]
        return cols


# ------------------------------------------------------------------------------------------------
# Parameters
# ------------------------------------------------------------------------------------------------
class Filter:
    """Machinery of every filter class: parameters from the class's table (keyword-only
    signature, checks, the map to the C++ names), ``params``, ``repr``, ``get_state``/``set_state``."""

    #: The parameter table (a tuple of :class:`Param`), one per filter in ``quatnav.filters.tables``.
    PARAMS: tuple = ()
    #: The flag table of the results.
    FLAGS: dict = {}
    _core_params: str = ""

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        if not cls.PARAMS:
            return
        params = [inspect.Parameter(p.name, inspect.Parameter.KEYWORD_ONLY, default=p.default) for p in cls.PARAMS]
        params.append(inspect.Parameter("dtype", inspect.Parameter.KEYWORD_ONLY, default=np.float64))
        sig = inspect.Signature([inspect.Parameter("self", inspect.Parameter.POSITIONAL_OR_KEYWORD)] + params)

        def __init__(self, *args, **kwargs):
            Filter.__init__(self, *args, **kwargs)

        __init__.__signature__ = sig
        __init__.__qualname__ = f"{cls.__name__}.__init__"
        cls.__init__ = __init__
        cls.__signature__ = inspect.Signature(params)
        cls.__doc__ = (cls.__doc__ or "").rstrip() + "\n\n" + _params_doc(cls.PARAMS)
        __init__.__doc__ = cls.__doc__

    def __init__(self, *args, dtype=np.float64, **params):
        cls = type(self).__name__
        if args:
            raise TypeError(f"{cls}: parameters are keyword-only (e.g. {cls}({self.PARAMS[0].name}=...)); "
                            f"got {len(args)} positional argument(s)")
        table = {p.name: p for p in self.PARAMS}
        unknown = [k for k in params if k not in table]
        if unknown:
            raise TypeError(f"{cls}: unknown parameter {unknown[0]!r}{V.did_you_mean(unknown[0], table)}; "
                            f"known: {', '.join(table)}")
        self.dtype = V.resolve_dtype(dtype)
        self._given = {k: table[k].check(v, self.dtype) for k, v in params.items()}
        self._opts = {p.name: self._given.get(p.name, p.default) for p in self.PARAMS if p.core_name is None}
        self._f = self._make(self._core_struct())

    def _core_struct(self, start=None):
        p = start if start is not None else compiled(self._core_params, self.dtype)()
        for q in self.PARAMS:
            if q.core_name is not None and q.name in self._given:
                setattr(p, q.core_name, self._given[q.name])
        return p

    def _make(self, p):  # pragma: no cover - every filter defines it
        raise NotImplementedError

    @property
    def params(self) -> dict:
        """Every parameter's current value, by the Python name."""
        p = self._f.params
        out = {}
        for q in self.PARAMS:
            if q.core_name is None:
                out[q.name] = self._opts[q.name]
            else:
                v = getattr(p, q.core_name)
                out[q.name] = np.array(v, dtype=float) if q.kind in ("vec3", "mat3") else v
        return out

    def __repr__(self) -> str:
        table = {p.name: p for p in self.PARAMS}
        args = [f"{k}={v.tolist() if isinstance(v, np.ndarray) else v!r}" for k, v in getattr(self, "_given", {}).items()
                if not table[k].same(v, table[k].default)]
        if getattr(self, "dtype", np.float64) != np.float64:
            args.append(f"dtype=np.{self.dtype.name}")
        return f"{type(self).__name__}({', '.join(args)})"

    @property
    def initialized(self) -> bool:
        return bool(self._f.initialized)

    def get_state(self) -> dict:
        """A copy of the complete state; :meth:`set_state` restores it exactly."""
        return {k: (np.array(v) if isinstance(v, np.ndarray) else v) for k, v in self._f.get_state().items()}

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state` (of this or another filter of the same class)."""
        if not isinstance(state, dict):
            raise TypeError(f"state: expected a dict from get_state(), got {type(state).__name__}")
        own = self._f.get_state()
        other = "a state of another filter or configuration (paper=, scale_factors=)?"
        missing = [k for k in own if k not in state]
        if missing:
            raise ValueError(f"state: missing keys {missing} for {self!r}: {other}")
        for k, v in own.items():
            if isinstance(v, np.ndarray) and np.shape(state[k]) != v.shape:
                raise ValueError(f"state: {k} has shape {np.shape(state[k])}, {self!r} has {v.shape}: {other}")
        status = self._f.set_state(state)
        if status != "ok":
            raise ValueError(f"state: refused ({status})")

    # A filter is its parameters and its state: pickle, copy.copy and copy.deepcopy rebuild it from
    # them, each copy with its own compiled filter (a shallow copy sharing it would run both).
    def __getstate__(self) -> dict:
        return {"params": dict(self._given), "dtype": self.dtype.name, "state": self.get_state()}

    def __setstate__(self, d: dict) -> None:
        type(self).__init__(self, dtype=d["dtype"], **d["params"])
        self.set_state(d["state"])


def _params_doc(params) -> str:
    """The numpydoc ``Parameters`` section of a parameter table."""
    lines = ["    Parameters", "    ----------"]
    for p in params:
        d = p.default
        default = repr(list(d)) if isinstance(d, tuple) else repr(d)
        kind = {"bool": "bool", "int1": "int", "iter": "int", "vec3": "(3,) array_like",
                "mat3": "(3, 3) or (3,) array_like",
                "choice": "str"}.get(p.kind, "float")
        unit = "" if p.unit in ("-", "1") else f" [{p.unit}]"
        lines += [f"    {p.name} : {kind}, default {default}", f"        {p.doc[0].upper() + p.doc[1:]}{unit}."]
    lines += ["    dtype : {numpy.float64, numpy.float32}, default numpy.float64",
              "        Precision of the C++ filter.", ""]
    return "\n".join(lines)


def check_imu_order(gyr, acc):
    """``gyr``, after refusing the argument order of the old navigation APIs (times first): a
    one-dimensional first argument is a TypeError naming it."""
    try:
        nd = np.ndim(gyr)
    except Exception:  # noqa: BLE001 - left to the array checks, which name the argument
        return gyr
    if nd == 1:
        raise TypeError(f"gyr: expected the (N, 3) angular rate, got shape {np.shape(gyr)}; the IMU comes first, "
                        "gyroscope then accelerometer, times as keywords: run(gyr, acc, *, t=... or dt=...)")
    return gyr


def marg_inputs(gyr, acc, mag, dtype, strict: bool):
    """The (N, 3) gyro, accelerometer and optional magnetometer of an attitude filter's run, checked
    once for every attitude filter: the IMU order, shapes and dtype, finite rows when ``strict``
    (magnetometer rows may be all-NaN: no sample), and no zero-norm acc or mag row."""
    g = V.vectors(check_imu_order(gyr, acc), "gyr", dtype=dtype, finite=strict)
    n = g.shape[0]
    a = V.vectors(acc, "acc", n=n, dtype=dtype, finite=strict)
    m = None
    if mag is not None:
        m = V.vectors(mag, "mag", n=n, dtype=dtype, finite=strict, allow_nan_rows=True)
    check_swapped(g, a)
    if strict:
        V.nonzero_rows(a, "acc")
        if m is not None:
            V.nonzero_rows(m, "mag")
    return g, a, m


def check_swapped(g: np.ndarray, a: np.ndarray) -> None:
    """Refuse specific force in the gyro's place (the order of the old navigation APIs): a TypeError
    when the median |gyr| reads as gravity in m/s^2 and the median |acc| as a rate."""
    if not len(g):
        return
    # A median over at most 4,096 evenly spaced rows: the test reads the sensors' typical
    # magnitudes, which such a sample gives as well as the whole log (all rows cost 27 ns per
    # sample, a twentieth of QuaternionEKF's batch run). Norms in float64 by einsum, without
    # float64 copies of the inputs.
    step = -(-len(g) // 4096)
    gs, as_ = g[::step], a[::step]
    with np.errstate(invalid="ignore", over="ignore"):
        ng = np.sqrt(np.einsum("ij,ij->i", gs, gs, dtype=np.float64))
        na = np.sqrt(np.einsum("ij,ij->i", as_, as_, dtype=np.float64))
        ng, na = ng[np.isfinite(ng)], na[np.isfinite(na)]
    # Gravity within 10 %, and a rate below 3 rad/s where the specific force should be (in m/s^2
    # or in g): a gyro whose median reads 9-10.8 rad/s with such an accelerometer is swapped.
    if ng.size and na.size and 8.8 < np.median(ng) < 10.8 and np.median(na) < 3.0:
        raise TypeError(f"gyr: median norm {np.median(ng):.3g} (rad/s) looks like specific force in m/s^2 and "
                        f"acc's {np.median(na):.3g} like an angular rate: the order is run(gyr, acc, ...), "
                        "gyroscope first")


def check_run_inputs(filt, gyr, acc, *, steps=None, t=None, axes: str = "up", rotation=None, rotation_fix=None,
                     increments: bool = False) -> None:
    """The plausibility checks of a filter's IMU input (:func:`quatnav.plausibility.check_imu`:
    units, axes, saturation, rate and gaps, on a sample of the rows), issued as warnings of their
    category to the caller of ``run``; the filter's ``gyro_range``, ``acc_range`` and ``max_dt``
    tell which samples it handles itself."""
    from ..plausibility.imu import warn_imu
    p = filt._f.params
    warn_imu(gyr, acc, steps=steps, t=t, where=f"{type(filt).__name__}.run", axes=axes, rotation=rotation,
             rotation_fix=rotation_fix, increments=increments, gyro_range=float(getattr(p, "gyro_range", 0.0)),
             acc_range=float(getattr(p, "acc_range", 0.0)), max_dt=float(getattr(p, "max_dt", np.inf)))


def no_mag(mag, filter_name: str) -> None:
    if mag is not None:
        raise TypeError(f"mag: {filter_name} takes no magnetometer; the times are keywords: run(gyr, acc, *, t=...)")


def times_of(n: int, t, steps) -> np.ndarray:
    """The result's times: ``t`` as given, or 0 and the cumulated steps after the first."""
    if t is not None:
        return np.asarray(t, dtype=np.float64)
    s = np.asarray(steps, dtype=np.float64)
    return np.concatenate([[0.0], np.cumsum(s[1:])]) if n else np.zeros(0)


def skipped_imu_rows(flags, table, names=("predict_skipped", "saturated"), drop_first=False) -> dict:
    out = {}
    for name in names:
        rows = np.flatnonzero(flags & table[name])
        if drop_first:
            rows = rows[rows > 0]
        if rows.size:
            out[name] = rows
    return out


def smoother_info(info) -> dict:
    """The compiled smoother's report as a plain dict. A run in which the filter never had an
    estimate ("nothing_to_smooth") keeps the forward result; a backward pass that could not run
    (the record's capacity exceeded: a bug) is a RuntimeError naming the reason."""
    d = dict(info)
    if d["status"] not in ("ok", "nothing_to_smooth"):
        raise RuntimeError(f"smooth: the backward pass did not run ({d['status']})")
    return d
