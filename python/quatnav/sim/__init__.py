"""Scenario generation and sensor simulation.

* :mod:`quatnav.sim.trajectory`: motion segments and waypoints with exact truth
  (:func:`make_trajectory`, :func:`trajectory_from_waypoints`);
* :mod:`quatnav.sim.sensors`: IMU, magnetometer, GPS, altimeter and compass models whose
  parameters are in datasheet units, converted in :mod:`quatnav.sim.units`;
* :mod:`quatnav.sim.scenarios`: named scenarios (:func:`make_scenario`, :func:`list_scenarios`);
  :mod:`quatnav.sim.fast_scenarios` the fast-motion ones of the attitude benchmark
  (:data:`FAST_MOTION`), built from the segments of :mod:`quatnav.sim.motion`;
* :mod:`quatnav.sim.allan`: overlapping Allan deviation and ARW / bias-instability read-outs;
* :mod:`quatnav.sim.io`: ``.npz`` and CSV save/load; :mod:`quatnav.sim.plot`: overview plot.

Conventions as in the rest of quatnav: Hamilton ``[w, x, y, z]``, ``q_nb`` body to NED, body FRD,
SI units and radians, Euler ZYX ``[roll, pitch, yaw]``.
"""

from .allan import AllanReadout, allan_deviation, allan_readout
from .io import load_csv, load_npz, save_csv, save_npz
from .fast_scenarios import FAST_MOTION
from .motion import LimbSwing, Pendulum, Running, Shaking, Vibration
from .scenarios import Scenario, list_scenarios, make_scenario
from .sensors import (AccelSpec, BaroSpec, CompassSpec, GpsSpec, GyroSpec, ImuSpec,
                      MagDisturbance, MagSpec, simulate_baro, simulate_compass, simulate_gps,
                      simulate_imu, simulate_mag)
from .trajectory import (Accelerate, Climb, CoordinatedTurn, Cruise, RandomMotion, Rest, Rotate,
                         Trajectory, Turn, WaypointPath, make_trajectory,
                         trajectory_from_waypoints)


def plot_scenario(scenario, path=None, show=False):
    """Plot a scenario (see :func:`quatnav.sim.plot.plot_scenario`; imports matplotlib)."""
    from .plot import plot_scenario as _plot
    return _plot(scenario, path=path, show=show)


__all__ = [
    "Accelerate", "Climb", "CoordinatedTurn", "Cruise", "RandomMotion", "Rest", "Rotate", "Turn",
    "WaypointPath", "Trajectory", "make_trajectory", "trajectory_from_waypoints",
    "GyroSpec", "AccelSpec", "ImuSpec", "MagSpec", "MagDisturbance", "GpsSpec", "BaroSpec",
    "CompassSpec", "simulate_imu", "simulate_mag", "simulate_gps", "simulate_baro",
    "simulate_compass", "Scenario", "make_scenario", "list_scenarios", "allan_deviation",
    "allan_readout", "AllanReadout", "save_npz", "load_npz", "save_csv", "load_csv",
    "plot_scenario", "FAST_MOTION", "Pendulum", "LimbSwing", "Running", "Shaking", "Vibration",
]
