"""Sensor noise parameters from the overlapping Allan deviation of a static log, and the filter
parameters they give.

Fits per axis (IEEE Std 952-1997, annex C), on the curve of :func:`quatnav.sim.allan.allan_deviation`:

* white noise ``N`` (ARW for a gyro, VRW for an accelerometer; unit/sqrt(Hz)): a line of slope
  -1/2, ``sigma(tau) = N / sqrt(tau)``, fitted in log space on the taus where the local slope is
  near -1/2 (within 0.2) below the curve's minimum; ``N`` is the line read at tau = 1 s;
* bias instability ``B``: the flat minimum of the curve divided by 0.664 (its tau is reported);
* rate random walk ``K`` (unit/s/sqrt(Hz)): a line of slope +1/2, ``sigma(tau) = K sqrt(tau/3)``,
  fitted where the slope is near +1/2 beyond the minimum; read at tau = 3 s. NaN when the log is
  too short to show that slope. The noise terms are independent, so their Allan variances add:
  each line is fitted on the curve with the other line's variance removed.

Confidence: an Allan deviation estimated from ``n/m`` clusters of ``m`` samples has a relative
standard error of about ``1 / sqrt(2 (n/m - 1))`` (IEEE 952, C.2; the overlapping estimate is
somewhat better). The line fits weight each point by ``n/m - 1`` (the inverse of that relative
variance), and each read-out reports the error of the best-determined point its fit uses (the
smallest tau; neighbouring points are correlated, so the fit is not much better than that).

A log in motion has no meaningful Allan deviation (the motion is signal, and is read as noise,
bias instability and random walk): :func:`motion_evidence` says when a log is evidently not static.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ._toml import dumps

__all__ = ["AxisNoise", "NoiseModel", "noise_parameters", "fit_allan", "motion_evidence", "noise_in_motion",
           "raised_noise", "noise_note", "FILTER_NOISE"]

#: the noise parameters of each filter (``filters/tables.py``): name -> (sensor, term). All are
#: continuous-time densities: ``gyro_noise`` rad/s/sqrt(Hz) = the ARW, ``acc_noise``
#: m/s^2/sqrt(Hz) = the VRW, ``*_bias_noise`` unit/s/sqrt(Hz) = the rate random walk.
#: MargFilter (a complementary filter) has no noise parameters.
FILTER_NOISE = {
    "QuaternionEKF": {"gyro_noise": ("gyro", "white"), "gyro_bias_noise": ("gyro", "bias_rw")},
    "EulerEKF": {"gyro_noise": ("gyro", "white"), "gyro_bias_noise": ("gyro", "bias_rw")},
    "NavFilter13": {"gyro_noise": ("gyro", "white"), "acc_noise": ("acc", "white"),
                    "gyro_bias_noise": ("gyro", "bias_rw"), "acc_bias_noise": ("acc", "bias_rw")},
    "GpsInsFilter": {"gyro_noise": ("gyro", "white"), "acc_noise": ("acc", "white"),
                     "gyro_bias_noise": ("gyro", "bias_rw"), "acc_bias_noise": ("acc", "bias_rw")},
}


def _rel_err(n, m):
    return 1.0 / np.sqrt(2.0 * np.maximum(n / m - 1.0, 1.0))


@dataclass
class AxisNoise:
    """Allan read-outs of one axis, in the signal's unit: ``white`` (/sqrt(Hz)),
    ``bias_instability`` (at ``tau_bias_instability`` s), ``rate_random_walk`` (/s/sqrt(Hz), NaN
    when not seen), and the relative standard error of each (``*_rel_err``).
    ``floor_reached``: False when the deviation still falls at the longest tau of the log, so
    that ``bias_instability`` is only an upper bound (the log is too short to show the floor)."""

    white: float
    white_rel_err: float
    bias_instability: float
    tau_bias_instability: float
    bias_instability_rel_err: float
    rate_random_walk: float
    rate_random_walk_rel_err: float
    floor_reached: bool = True


def fit_allan(taus: ArrayLike, adev: ArrayLike, n_samples: int, rate_hz: float,
              slope_tol: float = 0.2) -> "AxisNoise":
    """The three read-outs of one Allan-deviation curve (see the module doc) as an AxisNoise."""
    taus, adev = np.asarray(taus, float), np.asarray(adev, float)
    lt, la = np.log(taus), np.log(adev)
    slope = np.gradient(la, lt)
    k = np.ones(3) / 3.0
    slope = np.convolve(np.pad(slope, 1, mode="edge"), k, mode="valid")
    i_min = int(np.argmin(adev))
    m = np.round(taus * rate_hz)
    # white: slope -1/2 before the minimum (at least the first points)
    sel = (np.abs(slope + 0.5) < slope_tol) & (np.arange(len(taus)) <= i_min)
    if not sel.any():
        sel = np.arange(len(taus)) < 3
    w = np.maximum(n_samples / m - 1.0, 1.0)  # 1 / relative variance of each point
    sel_k = (np.abs(slope - 0.5) < slope_tol) & (np.arange(len(taus)) > i_min)
    var = adev ** 2
    white, rrw = 0.0, 0.0
    # the terms are independent, so their Allan variances add: each line is fitted on the
    # curve with the other's contribution removed (a few rounds; it converges at once)
    for _ in range(4):
        v = np.maximum(var - rrw ** 2 * taus / 3.0, 0.25 * var)
        white = float(np.exp(np.average(0.5 * np.log(v[sel]) + 0.5 * lt[sel], weights=w[sel])))
        if sel_k.sum() < 2:
            rrw = 0.0
            break
        v = np.maximum(var - white ** 2 / taus, 0.25 * var)
        rrw = float(np.exp(np.average(0.5 * np.log(v[sel_k]) - 0.5 * (lt[sel_k] - np.log(3.0)), weights=w[sel_k])))
    white_err = float(_rel_err(n_samples, m[sel].min()))
    if sel_k.sum() >= 2:
        rrw_err = float(_rel_err(n_samples, m[sel_k].min()))
    else:
        rrw, rrw_err = float("nan"), float("nan")
    return AxisNoise(white, white_err, float(adev[i_min] / 0.664), float(taus[i_min]),
                     float(_rel_err(n_samples, m[i_min])), rrw, rrw_err, floor_reached=i_min < len(taus) - 1)


@dataclass
class NoiseModel:
    """Allan read-outs of a static log: ``gyro`` and ``acc`` lists of 3 :class:`AxisNoise`
    (x, y, z; either may be None), the curves (``taus``, ``adev`` per sensor) and the log's
    ``rate_hz`` and ``duration``."""

    gyro: list | None
    acc: list | None
    rate_hz: float
    duration: float
    curves: dict = field(default_factory=dict)

    def term(self, sensor: str, term: str) -> float:
        """One value for a filter (which takes one density for the three axes): the RMS over the
        axes; the rate random walk replaced by its bias-instability equivalent when not seen."""
        axes = getattr(self, sensor)
        if axes is None:
            return None
        if term == "white":
            return float(np.sqrt(np.mean([a.white ** 2 for a in axes])))
        k = np.array([a.rate_random_walk for a in axes])
        if np.isfinite(k).all():
            return float(np.sqrt(np.mean(k ** 2)))
        # not seen in the log: the random walk whose Allan deviation at the bias-instability tau
        # equals the floor, K sqrt(tau/3) = 0.664 B
        return float(np.sqrt(np.mean([(0.664 * a.bias_instability) ** 2 * 3.0 / a.tau_bias_instability
                                      for a in axes])))

    def bias_source(self, sensor: str) -> str:
        axes = getattr(self, sensor)
        if axes is None:
            return None
        return "rate_random_walk" if all(np.isfinite(a.rate_random_walk) for a in axes) else "bias_instability"

    def filter_params(self) -> dict:
        """``{filter name: {parameter: value}}`` under each filter's own parameter names."""
        out = {}
        for f, table in FILTER_NOISE.items():
            d = {}
            for name, (sensor, term) in table.items():
                v = self.term(sensor, term)
                if v is not None:
                    d[name] = v
            out[f] = d
        return out

    def to_toml(self) -> str:
        params = self.filter_params()
        doc = {"filter": params["GpsInsFilter"], "parameters": params, "allan": {
            "rate_hz": self.rate_hz, "duration_s": self.duration}}
        for s in ("gyro", "acc"):
            axes = getattr(self, s)
            if axes is None:
                continue
            doc["allan"][s] = {k: [getattr(a, k) for a in axes] for k in AxisNoise.__dataclass_fields__}
            doc["allan"][s]["bias_noise_from"] = self.bias_source(s)
        return dumps(doc, header=(
            "quatnav noise parameters from the Allan deviation of a static log\n"
            "[filter]: GpsInsFilter parameters (read by 'quatnav ins run --config FILE')\n"
            "[parameters.NAME]: the same densities under each filter's parameter names; MargFilter has none\n"
            "[allan.gyro], [allan.acc]: per-axis read-outs (x, y, z), SI units; *_rel_err: relative std error"))


