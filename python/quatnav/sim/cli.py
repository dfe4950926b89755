r"""``quatnav simulate``: build a named scenario, save it, optionally plot it.

    quatnav simulate --list
    quatnav simulate NAME --seed S [--out FILE.npz] [--csv DIR | --csv FILE.csv] [--plot FILE.png]
                     [--json FILE|-]

--csv DIR writes the input files of 'quatnav ins run' into DIR (imu.csv, gnss.csv, baro.csv,
compass.csv, config.toml, in its columns and units), the other streams of the scenario (mag.csv
in uT, odometer.csv in m/s), scenario.toml (the IMU mounting body-from-IMU, the GNSS latency and
whether fixes are stamped on delivery, the lever arm, the stops and outages: what a filter must be
told, e.g. for car_city) and truth.csv (time, lat, lon (deg), h, v_n, v_e, v_d, roll, pitch,
yaw (deg)), so that

    quatnav ins run --imu DIR/imu.csv --gnss DIR/gnss.csv --baro DIR/baro.csv \
                    --compass DIR/compass.csv --config DIR/config.toml --out DIR/out.csv

runs the scenario unchanged. --csv FILE.csv (a name ending in .csv) writes every field of the
scenario instead (FILE.csv with the truth, FILE_imu.csv, ..., FILE_meta.json; quatnav.sim.io).
DIR is created if needed, but not its parent folder: as for --out, a path into a folder that
does not exist is refused.
Needs scipy for some sensor models: pip install 'quatnav[sim]'.
"""

from __future__ import annotations

import argparse

from .._command import UsageError, write_json


def add_parser(subparsers):
    """Register the ``simulate`` subcommand on an argparse subparsers object."""
    p = subparsers.add_parser("simulate", help="simulate a named scenario (truth + sensors)",
                              description=__doc__,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("name", nargs="?", help="scenario name (see --list)")
    p.add_argument("--list", action="store_true", help="list the scenarios and exit")
    p.add_argument("--seed", type=int, default=0, help="seed of every random draw (default 0)")
    p.add_argument("--out", help="write the scenario to this .npz file")
    p.add_argument("--csv", metavar="DIR|FILE.csv",
                   help="write the 'quatnav ins run' input files and truth.csv into DIR; or, for a name ending "
                        "in .csv, every field (FILE.csv, FILE_imu.csv, ..., FILE_meta.json)")
    p.add_argument("--plot", help="write an overview plot to this file (e.g. .png)")
    p.add_argument("--json", metavar="FILE", help="write a summary (samples, sensors, files) as JSON ('-': stdout)")
    p.set_defaults(func=run)
    return p


def _check_outputs(args) -> None:
    """Refuse, before the scenario is made, a --csv whose folder does not exist: --csv DIR creates
    DIR itself, not a chain of folders that a typo in the path would give. (--out, like every
    command's output file, is checked before any command runs: cli._preflight.)"""
    from pathlib import Path
    path = args.csv
    if not path:
        return
    p = Path(path)
    what = "cannot write"
    if not str(path).lower().endswith(".csv"):
        if p.exists() and not p.is_dir():
            raise UsageError(f"--csv {path}: not a folder (give a folder, or a name ending in .csv)")
        what = "cannot create it"
    parent = p.resolve().parent
    if not parent.is_dir():
        raise UsageError(f"--csv {path}: {what} (no such directory: {parent})")


def run(args) -> int:
    from . import scenarios
    if args.list:
        rows = [(n, scenarios.scenario_description(n)) for n in scenarios.list_scenarios()]
        if args.json:
            write_json({n: d for n, d in rows}, args)
        else:
            for n, d in rows:
                print(f"{n:32s} {d}")
        return 0
    known = scenarios.list_scenarios()
    if not args.name:
        raise UsageError(f"give a scenario NAME ({', '.join(known)}) or --list")
    if args.name not in known:
        raise UsageError(f"unknown scenario name {args.name!r}; known: {', '.join(known)} (see --list)")
    if args.seed < 0:
        raise UsageError(f"--seed: expected a non-negative integer, got {args.seed}")
    if not (args.out or args.csv or args.plot or args.json):
        raise UsageError("nothing to write: give --out FILE.npz, --csv DIR, --plot FILE.png and/or --json FILE")
    _check_outputs(args)
    s = scenarios.make_scenario(args.name, seed=args.seed)
    from . import io
    files = []
    if args.out:
        io.save_npz(s, args.out)
        files.append(str(args.out))
    if args.csv:
        if str(args.csv).lower().endswith(".csv"):
            io.save_csv(s, args.csv)
            files.append(str(args.csv))
        else:
            files += [str(p) for p in io.save_ins_csv(s, args.csv)]
    if args.plot:
        from .plot import plot_scenario
        plot_scenario(s, args.plot)
        files.append(str(args.plot))
    tr = s.truth
    sensors = {g: len(getattr(s, g).t) for g in s.SENSORS if getattr(s, g) is not None}
    print(f"{s.name}: seed {s.seed}, {len(tr)} samples at {tr.rate_hz:g} Hz over {tr.t[-1]:g} s"
          + "".join(f"; {g} {n}" for g, n in sensors.items()))
    if args.json:
        write_json({"name": s.name, "seed": s.seed, "description": s.description, "samples": len(tr),
                    "rate_hz": tr.rate_hz, "duration_s": float(tr.t[-1]), "sensors": sensors, "files": files}, args)
    return 0
