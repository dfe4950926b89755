"""Experiments that reproduce the papers' results: ``quatnav experiment NAME ...``.

Each experiment is a module with two functions:

* ``add_arguments(parser)``: add its options to an ``argparse.ArgumentParser``;
* ``run(args) -> int``: run it (exit status 0 on success).

:data:`EXPERIMENTS` maps the name used on the command line to the module path; modules are
imported only when their experiment is run. Registering a new experiment is one line here.
"""
from __future__ import annotations

import argparse
import importlib

#: name on the command line -> module (relative to this package) with add_arguments/run.
EXPERIMENTS: dict[str, str] = {
    "marg-turn": ".marg_turn",
    "marg-broad": ".marg_broad",
    "nav13": ".nav13",
    "gpsins": ".gpsins",
    "navego": ".navego",
    "walk-rtk": ".walk_rtk",
}


def load(name: str):
    """The module of experiment ``name`` (a key of :data:`EXPERIMENTS`)."""
    if name not in EXPERIMENTS:
        raise KeyError(f"unknown experiment {name!r}; known: {', '.join(sorted(EXPERIMENTS))}")
    return importlib.import_module(EXPERIMENTS[name], __name__)


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav experiment NAME [options]`` on an argparse subparsers object."""
    p = subparsers.add_parser("experiment", help="run a paper experiment (see 'quatnav experiment -h')",
                              description="Run one of the experiments: " + ", ".join(sorted(EXPERIMENTS)))
    sub = p.add_subparsers(dest="experiment", metavar="NAME")
    for name in sorted(EXPERIMENTS):
        sp = sub.add_parser(name, help=f"experiment {name}")
        sp.set_defaults(func=_dispatch(name), _experiment_parser=sp)
        _add_lazy(sp, name)
    p.set_defaults(func=lambda args: (p.print_help() or 2))
    return p


def _add_lazy(parser, name):
    # The experiment's own options; importing the module here keeps 'quatnav experiment NAME -h'
    # complete. An experiment whose module fails to import still shows up and reports the error
    # when run.
    try:
        load(name).add_arguments(parser)
    except ImportError as exc:  # pragma: no cover - a missing optional dependency
        parser.set_defaults(_import_error=exc)


def _dispatch(name):
    def run(args):
        err = getattr(args, "_import_error", None)
        if err is not None:
            raise err
        return int(load(name).run(args) or 0)
    return run