def noise_parameters(rate_hz: float, gyr: ArrayLike | None = None, acc: ArrayLike | None = None,
                     points_per_decade: int = 10) -> "NoiseModel":
    """Allan read-outs of a static log (``gyr`` rad/s and/or ``acc`` m/s^2, shape (N, 3), uniform
    rate ``rate_hz``) as a :class:`NoiseModel`."""
    from ..sim.allan import allan_deviation
    if gyr is None and acc is None:
        raise ValueError("give gyr and/or acc")
    out, curves, n = {}, {}, None
    for name, x in (("gyro", gyr), ("acc", acc)):
        if x is None:
            out[name] = None
            continue
        x = np.asarray(x, float)
        if x.ndim != 2 or x.shape[1] != 3 or x.shape[0] < 100:
            raise ValueError(f"{name} must have shape (N, 3) with N >= 100, got {x.shape}")
        n = x.shape[0]
        taus, adev = allan_deviation(x, rate_hz, points_per_decade=points_per_decade)
        curves[name] = (taus, adev)
        out[name] = [fit_allan(taus, adev[:, i], n, rate_hz) for i in range(3)]
    return NoiseModel(out["gyro"], out["acc"], float(rate_hz), n / rate_hz, curves)


#: what a still sensor's 1 s mean does not change by from one second to the next, whatever its
#: grade (:func:`motion_evidence`): gyro rad/s (0.57 deg/s), accelerometer as a fraction of the
#: gravity it measures (0.1 m/s^2, 0.57 deg of tilt)
STILL_STEP = {"gyro": 0.01, "acc": 0.01}


