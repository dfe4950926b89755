"""What the consistency tests share: a filter run with its noise scaled, and chi-square bounds
sized for power.

Every consistency test (NEES, NIS, error against the filter's own sigma) must fail for a filter
1.5x over-confident and for one 1.5x under-confident, and pass for the true one. A test builds
its filter through :func:`scaled` (constructor parameters), :func:`scaled_sigma` (a one-sigma
given per measurement or an initial one) and :func:`scaled_covariance` (an initial covariance);
each multiplies every variance the filter is told -- process noise Q, measurement noise R and
the initial covariance P0 -- by the factor c of the environment variable
``QUATNAV_TEST_VARIANCE_SCALE`` (default 1: the truth). For a linear filter, Q, R and P0 all
times c give the same estimates with c times the covariance, so the NEES is exactly 1/c times
the true filter's: c = 1/1.5 is a filter 1.5x over-confident (NEES 1.5x too large), c = 1.5 one
1.5x under-confident. ``python3 tools/mutate.py --consistency`` runs every consistency test at
both (each must fail) and at 1 (each must pass).

    from _consistency import scaled, scaled_covariance
    flt = quatnav.NavFilter13(**scaled("NavFilter13", acc_noise=a, gyro_noise=g))
    flt.reset(v0, q0, ba0, bg0, scaled_covariance(P0), lat=..., lon=..., h=...)

The chi-square helpers size a Monte Carlo for that power: :func:`chi2_interval` is the two-sided
acceptance interval of a mean of normalized errors squared, :func:`power` the probability that
it rejects a filter whose covariance is off by a factor, :func:`required_dof` the degrees of
freedom a test needs for a given power. Samples of one run are correlated (a bias error persists
over the whole run): count a run's samples as ``m_eff`` independent ones only where that is
measured, else as one (:func:`check_mean_nees`).
"""
from __future__ import annotations

import math
import os

import numpy as np

VARIANCE_SCALE_ENV = "QUATNAV_TEST_VARIANCE_SCALE"

#: Parameters whose name says noise or one-sigma but that are not a variance the filter is told
#: (a threshold; a number of the filter's own one-sigmas): never scaled.
NOT_NOISE = frozenset({"acc_lp_bias_sigma", "mag_dip_sigmas"})


def variance_scale() -> float:
    """The factor c on every variance (``QUATNAV_TEST_VARIANCE_SCALE``, default 1)."""
    text = os.environ.get(VARIANCE_SCALE_ENV, "").strip()
    if not text:
        return 1.0
    c = float(text)
    if not (math.isfinite(c) and c > 0):
        raise ValueError(f"{VARIANCE_SCALE_ENV}={text!r}: expected a positive number")
    return c


def noise_params(filter_name: str) -> tuple[str, ...]:
    """The parameters of a filter (``quatnav.<filter_name>``) that are a noise density or a
    one-sigma value: its Q (``*_noise``), R (``*_sigma``, ``*_sigma_h``, ``*_sigma_min``, ...)
    and P0 (``init_*_sigma``, ``lever_arm_sigma``, ...)."""
    from quatnav.filters.tables import PARAM_TABLES
    return tuple(p.name for p in PARAM_TABLES[filter_name]
                 if (p.name.endswith("_noise") or p.name.endswith("_sigma") or "_sigma_" in p.name)
                 and p.name not in NOT_NOISE)


def scaled(filter_name: str, c: float | None = None, **params) -> dict:
    """Constructor keywords of ``quatnav.<filter_name>``: ``params`` with every noise parameter
    (given, or the default) times sqrt(c) (its variance times c); c defaults to
    :func:`variance_scale`."""
    from quatnav.filters.tables import PARAM_TABLES
    c = variance_scale() if c is None else c
    defaults = {p.name: p.default for p in PARAM_TABLES[filter_name]}
    unknown = set(params) - set(defaults)
    if unknown:
        raise TypeError(f"{filter_name}: unknown parameters {sorted(unknown)}")
    out = dict(params)
    for name in noise_params(filter_name):
        out[name] = float(out.get(name, defaults[name])) * math.sqrt(c)
    return out


