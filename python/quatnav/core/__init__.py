"""The pure-numpy core: quaternions and rotations (:mod:`~quatnav.core.quaternion`), the WGS-84
Earth model (:mod:`~quatnav.core.earth`) and the NED strapdown mechanization
(:mod:`~quatnav.core.strapdown`), twins of ``cpp/include/quatnav/core/`` and ``nav/strapdown.hpp``.

Importable without the compiled module; :mod:`quatnav.reference`, :mod:`quatnav.sim` and
:mod:`quatnav.datasets` are built on it.
"""
from . import earth, quaternion, strapdown

__all__ = ["earth", "quaternion", "strapdown"]
