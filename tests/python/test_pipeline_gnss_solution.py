"""run_ins passes the receiver's solution kind (a log's GNSS quality codes) to the filter, so that
each fix gets its kind's sigma floor, and says so in the run's notes; a log without quality codes
runs as before (every fix "unknown": the floor gps_pos_sigma_min)."""
import numpy as np
import pytest

import quatnav
from quatnav import io
from quatnav.filters.gpsins import GNSS_SOLUTIONS
from quatnav.pipeline import run_ins
from quatnav.sim import make_scenario


@pytest.fixture(scope="module")
def walk():
    return make_scenario("paper004_walk", seed=0)


def _log(s, quality=None, kind=""):
    g = s.gps
    return io.Log(source="walk", imu=io.Imu(t=s.imu.t, gyr=s.imu.gyro, acc=s.imu.accel),
                  gnss=io.Gnss(t=g.t_valid, lat=g.lat, lon=g.lon, h=g.h, vel_n=g.v_n,
                               sigma=np.full((len(g.t_valid), 3), 0.5), quality=quality, quality_kind=kind))


def _captured(monkeypatch, log):
    seen = {}
    run = quatnav.GpsInsFilter.run

    def spy(self, *a, **kw):
        seen.setdefault("gps_solution", kw.get("gps_solution"))
        return run(self, *a, **kw)
    monkeypatch.setattr(quatnav.GpsInsFilter, "run", spy)
    return run_ins(log), seen["gps_solution"]


@pytest.mark.parametrize("kind, codes, names", [
    ("rtklib", (1, 2, 5), ("rtk_fixed", "rtk_float", "single")),
    ("nmea-gga", (4, 5, 1), ("rtk_fixed", "rtk_float", "single")),
    ("px4-fix_type", (6, 5, 3), ("rtk_fixed", "rtk_float", "single")),
])
def test_quality_codes_reach_the_filter_as_solution_kinds(walk, monkeypatch, kind, codes, names):
    n = len(walk.gps.t_valid)
    pick = np.arange(n) % 3
    r, got = _captured(monkeypatch, _log(walk, np.asarray(codes)[pick], kind))
    want = np.array([GNSS_SOLUTIONS.index(names[i]) for i in pick], dtype=np.uint8)
    assert got is not None and np.array_equal(got, want)
    counts = {name: int(np.sum(pick == i)) for i, name in enumerate(names)}
    note = [x for x in r.notes if x.startswith("GNSS solution kinds")]
    assert len(note) == 1 and all(f"{c:,} {name}" in note[0] for name, c in counts.items()), r.notes


def test_a_log_without_quality_codes_passes_no_solution_kinds(walk, monkeypatch):
    r, got = _captured(monkeypatch, _log(walk))
    assert got is None and not [x for x in r.notes if x.startswith("GNSS solution kinds")]


def test_the_solution_kinds_change_the_fixes_weight(walk):
    """The same fixes (0.5 m given) as RTK-fixed solutions (floor 1 cm: 0.5 m used) and as
    single-point ones (floor 1.5 m) are weighted differently, so the estimates differ."""
    n = len(walk.gps.t_valid)
    fixed = run_ins(_log(walk, np.ones(n, int), "rtklib"))
    single = run_ins(_log(walk, np.full(n, 5), "rtklib"))
    assert not np.array_equal(fixed.result.position, single.result.position)