def scaled_sigma(sigma, c: float | None = None):
    """A one-sigma value (or array) times sqrt(c)."""
    c = variance_scale() if c is None else c
    return np.asarray(sigma, float) * math.sqrt(c) if np.ndim(sigma) else float(sigma) * math.sqrt(c)


def scaled_covariance(P, c: float | None = None) -> np.ndarray:
    """A covariance times c."""
    c = variance_scale() if c is None else c
    return np.asarray(P, float) * c


# ------------------------------------------------------------------------------------------------
# Chi-square bounds and their power.
# ------------------------------------------------------------------------------------------------
def chi2_interval(n: float, alpha: float = 0.01) -> tuple[float, float]:
    """Two-sided 1 - alpha interval of X / n for X ~ chi-square with n degrees of freedom: the
    bounds of a mean of normalized errors squared per degree of freedom (NEES / dof) over samples
    worth n independent degrees of freedom."""
    from scipy.stats import chi2
    lo, hi = chi2.ppf([alpha / 2, 1 - alpha / 2], n) / n
    return float(lo), float(hi)


def power(n: float, factor: float = 1.5, alpha: float = 0.01) -> float:
    """Probability that :func:`chi2_interval` (n, alpha) rejects a filter whose covariance is off
    by ``factor``, the smaller of the over-confident (NEES x factor) and the under-confident
    (NEES / factor) case."""
    from scipy.stats import chi2
    lo, hi = chi2_interval(n, alpha)
    over = chi2.sf(hi * n / factor, n) + chi2.cdf(lo * n / factor, n)
    under = chi2.sf(hi * n * factor, n) + chi2.cdf(lo * n * factor, n)
    return float(min(over, under))


def required_dof(factor: float = 1.5, alpha: float = 0.01, beta: float = 0.01) -> int:
    """The fewest degrees of freedom n for which :func:`power` (n, factor, alpha) >= 1 - beta
    (factor 1.5, alpha = beta = 0.01: n = 296)."""
    lo, hi = 1, 1
    while power(hi, factor, alpha) < 1 - beta:
        lo, hi = hi, 2 * hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if power(mid, factor, alpha) < 1 - beta else (lo, mid)
    return hi


def check_mean_nees(nees, dof: int, m_eff: float = 1.0, alpha: float = 0.01, factor: float = 1.5,
                    beta: float = 0.01, what: str = "NEES") -> float:
    """Assert that the mean of ``nees`` (runs x samples, each of ``dof`` degrees of freedom) lies
    in the chi-square interval, counting each run as ``m_eff`` independent samples (1 when the
    samples of a run may be fully correlated, the conservative count), and that the test has the
    power 1 - beta against a covariance off by ``factor`` (else the design is too small: more
    runs). Returns the mean NEES / dof."""
    nees = np.atleast_2d(np.asarray(nees, float))
    runs = nees.shape[0]
    n = runs * m_eff * dof
    p = power(n, factor, alpha)
    assert p >= 1 - beta, (f"{what}: {runs} runs x {m_eff:g} independent samples x {dof} dof = {n:g} dof have power "
                           f"{p:.3f} < {1 - beta} against a factor {factor}: need {required_dof(factor, alpha, beta)}")
    lo, hi = chi2_interval(n, alpha)
    s = float(np.mean(nees)) / dof
    assert np.isfinite(s) and lo < s < hi, (
        f"{what}: mean / dof = {s:.3f} outside [{lo:.3f}, {hi:.3f}] ({runs} runs x {m_eff:g} x {dof} dof, "
        f"two-sided {1 - alpha:.0%}; variance scale {variance_scale():g})")
    return s
