"""The ``quatnav`` command line: ``quatnav demo``, and one subcommand per tool."""
from __future__ import annotations

import argparse
import sys


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="quatnav", description="Attitude and inertial-navigation filters.")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    from . import demo
    demo.add_parser(sub)
    from .sim import cli as sim_cli
    sim_cli.add_parser(sub)
    from . import experiments
    experiments.add_parser(sub)
    from . import bench
    bench.add_parser(sub)
    from . import evaluate
    evaluate.add_parser(sub)
    from . import ins_cli
    ins_cli.add_parser(sub)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.version:
        from . import __version__
        print(__version__)
        return 0
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    return int(args.func(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
