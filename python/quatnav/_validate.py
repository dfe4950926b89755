"""Input validation shared by every Python entry point.

Each helper raises ``TypeError`` (not numeric) or ``ValueError`` (shape, length, values) with
a message that names the argument and, for batch input, the first offending row.
"""
from __future__ import annotations

import difflib
import importlib
import numbers

import numpy as np

ON_INVALID = ("raise", "skip")


def num(x) -> str:
    """A number as it should read in a message: ``4000.0``, not ``np.float64(4000.0)``."""
    if isinstance(x, (bool, np.bool_)):
        return str(bool(x))
    if isinstance(x, (numbers.Integral, np.integer)):
        return str(int(x))
    if isinstance(x, (numbers.Real, np.floating)):
        return repr(float(x))
    return repr(x)


def did_you_mean(name, known) -> str:
    """`` (did you mean 'x'?)`` naming the known names closest to a mistyped ``name``, or ``""``."""
    close = difflib.get_close_matches(str(name), list(known), n=2, cutoff=0.75)
    return f" (did you mean {' or '.join(map(repr, close))}?)" if close else ""


def resolve_dtype(dtype) -> np.dtype:
    try:
        dt = np.dtype(dtype)
    except TypeError as exc:
        raise TypeError(f"dtype: expected float32 or float64, got {dtype!r}") from exc
    if dt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise TypeError(f"dtype: expected float32 or float64, got {dt}")
    return dt


def _numeric(x, name: str) -> np.ndarray:
    if isinstance(x, (str, bytes)):
        raise TypeError(f"{name}: expected a numeric array, got {type(x).__name__}")
    try:
        a = np.asarray(x)
    except Exception as exc:  # ragged lists and the like
        raise ValueError(f"{name}: cannot be converted to an array ({exc})") from exc
    if a.dtype.kind in "mM":  # numpy counts timedelta64 as a number: its ticks would be taken for seconds
        how = ("(t - t0) / np.timedelta64(1, 's') with one t0 for the IMU and its aids" if a.dtype.kind == "M"
               else "t / np.timedelta64(1, 's')")
        raise TypeError(f"{name}: values of dtype {a.dtype} are not accepted: give seconds as floats, e.g. {how}")
    if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool):
        raise TypeError(f"{name}: expected a numeric array, got dtype {a.dtype}")
    if np.iscomplexobj(a):
        raise TypeError(f"{name}: complex values are not accepted")
    return a


def first_bad_row(a: np.ndarray) -> int | None:
    """Index of the first row of ``a`` with a non-finite value, or None."""
    if a.dtype.kind == "f" and np.isfinite(np.add.reduce(a, axis=None)):
        return None  # a NaN or infinity makes the sum non-finite (an overflow takes the long way)
    bad = ~np.isfinite(a)
    if a.ndim > 1:
        bad = bad.reshape(a.shape[0], int(np.prod(a.shape[1:]))).any(axis=1)  # also for 0 rows
    idx = np.flatnonzero(bad)
    return int(idx[0]) if idx.size else None


def vectors(x, name: str, cols: int = 3, n: int | None = None, dtype=np.float64,
            finite: bool = True, allow_nan_rows: bool = False, like: str = "gyr") -> np.ndarray:
    """Check an (N, cols) array and return it C-contiguous in ``dtype``.

    ``n``: the rows expected, as many as the argument named ``like`` has (for the message).
    ``finite``: raise on the first row with NaN/inf. ``allow_nan_rows``: rows that are entirely
    NaN are allowed (they mean "no sample") while partly-NaN or infinite rows still raise.
    """
    a = _numeric(x, name)
    if a.ndim != 2 or a.shape[1] != cols:
        raise ValueError(f"{name}: expected shape (N, {cols}), got {a.shape}")
    if n is not None and a.shape[0] != n:
        raise ValueError(f"{name}: expected {n} rows (as many as {like}), got {a.shape[0]}")
    if a.shape[0] == 0:
        raise ValueError(f"{name}: no samples")
    a = np.ascontiguousarray(a, dtype=dtype)
    if finite:
        check = a
        if allow_nan_rows and np.isfinite(np.add.reduce(a, axis=None)):
            pass  # no NaN or infinity at all (the fast path of the test below)
        elif allow_nan_rows:
            allnan = np.isnan(a).all(axis=1)
            check = a[~allnan]
            rows = np.flatnonzero(~allnan)
            r = first_bad_row(check)
            if r is not None:
                raise ValueError(f"{name}: non-finite value in row {int(rows[r])}: {a[rows[r]]}")
        else:
            r = first_bad_row(check)
            if r is not None:
                raise ValueError(f"{name}: non-finite value in row {r}: {a[r]}")
    return a


