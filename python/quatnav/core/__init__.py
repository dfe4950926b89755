"""The pure-numpy core: quaternions and rotations (:mod:`~quatnav.core.quaternion`), the WGS-84
Earth model (:mod:`~quatnav.core.earth`) and the NED strapdown mechanization
(:mod:`~quatnav.core.strapdown`), twins of ``cpp/include/quatnav/core/`` and ``nav/strapdown.hpp``;
and the Earth's magnetic declination of the World Magnetic Model (:mod:`~quatnav.core.magnetic`,
through the ``ahrs`` package when it is called), and GPS time against UTC
(:mod:`~quatnav.core.timescales`, the leap seconds).

Importable without the compiled module; :mod:`quatnav.reference`, :mod:`quatnav.sim` and
:mod:`quatnav.datasets` are built on it.
"""
from . import earth, magnetic, quaternion, strapdown, timescales

__all__ = ["earth", "magnetic", "quaternion", "strapdown", "timescales"]
