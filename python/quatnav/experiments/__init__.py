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
    "gpsins-car": ".gpsins_car",
    "smoothing": ".smoothing",
}


def load(name: str):
    """The module of experiment ``name`` (a key of :data:`EXPERIMENTS`)."""
    if name not in EXPERIMENTS:
        raise KeyError(f"unknown experiment {name!r}; known: {', '.join(sorted(EXPERIMENTS))}")
    return importlib.import_module(EXPERIMENTS[name], __name__)


def summary(name: str) -> str:
    """One line describing experiment ``name``: its module's ``SUMMARY`` (else its docstring's
    first line), or why it cannot be loaded."""
    try:
        mod = load(name)
    except ImportError as exc:  # pragma: no cover - a missing optional dependency
        return f"(cannot be loaded here: {exc})"
    text = getattr(mod, "SUMMARY", None) or (mod.__doc__ or "").strip().split("\n")[0] or f"experiment {name}"
    return " ".join(text.split())


EPILOG = """\
Each NAME has its own options: quatnav experiment NAME -h. --json FILE writes the results
('-': to stdout, the table then goes to stderr); --plot FILE.png needs matplotlib
(pip install 'quatnav[eval]'). The experiments on real data read $QUATNAV_DATA (the folder of
the shared datasets; default ../shared/data next to the source tree) unless --data DIR is given."""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav experiment NAME [options]`` on an argparse subparsers object."""
    names = sorted(EXPERIMENTS)
    width = max(len(n) for n in names)
    lines = "\n".join(f"  {n:{width}s}  {summary(n)}" for n in names)
    p = subparsers.add_parser("experiment", help="run a paper experiment (see 'quatnav experiment -h')",
                              description="Rerun the papers' experiments:\n" + lines, epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="experiment", metavar="NAME")
    for name in names:
        text = summary(name)
        sp = sub.add_parser(name, description=text)  # listed one per line in the description above
        sp.set_defaults(func=_dispatch(name), _experiment_parser=sp)
        _add_lazy(sp, name)
    p.set_defaults(func=None)
    return p


def _add_lazy(parser, name):
    # The experiment's own options; importing the module here keeps 'quatnav experiment NAME -h'
    # complete. An experiment whose module fails to import still shows up, takes any options and
    # reports the error (naming the missing package) when run.
    try:
        load(name).add_arguments(parser)
    except ImportError as exc:  # pragma: no cover - a missing optional dependency
        parser.add_argument("_options", nargs=argparse.REMAINDER, help=argparse.SUPPRESS)
        parser.set_defaults(_import_error=exc)


def _dispatch(name):
    def run(args):
        err = getattr(args, "_import_error", None)
        if err is not None:
            raise err
        return int(load(name).run(args) or 0)
    return run
