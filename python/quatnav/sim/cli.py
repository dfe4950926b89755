"""``quatnav simulate``: build a named scenario, save it, optionally plot it.

    quatnav simulate --list
    quatnav simulate NAME --seed S --out FILE.npz [--csv FILE.csv] [--plot FILE.png]
"""

from __future__ import annotations

import argparse
import sys


def add_parser(subparsers):
    """Register the ``simulate`` subcommand on an argparse subparsers object."""
    p = subparsers.add_parser("simulate", help="simulate a named scenario (truth + sensors)",
                              description=__doc__,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("name", nargs="?", help="scenario name (see --list)")
    p.add_argument("--list", action="store_true", help="list the scenarios and exit")
    p.add_argument("--seed", type=int, default=0, help="seed of every random draw (default 0)")
    p.add_argument("--out", help="write the scenario to this .npz file")
    p.add_argument("--csv", help="also write CSV files (this name plus _imu.csv, ..., _meta.json)")
    p.add_argument("--plot", help="write an overview plot to this file (e.g. .png)")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    from . import scenarios
    if args.list:
        for n in scenarios.list_scenarios():
            print(f"{n:32s} {scenarios.scenario_description(n)}")
        return 0
    if not args.name:
        print("quatnav simulate: give a scenario NAME or --list", file=sys.stderr)
        return 2
    if not (args.out or args.csv or args.plot):
        print("quatnav simulate: give --out, --csv and/or --plot", file=sys.stderr)
        return 2
    try:
        s = scenarios.make_scenario(args.name, seed=args.seed)
    except ValueError as e:
        print(f"quatnav simulate: {e}", file=sys.stderr)
        return 2
    from . import io
    if args.out:
        io.save_npz(s, args.out)
    if args.csv:
        io.save_csv(s, args.csv)
    if args.plot:
        from .plot import plot_scenario
        plot_scenario(s, args.plot)
    tr = s.truth
    print(f"{s.name}: seed {s.seed}, {len(tr)} samples at {tr.rate_hz:g} Hz over {tr.t[-1]:g} s"
          + "".join(f"; {g} {len(getattr(s, g).t)}" for g in s.SENSORS if getattr(s, g) is not None))
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="quatnav")
    add_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["simulate", *(argv if argv is not None else sys.argv[1:])])
    return args.func(args)
