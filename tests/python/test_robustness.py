"""Arbitrary input through the Python API: every call either raises ValueError/TypeError
naming the argument, or returns finite estimates (a rejected sample is reported in flags).

Property-based (hypothesis): the inputs mix ordinary readings with NaN, +-inf, zeros, huge and
tiny values, repeated and decreasing timestamps and saturated readings.
"""
from __future__ import annotations

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

import quatnav  # noqa: E402
from quatnav import FLAGS  # noqa: E402

SETTINGS = settings(max_examples=60, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

NASTY = [np.nan, np.inf, -np.inf, 0.0, -0.0, 1e300, -1e300, 1e-300, 5e-324, 3.4e38, 1e-45]


def _column(n, typical, draw):
    """n readings near `typical`, with some entries replaced by nasty values."""
    base = np.tile(np.asarray(typical, float), (n, 1))
    noise = draw(hnp.arrays(np.float64, (n, 3), elements=st.floats(-1, 1)))
    a = base + noise * np.linalg.norm(typical) * 0.05
    k = draw(st.integers(0, 3))
    for _ in range(k):
        i, j = draw(st.integers(0, n - 1)), draw(st.integers(0, 2))
        a[i, j] = draw(st.sampled_from(NASTY))
    if draw(st.booleans()):  # a whole row of NaN ("no sample" for mag) or of zeros
        a[draw(st.integers(0, n - 1))] = draw(st.sampled_from([np.nan, 0.0]))
    return a


@st.composite
def logs(draw):
    n = draw(st.integers(1, 40))
    gyr = _column(n, [0.1, -0.05, 0.2], draw)
    acc = _column(n, [0.3, -0.2, -9.8], draw)
    mag = _column(n, [20.0, 2.0, 43.0], draw) if draw(st.booleans()) else None
    if draw(st.booleans()):
        dt = draw(st.sampled_from([0.01, 0.0, -0.01, np.nan, np.inf, 5.0]))
        return gyr, acc, mag, {"dt": dt}
    t = np.cumsum(np.full(n, 0.01))
    if n > 1 and draw(st.booleans()):
        i = draw(st.integers(1, n - 1))
        t[i] = t[i - 1] + draw(st.sampled_from([0.0, -0.01, np.nan, 10.0]))  # repeated, decreasing
    return gyr, acc, mag, {"t": t}


FILTERS = [
    ("QuaternionEKF", dict(gyro_range=20.0, acc_range=150.0)),
    ("EulerEKF", dict(gyro_range=20.0, acc_range=150.0)),
    ("MargFilter", {}),
]


def _check_result(res, n):
    assert np.all(np.isfinite(res.quat)), "non-finite quaternion returned"
    norms = np.linalg.norm(res.quat, axis=1)
    assert np.all(np.abs(norms - 1) < 1e-3)
    assert res.flags.shape == (n,)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("name,params", FILTERS, ids=[f[0] for f in FILTERS])
@pytest.mark.parametrize("on_invalid", ["raise", "skip"])
@SETTINGS
@given(log=logs())
def test_batch_raises_or_stays_finite(name, params, dtype, on_invalid, log):
    gyr, acc, mag, timing = log
    f = getattr(quatnav, name)(dtype=dtype, **params)
    try:
        res = f.run(gyr, acc, mag, on_invalid=on_invalid, **timing)
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        assert msg.split(":")[0].split("[")[0] in {"gyr", "acc", "mag", "dt", "t"}, msg
        return
    _check_result(res, gyr.shape[0])
    if on_invalid == "skip":
        # Every row with a non-finite gyro reading is reported as a skipped predict.
        bad_g = ~np.all(np.isfinite(gyr), axis=1)
        bad_g[0] = False  # the first sample initializes (no predict)
        init_rows = np.flatnonzero(res.flags & FLAGS["initialized"])
        if init_rows.size:
            bad_g[: init_rows[0] + 1] = False
            assert np.all(res.flags[bad_g] & FLAGS["predict_skipped"])


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("name,params", FILTERS[:2], ids=[f[0] for f in FILTERS[:2]])
@SETTINGS
@given(ops=st.lists(st.tuples(st.sampled_from(["predict", "update_acc", "update_mag"]),
                              st.lists(st.sampled_from(NASTY + [0.1, -9.8, 20.0, 43.0, 25.0]),
                                       min_size=3, max_size=3),
                              st.sampled_from([0.01, 0.0, -1.0, np.nan, 1e9])),
                    min_size=1, max_size=30))
def test_steps_refuse_or_keep_state_finite(name, params, dtype, ops):
    f = getattr(quatnav, name)(dtype=dtype, **params)
    f.initialize([0.3, -0.2, -9.8], [20.0, 2.0, 43.0])
    for op, v, dt in ops:
        before = f.get_state()
        try:
            if op == "predict":
                status = f.predict(v, dt)
            else:
                status = getattr(f, op)(v).status
        except (ValueError, TypeError) as exc:
            assert str(exc).split(":")[0] in {"gyr", "acc", "mag", "dt"}, str(exc)
            status = "raised"
        after = f.get_state()
        if status not in ("ok", "rejected"):
            for key, value in before.items():  # refused: state bit for bit as it was
                np.testing.assert_array_equal(np.asarray(after[key]), np.asarray(value), err_msg=key)
        for value in after.values():
            assert np.all(np.isfinite(np.asarray(value, dtype=float)))
        assert np.isfinite(f.quat).all() and abs(np.linalg.norm(f.quat) - 1) < 1e-3
