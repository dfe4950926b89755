"""Save and load scenarios: ``.npz`` (everything) and CSV (documented columns).

NPZ
---
One array per field, named ``<group>.<field>`` (groups ``truth``, ``imu``, ``gps``, ``mag``,
``baro``, ``compass``, ``odometer``), plus ``meta``: a JSON string with name, seed, description,
params, the trajectory's rate and Earth-rate flag, the IMU mounting ``q_b_imu`` and whether the
GNSS fixes are stamped on delivery.

CSV
---
``save_csv(scenario, "run.csv")`` writes

* ``run.csv``: the truth at every trajectory sample, columns :func:`csv_columns` ``("truth")``;
* ``run_imu.csv``, ``run_gps.csv``, ``run_mag.csv``, ``run_baro.csv``, ``run_compass.csv``,
  ``run_odometer.csv`` for the sensors present, columns :func:`csv_columns` ``(group)``;
* ``run_meta.json``: the metadata.

INS input (``quatnav ins run``)
-------------------------------
``save_ins_csv(scenario, "DIR")`` writes the files that ``quatnav ins run`` reads, in its columns
and units (``quatnav ins run -h``), so a simulated run goes through the command line unchanged::

    quatnav simulate paper004_walk --csv run/
    quatnav ins run --imu run/imu.csv --gnss run/gnss.csv --baro run/baro.csv \
                    --compass run/compass.csv --config run/config.toml --out run/out.csv

* ``imu.csv``: ``time`` (s), ``gyro_x gyro_y gyro_z`` (rad/s), ``accel_x accel_y accel_z``
  (m/s^2), the simulated (noisy, biased) IMU in the IMU's own axes (rotated from the body
  when the scenario mounts it rotated: ``scenario.toml`` says how); row k is the mean over
  (time[k-1], time[k]];
* ``gnss.csv``: ``time`` (s: the time of validity, or the delivery time when the scenario's
  receiver stamps fixes on delivery, late by its latency), ``lat lon`` (deg), ``h`` (m) and
  ``v_n v_e v_d`` (m/s) of the antenna, ``sigma_n sigma_e sigma_d`` (m) and
  ``sigma_vn sigma_ve sigma_vd`` (m/s) from the receiver's simulated noise;
* ``baro.csv``: ``time``, ``h`` (m); ``compass.csv``: ``time``, ``heading`` (deg; the simulated
  compass measures true heading, so the configuration leaves ``declination`` at 0);
* ``mag.csv``: ``time``, ``mag_x mag_y mag_z`` (uT, sensor frame); ``odometer.csv``: ``time``,
  ``speed`` (m/s, forward along body x);
* ``config.toml``: ``[filter]`` with the antenna lever arm ``lever_arm_b`` (m);
* ``scenario.toml``: what the scenario knows and a filter may be told: ``[imu]`` the mounting
  (``mounting_rpy_deg``, ZYX deg, and ``C_b_imu``, body from IMU), ``[gnss]`` ``lever_arm_b_m``,
  ``latency_s`` and ``time_stamp`` ("valid" or "delivery"), ``[mag]`` the Earth field
  (``declination_deg``, ``inclination_deg``, ``intensity_uT``) and the magnetometer's
  ``hard_iron_uT`` and ``soft_iron``, ``[events]`` the stops and GNSS outages (s);
* ``truth.csv``: ``time, lat, lon`` (deg), ``h``, ``v_n v_e v_d``, ``roll pitch yaw`` (deg) at
  every trajectory sample: the first columns of ``ins run``'s output, for comparison.

Only the sensors of the scenario are written (a scenario without GPS gives no ``gnss.csv``).

Column names are the field names; vectors get a suffix per component: ``_N, _E, _D`` for
NED vectors (``*_n``), ``_x, _y, _z`` for body vectors (``*_b``) and sensor triads,
``_w, _x, _y, _z`` for quaternions and ``_roll, _pitch, _yaw`` for ``rpy``. Units are SI and
radians as in the in-memory objects (:class:`~quatnav.sim.trajectory.Trajectory` and the
``*Data`` classes of :mod:`quatnav.sim.sensors`).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from .scenarios import Scenario
from .sensors import BaroData, CompassData, GpsData, ImuData, MagData, OdometerData
from .trajectory import Trajectory

__all__ = ["save_npz", "load_npz", "save_csv", "load_csv", "csv_columns", "save_ins_csv", "TRUTH_COLUMNS"]

_TYPES = {"imu": ImuData, "gps": GpsData, "mag": MagData, "baro": BaroData, "compass": CompassData,
          "odometer": OdometerData}
#: fields that are not per-sample arrays: kept in the metadata
_META_FIELDS = ("rate_hz", "earth_rate", "q_b_imu", "stamped_on_delivery")


def _array_fields(cls):
    return [f.name for f in dataclasses.fields(cls) if f.name not in _META_FIELDS]


def _suffixes(name, width):
    if width == 4:
        return ["_w", "_x", "_y", "_z"]
    if name == "rpy":
        return ["_roll", "_pitch", "_yaw"]
    if name.endswith("_n"):
        return ["_N", "_E", "_D"]
    return ["_x", "_y", "_z"][:width] if width <= 3 else [f"_{i}" for i in range(width)]


_WIDTHS = {"pos_n": 3, "v_n": 3, "a_n": 3, "q_nb": 4, "rpy": 3, "omega_nb_b": 3,
           "omega_ib_b": 3, "alpha_nb_b": 3, "f_ib_b": 3, "dtheta_b": 3, "dv_b": 3, "gyro": 3,
           "accel": 3, "gyro_bias": 3, "accel_bias": 3, "mag": 3}


def csv_columns(group):
    """Column names of a CSV file of ``group`` ("truth", "imu", "gps", "mag", "baro", "compass")."""
    cls = Trajectory if group == "truth" else _TYPES[group]
    cols = []
    for name in _array_fields(cls):
        if group == "mag" and name == "field_n":
            continue  # constant: stored in the metadata
        w = _WIDTHS.get(name, 1)
        cols += [name] if w == 1 else [name + s for s in _suffixes(name, w)]
    return cols


def _meta(s: Scenario):
    m = {"name": s.name, "seed": s.seed, "description": s.description, "params": s.params,
         "truth": {"rate_hz": s.truth.rate_hz, "earth_rate": s.truth.earth_rate},
         "imu": {"rate_hz": s.imu.rate_hz, "q_b_imu": np.asarray(s.imu.q_b_imu, float).tolist()}}
    if s.gps is not None:
        m["gps"] = {"stamped_on_delivery": bool(s.gps.stamped_on_delivery)}
    if s.mag is not None:
        m["mag"] = {"field_n": s.mag.field_n.tolist()}
    return m


def _json_default(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.generic):
        return o.item()
    raise TypeError(f"cannot serialize {type(o).__name__}")


def save_npz(scenario: Scenario, path):
    """Write a scenario to ``path`` (.npz, compressed)."""
    arrays = {}
    for f in _array_fields(Trajectory):
        arrays[f"truth.{f}"] = getattr(scenario.truth, f)
    for g in _TYPES:
        obj = getattr(scenario, g)
        if obj is None:
            continue
        for f in _array_fields(type(obj)):
            arrays[f"{g}.{f}"] = getattr(obj, f)
    arrays["meta"] = np.array(json.dumps(_meta(scenario), default=_json_default))
    np.savez_compressed(path, **arrays)


def _build(meta, get):
    truth = Trajectory(**{f: get("truth", f) for f in _array_fields(Trajectory)},
                       rate_hz=float(meta["truth"]["rate_hz"]),
                       earth_rate=bool(meta["truth"]["earth_rate"]))
    sensors = {}
    for g, cls in _TYPES.items():
        if get(g, None) is None:
            continue
        kw = {f: get(g, f) for f in _array_fields(cls)}
        if g == "imu":
            kw["rate_hz"] = float(meta["imu"]["rate_hz"])
            kw["q_b_imu"] = np.asarray(meta["imu"].get("q_b_imu", [1.0, 0.0, 0.0, 0.0]), float)
        if g == "gps":
            kw["stamped_on_delivery"] = bool(meta.get("gps", {}).get("stamped_on_delivery", False))
        sensors[g] = cls(**kw)
    return Scenario(name=meta["name"], seed=int(meta["seed"]), description=meta["description"],
                    truth=truth, params=meta["params"], **sensors)


def load_npz(path) -> Scenario:
    """Read a scenario written by :func:`save_npz`."""
    with np.load(path, allow_pickle=False) as z:
        data = {k: z[k] for k in z.files}
    meta = json.loads(str(data["meta"]))

    def get(group, field):
        if field is None:
            return True if any(k.startswith(group + ".") for k in data) else None
        return data[f"{group}.{field}"]
    return _build(meta, get)


def _paths(path):
    p = Path(path)
    stem = p.with_suffix("")
    return p, {g: Path(f"{stem}_{g}.csv") for g in _TYPES}, Path(f"{stem}_meta.json")


def _to_table(obj, group):
    cls = Trajectory if group == "truth" else _TYPES[group]
    cols = []
    for name in _array_fields(cls):
        if group == "mag" and name == "field_n":
            continue
        a = np.asarray(getattr(obj, name), dtype=float)
        cols.append(a.reshape(a.shape[0], -1))
    return np.hstack(cols)


def save_csv(scenario: Scenario, path):
    """Write a scenario as CSV files (see the module doc for the files and columns)."""
    main, side, meta_path = _paths(path)
    np.savetxt(main, _to_table(scenario.truth, "truth"), delimiter=",",
               header=",".join(csv_columns("truth")), comments="", fmt="%.17g")
    for g in _TYPES:
        obj = getattr(scenario, g)
        if obj is not None:
            np.savetxt(side[g], _to_table(obj, g), delimiter=",",
                       header=",".join(csv_columns(g)), comments="", fmt="%.17g")
    meta_path.write_text(json.dumps(_meta(scenario), default=_json_default, indent=1))


def load_csv(path) -> Scenario:
    """Read a scenario written by :func:`save_csv`."""
    main, side, meta_path = _paths(path)
    meta = json.loads(meta_path.read_text())
    tables = {}

    def read(group, file):
        with open(file) as fh:
            header = fh.readline().strip().split(",")
        if header != csv_columns(group):
            raise ValueError(f"{file}: unexpected columns {header[:4]}...; expected {csv_columns(group)[:4]}...")
        tables[group] = np.atleast_2d(np.loadtxt(file, delimiter=",", skiprows=1, ndmin=2))

    read("truth", main)
    for g, f in side.items():
        if f.exists():
            read(g, f)
    ints = {"index", "index_valid"}
    bools = {"saturated", "disturbed"}

    def get(group, field):
        if field is None:
            return True if group in tables else None
        if group == "mag" and field == "field_n":
            return np.asarray(meta["mag"]["field_n"], float)
        cols = csv_columns(group)
        sel = [i for i, c in enumerate(cols) if c == field or (c.startswith(field + "_")
               and c[len(field) + 1:] in ("N", "E", "D", "x", "y", "z", "w", "roll", "pitch", "yaw"))]
        a = tables[group][:, sel]
        a = a[:, 0] if len(sel) == 1 else a
        if field in ints:
            return a.astype(np.int64)
        if field in bools:
            return a.astype(bool)
        return a
    return _build(meta, get)


#: Columns of ``truth.csv`` written by :func:`save_ins_csv` (those of ``quatnav ins run``'s output).
TRUTH_COLUMNS = ("time", "lat", "lon", "h", "v_n", "v_e", "v_d", "roll", "pitch", "yaw")


def _write(path, header, cols, fmt):
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(header), comments="", fmt=fmt)
    return Path(path)


def save_ins_csv(scenario: Scenario, directory) -> list:
    """Write the ``quatnav ins run`` input files of a scenario into ``directory`` (created).

    See the module doc for the files, columns and units. Returns the paths written.
    """
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    s, written = scenario, []
    imu = s.imu
    written.append(_write(d / "imu.csv", ("time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"),
                          [imu.t, *np.asarray(imu.gyro).T, *np.asarray(imu.accel).T], "%.17g"))
    spec = s.params.get("gps", {})
    if s.gps is not None:
        g = s.gps
        k = len(g.t_valid)
        sh, sv = float(spec.get("pos_sigma_h_m", 2.0)), float(spec.get("pos_sigma_v_m", 4.0))
        svel = float(spec.get("vel_sigma_m_s", 0.1))
        written.append(_write(d / "gnss.csv", ("time", "lat", "lon", "h", "v_n", "v_e", "v_d", "sigma_n", "sigma_e",
                                                "sigma_d", "sigma_vn", "sigma_ve", "sigma_vd"),
                              [g.t_stamp, np.degrees(g.lat), np.degrees(g.lon), g.h, *np.asarray(g.v_n).T,
                               *(np.full(k, x) for x in (sh, sh, sv, svel, svel, svel))], "%.15g"))
    if s.baro is not None:
        written.append(_write(d / "baro.csv", ("time", "h"), [s.baro.t, s.baro.h], "%.10g"))
    if s.compass is not None:
        written.append(_write(d / "compass.csv", ("time", "heading"), [s.compass.t, np.degrees(s.compass.yaw)],
                              "%.10g"))
    if s.mag is not None:
        written.append(_write(d / "mag.csv", ("time", "mag_x", "mag_y", "mag_z"),
                              [s.mag.t, *(np.asarray(s.mag.mag) * 1e6).T], "%.10g"))
    if s.odometer is not None:
        written.append(_write(d / "odometer.csv", ("time", "speed"), [s.odometer.t, s.odometer.speed], "%.10g"))
    lever = np.broadcast_to(np.asarray(spec.get("lever_arm_b_m", 0.0), float), (3,))
    cfg = d / "config.toml"
    cfg.write_text(f"# quatnav ins run configuration of the simulated scenario {s.name} (seed {s.seed})\n"
                   "[filter]\n"
                   f"lever_arm_b = [{', '.join(repr(float(x)) for x in lever)}]   # m, GPS antenna in the body frame\n")
    written.append(cfg)
    written.append(_write_scenario_toml(s, d / "scenario.toml", lever))
    tr = s.truth
    written.append(_write(d / "truth.csv", TRUTH_COLUMNS,
                          [tr.t, np.degrees(tr.lat), np.degrees(tr.lon), tr.h, *np.asarray(tr.v_n).T,
                           *np.degrees(np.asarray(tr.rpy)).T], "%.15g"))
    return written


def _write_scenario_toml(s: Scenario, path, lever) -> Path:
    """``scenario.toml``: the sensor model and events of a scenario, for a filter to be told."""
    from ..calibration._toml import dumps
    from ..core import quaternion as quat
    q = np.asarray(s.imu.q_b_imu, float)
    rpy = s.params.get("imu", {}).get("mounting_rpy_deg", (0.0, 0.0, 0.0))
    doc = {"scenario": {"name": s.name, "seed": int(s.seed)},
           "imu": {"rate_hz": float(s.imu.rate_hz),
                   "mounting_rpy_deg": [float(x) for x in np.broadcast_to(np.asarray(rpy, float), (3,))],
                   "C_b_imu": [[float(x) for x in row] for row in quat.to_rotmat(q)],
                   "q_b_imu": [float(x) for x in q]}}
    if s.gps is not None:
        gp = s.params.get("gps", {})
        doc["gnss"] = {"lever_arm_b_m": [float(x) for x in lever], "latency_s": float(gp.get("latency_s", 0.0)),
                       "time_stamp": "delivery" if s.gps.stamped_on_delivery else "valid"}
    mp = s.params.get("mag")
    if s.mag is not None and mp:
        # the Earth field the magnetometer sees (declination: what --declination must say for a
        # true heading) and its errors in the sensor frame (what a calibration removes)
        doc["mag"] = {k: ([[float(x) for x in r] for r in mp[k]] if k == "soft_iron" else
                          [float(x) for x in mp[k]] if k == "hard_iron_uT" else float(mp[k]))
                      for k in ("declination_deg", "inclination_deg", "intensity_uT", "hard_iron_uT", "soft_iron")
                      if k in mp}
    ev = s.params.get("events")
    if ev:
        doc["events"] = {k: v for k, v in ev.items() if k in ("stops", "gnss_outages")}
    head = (f"quatnav simulate: sensor model and events of {s.name} (seed {s.seed})\n"
            "imu: the IMU's axes relative to the body (ZYX deg; C_b_imu rotates IMU-frame vectors into the body)\n"
            "gnss.time_stamp: 'delivery' = the fixes in gnss.csv are stamped late by latency_s\n"
            "mag: the Earth field (declination east of true north) and the sensor's hard and soft iron")
    Path(path).write_text(dumps(doc, header=head))
    return Path(path)