def motion_evidence(t: ArrayLike, gyr: ArrayLike | None = None, acc: ArrayLike | None = None,
                    window: float = 1.0, k: float = 10.0) -> str | None:
    """Why a log is evidently not static, in words, or None when nothing says so.

    The log (``t`` (N,) s; ``gyr`` rad/s, ``acc`` m/s^2, (N, 3)) is cut into blocks of ``window``
    seconds. At rest, the means of consecutive blocks differ by the white noise, whose standard
    deviation per axis is ``sqrt(2) sigma / sqrt(m)`` (``m`` samples a block, ``sigma`` the
    per-sample noise from the sample-to-sample differences), and by the bias's wander, a slow
    process: within a second it stays far below :data:`STILL_STEP` for any grade (bias
    instability from ~0.003 deg/h for a navigation-grade gyro to ~10 deg/h = 0.003 deg/s for a
    consumer MEMS one, 5-100 ug for accelerometers; temperature drifts over minutes). A hand, a
    vehicle or a turntable turns the sensor by degrees per second and accelerates it by tenths of
    m/s^2. A change beyond both ``k`` times its white-noise standard deviation (``k`` = 10: never
    reached by Gaussian noise) and that floor is evidence of motion; the largest is reported.
    """
    t = np.asarray(t, float)
    rate = 1.0 / float(np.median(np.diff(t)))
    m = max(1, int(round(window * rate)))
    nb = len(t) // m
    if nb < 2:
        return None
    worst = None
    for name, x in (("gyro", gyr), ("acc", acc)):
        if x is None:
            continue
        x = np.asarray(x, float)
        d = np.diff(x, axis=0)
        sigma = 1.4826 * np.median(np.abs(d - np.median(d, axis=0)), axis=0)  # robust to a few jumps
        sigma = np.where(sigma > 0, sigma, np.std(d, axis=0)) / np.sqrt(2)   # (a quantized sensor)
        means = x[:nb * m].reshape(nb, m, 3).mean(axis=1)
        step = np.abs(np.diff(means, axis=0))
        floor = STILL_STEP[name] * (float(np.linalg.norm(np.median(means, axis=0))) if name == "acc" else 1.0)
        limit = np.maximum(k * np.sqrt(2.0 / m) * sigma, floor)
        ratio = step / limit
        i, a = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        if ratio[i, a] > 1.0 and (worst is None or ratio[i, a] > worst[0]):
            unit = "rad/s" if name == "gyro" else "m/s^2"
            c = i * m + m // 2  # the centres of the two blocks
            worst = (ratio[i, a], f"the {name} {'xyz'[a]}'s {window:g} s mean changes by {step[i, a]:.3g} {unit} "
                                  f"between t = {t[c]:.1f} s and {t[c + m]:.1f} s (a still sensor's, by at most "
                                  f"{limit[a]:.2g} {unit})")
    return worst[1] if worst else None


