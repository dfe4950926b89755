"""The compiled classes of ``quatnav._core`` behind the Python filters, named in one place.

Every class is written out for both scalar types, so that a search, an IDE and the type stubs
(``_core/__init__.pyi``) follow it from here; :func:`compiled` is the only lookup. The keys are
the Python names (a filter, its form, or its parameter struct).
"""
from __future__ import annotations

import functools
import importlib

import numpy as np

__all__ = ["compiled"]


@functools.lru_cache(maxsize=1)
def _table() -> dict:
    c = importlib.import_module("quatnav._core")
    return {
        # attitude
        "QuaternionEKF": (c.QuaternionEKF_f64, c.QuaternionEKF_f32),
        "QuaternionEKFPaper": (c.QuaternionEKFPaper_f64, c.QuaternionEKFPaper_f32),
        "QuaternionEKFParams": (c.QuaternionEKFParams_f64, c.QuaternionEKFParams_f32),
        "EulerEKF": (c.EulerEKF_f64, c.EulerEKF_f32),
        "EulerEKFParams": (c.EulerEKFParams_f64, c.EulerEKFParams_f32),
        "MargFilter": (c.MargFilter_f64, c.MargFilter_f32),
        "MargFilterParams": (c.MargFilterParams_f64, c.MargFilterParams_f32),
        # navigation
        "NavFilter13 ekf": (c.NavFilter13Ekf_f64, c.NavFilter13Ekf_f32),
        "NavFilter13 second_order": (c.NavFilter13SecondOrder_f64, c.NavFilter13SecondOrder_f32),
        "NavFilter13 ukf": (c.NavFilter13Ukf_f64, c.NavFilter13Ukf_f32),
        "NavFilter13Params": (c.NavFilter13Params_f64, c.NavFilter13Params_f32),
        "GpsInsFilter": (c.GpsInsFilter_f64, c.GpsInsFilter_f32),
        "GpsInsFilter scale_factors": (c.GpsInsFilterScale_f64, c.GpsInsFilterScale_f32),
        "GpsInsParams": (c.GpsInsParams_f64, c.GpsInsParams_f32),
    }


def compiled(name: str, dtype) -> type:
    """The compiled class ``name`` (a key of the table above) for ``dtype`` (float64 or float32)."""
    f64, f32 = _table()[name]
    return f32 if np.dtype(dtype) == np.float32 else f64
