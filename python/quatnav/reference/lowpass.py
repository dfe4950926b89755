"""The first-order low-passes of the filters' detectors and learned references
(as cpp/include/quatnav/core/lowpass.hpp)."""

from __future__ import annotations

import math

__all__ = ["lowpass_gain", "lowpass", "lowpass_weight"]


def lowpass_gain(dt, tau):
    """The backward-Euler weight dt / (tau + dt) of one step; tau <= 0: no filtering (1)."""
    return dt / (tau + dt) if tau > 0 else 1.0


def lowpass(y, x, dt, tau):
    """One low-pass step y + a (x - y), a = lowpass_gain(dt, tau)."""
    return y + lowpass_gain(dt, tau) * (x - y)


def lowpass_weight(T, tau):
    """The zero-order-hold weight 1 - exp(-T / tau) of one step; tau <= 0: no filtering (1)."""
    return 1.0 - math.exp(-T / tau) if tau > 0 else 1.0