def nonzero_rows(a: np.ndarray, name: str) -> None:
    """Raise on the first row with (near) zero norm: at most sqrt(tiny) of its dtype. Rows with a
    non-finite norm (NaN, infinity) are not this test's concern and are left out."""
    if a.ndim == 2 and a.shape[1] == 3 and a.dtype in (np.float32, np.float64) and a.flags.c_contiguous:
        # One compiled pass without temporaries (about 1 ns per row against 6 for the norms below).
        r = importlib.import_module("quatnav._core").first_zero_norm_row(a)
        if r >= 0:
            raise ValueError(f"{name}: zero-norm vector in row {r}")
        return
    norms = np.sqrt(np.einsum("ij,ij->i", a, a))  # np.linalg.norm(a, axis=1), without its temporaries
    idx = np.flatnonzero(norms <= np.finfo(a.dtype).tiny ** 0.5)  # NaN compares False
    if idx.size:
        raise ValueError(f"{name}: zero-norm vector in row {int(idx[0])}")


def vector(x, name: str, size: int = 3, dtype=np.float64, nonzero: bool = False) -> np.ndarray:
    """Check one vector of ``size`` finite values."""
    a = _numeric(x, name)
    if a.shape != (size,):
        raise ValueError(f"{name}: expected shape ({size},), got {a.shape}")
    a = np.ascontiguousarray(a, dtype=dtype)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: non-finite value {a}")
    if nonzero and not np.linalg.norm(a) > 0:
        raise ValueError(f"{name}: zero-norm vector")
    return a


def positive(x, name: str, allow_zero: bool = False) -> float:
    if isinstance(x, bool) or not isinstance(x, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name}: expected a real number, got {type(x).__name__}")
    v = float(x)
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise ValueError(f"{name}: expected a {'non-negative' if allow_zero else 'positive'} finite number, got {num(x)}")
    return v


def angle(x, name: str, limit: float = np.pi) -> float:
    """A finite angle in rad within [-limit, limit]; a value outside (for example degrees
    passed where radians are expected) is refused with a hint."""
    if isinstance(x, bool) or not isinstance(x, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name}: expected an angle in rad (a real number), got {type(x).__name__}")
    v = float(x)
    if not np.isfinite(v) or abs(v) > limit:
        hint = f" (degrees? use np.radians({v:g}))" if np.isfinite(v) and abs(v) <= 360 else ""
        raise ValueError(f"{name}: expected a finite angle in [-{limit:.4g}, {limit:.4g}] rad, got {v:g}{hint}")
    return v


def euler(x, name: str = "euler", dtype=np.float64) -> np.ndarray:
    """ZYX Euler angles [roll, pitch, yaw] in rad: finite, each within [-2 pi, 2 pi] (a larger one was
    most likely given in degrees: refused with a hint)."""
    e = vector(x, name, 3, dtype=dtype)
    big = np.flatnonzero(np.abs(e) > 2 * np.pi)
    if big.size:
        v = float(e[big[0]])
        hint = f" (degrees? use np.radians({e.tolist()}))" if np.all(np.abs(e) <= 360) else ""
        raise ValueError(f"{name}: {('roll', 'pitch', 'yaw')[big[0]]} {v:g} is not an angle in rad{hint}")
    return e


def time_steps(n: int, dt=None, t=None, dtype=np.float64, max_dt: float | None = None) -> np.ndarray:
    """Per-sample step lengths (N,) from a scalar/array ``dt`` or timestamps ``t``.

    With timestamps, ``dt[k] = t[k] - t[k-1]`` and the first step repeats ``t[1] - t[0]``
    (the first sample is taken one period after the state it updates). Timestamps must be
    strictly increasing.
    """
    if (dt is None) == (t is None):
        raise ValueError("dt, t: give exactly one of dt (seconds) or t (timestamps, seconds)")
    if t is not None:
        ta = _numeric(t, "t")
        if ta.shape != (n,):
            raise ValueError(f"t: expected shape ({n},), got {ta.shape}")
        ta = ta.astype(np.float64)
        r = first_bad_row(ta)
        if r is not None:
            raise ValueError(f"t: non-finite value in row {r}")
        d = np.diff(ta)
        bad = np.flatnonzero(~(d > 0))
        if bad.size:
            k = int(bad[0]) + 1
            raise ValueError(f"t: timestamps must be strictly increasing; row {k} ({num(ta[k])}) "
                             f"does not follow row {k - 1} ({num(ta[k - 1])})")
        if n == 1:
            raise ValueError("t: one timestamp gives no step length; pass dt instead")
        steps = np.concatenate([d[:1], d])
    else:
        da = _numeric(dt, "dt")
        if da.ndim == 0:
            v = positive(float(da), "dt")
            steps = np.full(n, v)
        else:
            if da.shape != (n,):
                raise ValueError(f"dt: expected a scalar or shape ({n},), got {da.shape}")
            steps = da.astype(np.float64)
            bad = np.flatnonzero(~(np.isfinite(steps) & (steps > 0)))
            if bad.size:
                raise ValueError(f"dt: expected positive finite steps; row {int(bad[0])} is {num(steps[bad[0]])}")
    if max_dt is not None:
        big = np.flatnonzero(steps > max_dt)
        if big.size:
            raise ValueError(f"{'t' if t is not None else 'dt'}: step {num(steps[big[0]])} s in row {int(big[0])} "
                             f"exceeds max_dt={num(max_dt)} s")
    return np.ascontiguousarray(steps, dtype=dtype)


def on_invalid(value: str) -> str:
    if value not in ON_INVALID:
        raise ValueError(f"on_invalid: expected one of {ON_INVALID}, got {value!r}")
    return value