def plot_allan(model: NoiseModel, path):
    """Log-log Allan deviation per axis with the fitted -1/2, 0 and +1/2 lines."""
    from .. import _plotting
    sensors = [s for s in ("gyro", "acc") if s in model.curves]
    fig = _plotting.figure((5.2 * len(sensors), 4.0))
    units = {"gyro": "rad/s", "acc": "m/s^2"}
    for k, s in enumerate(sensors):
        ax = fig.add_subplot(1, len(sensors), k + 1)
        taus, adev = model.curves[s]
        for i, axis in enumerate("xyz"):
            a = getattr(model, s)[i]
            line, = ax.loglog(taus, adev[:, i], lw=1.2, label=f"{axis}")
            c = line.get_color()
            ax.loglog(taus, a.white / np.sqrt(taus), "--", color=c, lw=0.7)
            ax.loglog(taus, np.full_like(taus, 0.664 * a.bias_instability), ":", color=c, lw=0.7)
            if np.isfinite(a.rate_random_walk):
                ax.loglog(taus, a.rate_random_walk * np.sqrt(taus / 3.0), "-.", color=c, lw=0.7)
        ax.set_ylim(adev.min() / 3, adev.max() * 3)
        ax.set_xlabel("tau (s)")
        ax.set_ylabel(f"Allan deviation ({units[s]})")
        ax.set_title(f"{s}: white --, bias instability :, rate random walk -.", fontsize=8)
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
    return _plotting.save(fig, path)


