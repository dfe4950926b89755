"""quatnav: attitude and inertial-navigation filters.

Conventions: Hamilton quaternions ``[w, x, y, z]``; ``q_nb`` rotates body vectors into the
navigation frame (NED); SI units and radians; Euler angles ZYX ``[roll, pitch, yaw]``. See
:mod:`quatnav.core.quaternion`.
"""
import importlib

from . import core, datasets, evaluation  # noqa: F401  (numpy core, dataset loaders, BROAD metrics)
from .filters._base import Aid, AidResult, AidWarning, FilterResult
from .filters.tables import FLAGS, Flag, Status
from .filters.attitude import AttitudeResult, EulerEKF, QuaternionEKF
from .filters.marg import MargFilter, MargResult
from .filters._base import NavResult
from .filters.nav13 import NavFilter13, NavFilter13Result
from .filters.gpsins import GpsInsFilter, GpsInsResult, NavigationWarning
from .plausibility.categories import (AxesWarning, ClockWarning, GapWarning, PlausibilityWarning, RateWarning,
                                      SaturationWarning, UnitWarning)



def __getattr__(name):
    # The compiled module loads when a filter is first used (or when asked for here), so that the
    # numpy parts import without it.
    if name == "_core":
        return importlib.import_module("quatnav._core")
    if name == "__version__":
        return importlib.import_module("quatnav._core").__version__
    raise AttributeError(f"module 'quatnav' has no attribute {name!r}")


__all__ = ["Aid", "AidResult", "AidWarning", "FilterResult", "QuaternionEKF", "EulerEKF", "AttitudeResult", "FLAGS", "Flag", "Status", "core", "__version__"]
__all__ += ["MargFilter", "MargResult"]
__all__ += ["NavFilter13", "NavFilter13Result", "NavResult"]
__all__ += ["GpsInsFilter", "GpsInsResult", "NavigationWarning"]
__all__ += ["PlausibilityWarning", "UnitWarning", "AxesWarning", "ClockWarning", "RateWarning", "GapWarning",
            "SaturationWarning"]
