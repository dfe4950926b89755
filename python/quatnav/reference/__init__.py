"""Plain numpy implementations of every quatnav filter, written to be read.

They use the same method names as the C++-backed classes and the same algorithm step by step,
so tests run both on the same inputs and compare them (to ~1e-9 in double precision).
"""
from .kalman import kalman_correct
from .attitude import EulerEKF, QuaternionEKF, QuaternionEKFPaper
from .marg import MargFilter
from .nav13 import NavFilter13
from .gpsins import GpsInsFilter

__all__ = ["kalman_correct", "QuaternionEKF", "QuaternionEKFPaper", "EulerEKF"]
__all__ += ["MargFilter"]
__all__ += ["NavFilter13"]
__all__ += ["GpsInsFilter"]