def noise_in_motion(t: ArrayLike, gyr: ArrayLike, acc: ArrayLike, window: float = 1.0,
                    smooth: float = 0.1) -> dict:
    """The white-noise densities a log's IMU shows while it runs, vibration included: a car's
    road and engine vibration, aliased into the IMU's band, acts on the filter as noise far above
    a datasheet's (measured at rest on a bench).

    Each axis less its centred ``smooth``-second moving mean (the residual keeps what changes
    faster than ~1/``smooth`` Hz: the sensor's noise and the vibration, not the vehicle's
    manoeuvres) has a per-sample variance in each ``window``-second block; the mean over the three
    axes, the median over the blocks (a typical second of the log: a few shocks do not count),
    corrected for the mean's share of white noise, gives the per-sample sigma and, at the median
    sample interval dt, the density sigma sqrt(dt). Returns ``{"gyro_noise": rad/s/sqrt(Hz),
    "acc_noise": m/s^2/sqrt(Hz), "blocks": int}`` (NaN densities when the log is shorter than two
    blocks). Motion faster than 1/``smooth`` Hz (a walker's steps) counts as noise too, which is
    what it is to a filter without a step model.
    """
    t = np.asarray(t, float)
    dt = float(np.median(np.diff(t))) if len(t) > 1 else float("nan")
    if not (np.isfinite(dt) and dt > 0):
        return {"gyro_noise": float("nan"), "acc_noise": float("nan"), "blocks": 0}
    k = max(3, int(round(smooth / dt)) | 1)  # odd, centred
    m = max(2 * k, int(round(window / dt)))
    out = {"blocks": 0}
    for name, x in (("gyro_noise", gyr), ("acc_noise", acc)):
        x = np.asarray(x, float)
        nb = (len(x) - k + 1) // m
        if nb < 2:
            out[name] = float("nan")
            continue
        c = np.cumsum(np.vstack([np.zeros((1, 3)), x]), axis=0)
        mean = (c[k:] - c[:-k]) / k  # centred on x[k // 2:len(x) - k // 2]
        r = x[k // 2:k // 2 + len(mean)] - mean
        blocks = r[:nb * m].reshape(nb, m, 3).var(axis=1).mean(axis=1)
        var = float(np.median(blocks)) / (1.0 - 1.0 / k)  # white noise: var(x - mean) = (1 - 1/k) sigma^2
        out[name] = float(np.sqrt(var * dt))
        out["blocks"] = nb
    return out


#: raise a given density only when the log's exceeds it by more than this factor: within it the
#: two agree (a datasheet value against the estimate's scatter), and the filter hardly notices
RAISE_ABOVE = 1.2


def raised_noise(given: dict, measured: dict, factor: float = RAISE_ABOVE) -> dict:
    """The white-noise densities of ``measured`` (:func:`noise_in_motion`) that exceed the
    ``given`` ones (``gyro_noise``, ``acc_noise``) by more than ``factor``, by name: the values to
    raise them to. A given value above the log's is kept: it may cover what the log's noise does
    not show (scale-factor and misalignment errors, a deliberately cautious setting)."""
    return {k: float(measured[k]) for k in ("gyro_noise", "acc_noise")
            if np.isfinite(measured.get(k, np.nan)) and measured[k] > factor * float(given[k])}


#: lower a given density only when it exceeds the log's by more than this factor, and then to
#: this factor times the log's. White noise several times what the IMU shows makes the filter
#: follow each fix with its attitude and its gyro bias, and bridge an outage worse (the simulated
#: car, noise x10: 30 s drift 1.6x the defaults'; lowered to 3x the log's 1.3x; to the log's
#: itself 1.5x, worst outage 66 m against 40 m): the margin keeps room for what the log's noise
#: does not show (scale-factor and misalignment errors; the default gyro noise is 1.4x the car's).
LOWER_ABOVE = 3.0


def lowered_noise(given: dict, measured: dict, factor: float = LOWER_ABOVE) -> dict:
    """The white-noise densities (``gyro_noise``, ``acc_noise``) ``given`` more than ``factor``
    times above the log's (:func:`noise_in_motion`), by name: ``factor`` times the log's, the
    values to lower them to."""
    return {k: factor * float(measured[k]) for k in ("gyro_noise", "acc_noise")
            if np.isfinite(measured.get(k, np.nan)) and measured[k] > 0 and float(given[k]) > factor * measured[k]}


def noise_note(given: dict, measured: dict, raised: dict, lowered: dict | None = None) -> str:
    """One line for a run's notes: the noise the log shows and what was raised or lowered."""
    text = (f"IMU noise in the log (vibration included; {measured['blocks']} s): gyro {measured['gyro_noise']:.3g} "
            f"rad/s/sqrt(Hz), accelerometer {measured['acc_noise']:.3g} m/s^2/sqrt(Hz); ")
    if not raised and not lowered:
        return text + (f"the filter's values were kept (not more than {RAISE_ABOVE:g}x below it nor "
                       f"{LOWER_ABOVE:g}x above it)")
    parts = []
    if raised:
        parts.append(f"raised (more than {RAISE_ABOVE:g}x below it): "
                     + ", ".join(f"{k} {float(given[k]):.3g} -> {v:.3g}" for k, v in raised.items()))
    if lowered:
        parts.append(f"lowered to {LOWER_ABOVE:g}x it (more than {LOWER_ABOVE:g}x above it): "
                     + ", ".join(f"{k} {float(given[k]):.3g} -> {v:.3g}" for k, v in lowered.items()))
    return text + "; ".join(parts)
