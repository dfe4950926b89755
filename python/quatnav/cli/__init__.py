"""The ``quatnav`` command line: ``quatnav demo``, and one subcommand per tool.

Every user mistake (a bad option, a missing or malformed input file, a missing optional
package) ends the command with one line on stderr naming what is wrong and what to do, and exit
status 2; :func:`main` is the one place that turns such an exception into that line. A user
error is a :class:`UsageError` (or a subclass), or a ``ValueError`` / ``FileNotFoundError``
raised by quatnav's own input validation; anything else is a bug and keeps its traceback.
``QUATNAV_TRACEBACK=1`` shows the traceback of user errors too.
"""
from __future__ import annotations

import argparse
import contextlib
import linecache
import os
import sys
import warnings
from pathlib import Path

__all__ = ["main", "build_parser"]

from .._command import _EXTRAS, UsageError, missing_extra

EPILOG = """\
environment:
  QUATNAV_DATA   folder of the shared datasets (broad/, navego_synthetic/, gnss_imu_walk/, px4/),
                 used by 'eval broad' and the experiments on real data when no DIR / --data is
                 given; default: ../shared/data next to the source tree
  QUATNAV_TRACEBACK=1  show the Python traceback of a user error as well
  NUMPY_MADVISE_HUGEPAGE=1  let numpy ask for transparent huge pages (the commands turn them off
                 unless this is set: faulting in the huge pages of their large temporary arrays
                 cost a 1-hour 'ins run' 2.5 s of system time)
  ARROW_DEFAULT_MEMORY_POOL  pyarrow's allocator; the commands use 'system' unless this is set
                 (mimalloc's huge pages cost a 1-hour 'ins run --out X.parquet' 1 s)

exit status: 0 success, 1 ran but produced nothing useful (e.g. 'ins run': navigation never
started), 2 a user error (one line on stderr)"""

class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose errors are one line: ``PROG: error: MESSAGE (see 'PROG -h')``."""

    def error(self, message):  # noqa: D401 - argparse API
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} -h')\n")

    def parse_args(self, args=None, namespace=None):
        """argparse's, but an unknown option is reported by the (sub)command that was given
        (``quatnav ins run: error: unrecognized arguments: ...``), not by ``quatnav``: a
        subcommand's parser hands the words it does not know up to its parent."""
        ns, extras = self.parse_known_args(args, namespace)
        if extras:
            self._command_parser(getattr(ns, "_prog", self.prog)).error(
                f"unrecognized arguments: {' '.join(extras)}")
        return ns

    def _command_parser(self, prog: str) -> argparse.ArgumentParser:
        """The parser of the tree whose prog is ``prog`` (``self`` if none is)."""
        todo = [self]
        while todo:
            p = todo.pop()
            if p.prog == prog:
                return p
            todo += [sub for a in p._actions if isinstance(a, argparse._SubParsersAction)
                     for sub in a.choices.values()]
        return self


def _missing_module(exc: ImportError) -> str | None:
    """The optional module whose absence caused ``exc`` (following ``raise ... from``), or None."""
    e = exc
    while e is not None:
        name = getattr(e, "name", None)
        if isinstance(e, ImportError) and name and name.split(".")[0] in _EXTRAS:
            return name.split(".")[0]
        e = e.__cause__ or e.__context__
    return None


def _raised_by_quatnav(exc: BaseException) -> bool:
    """True when ``exc`` comes from an explicit ``raise`` statement in quatnav's own code (input
    validation), not from numpy, the compiled core or an operation that failed."""
    tb = exc.__traceback__
    if tb is None:
        return False
    while tb.tb_next is not None:
        tb = tb.tb_next
    fname = tb.tb_frame.f_code.co_filename
    pkg = str(Path(__file__).resolve().parents[1])  # the quatnav package
    try:
        inside = str(Path(fname).resolve()).startswith(pkg + os.sep)
    except OSError:  # pragma: no cover
        return False
    return inside and linecache.getline(fname, tb.tb_lineno).lstrip().startswith("raise")


def _plain(msg: str) -> str:
    return " ".join(str(msg).split())  # one line whatever the exception's text


def _leaf_progs(parser) -> None:
    """Set ``_prog`` (the full command name, for messages), ``_command`` (the first word after
    ``quatnav``) and ``_choices`` (its subcommands, if any) on every parser of the tree."""
    words = parser.prog.split()
    choices = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            choices = list(action.choices)
            for sub in action.choices.values():
                _leaf_progs(sub)
    parser.set_defaults(_prog=parser.prog, _command=words[1] if len(words) > 1 else None, _choices=choices)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="quatnav", description="Attitude and inertial-navigation filters.", epilog=EPILOG,
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    from .. import demo
    demo.add_parser(sub)
    from ..sim import cli as sim_cli
    sim_cli.add_parser(sub)
    from .. import experiments
    experiments.add_parser(sub)
    from ..evaluation import bench
    bench.add_parser(sub)
    from ..evaluation import evaluate
    evaluate.add_parser(sub)
    from . import ins
    ins.add_parser(sub)
    from . import ahrs
    ahrs.add_parser(sub)
    from . import compare
    compare.add_parser(sub)
    from . import calibrate
    calibrate.add_parser(sub)
    calibrate.add_allan_parser(sub)
    from ..evaluation import optimize
    optimize.add_parser(sub)
    _leaf_progs(parser)
    parser.set_defaults(func=None)
    return parser


def _preflight(args) -> None:
    """Checks common to every command, before it runs (and saves the user a long run before a
    certain failure)."""
    seed = getattr(args, "seed", None)
    if isinstance(seed, int) and seed < 0:
        raise UsageError(f"--seed: expected a non-negative integer, got {seed}")
    # Output files: a path into a folder that does not exist fails only after the whole run (or
    # a typo creates a chain of folders): refused first. --plot may create its own folder (one
    # level: `quatnav demo --plot out/demo.png` in a fresh checkout), not a chain.
    for dest in ("out", "json", "diagnostics", "kml", "gpx", "plot"):
        value = getattr(args, dest, None)
        if not isinstance(value, (str, Path)) or str(value) in ("", "-"):
            continue
        folder = Path(value).resolve().parent
        if dest == "plot" and not folder.is_dir():
            if not folder.parent.is_dir():
                raise UsageError(f"--plot {value}: cannot write (no such directory: {folder}, nor {folder.parent})")
            if Path(value).suffix:  # a figure file (eval broad's --plot is a folder, which it makes)
                folder.mkdir()
        elif not folder.is_dir():
            raise UsageError(f"--{dest} {value}: cannot write (no such directory: {folder})")
    plot = getattr(args, "plot", None)
    if plot:
        import importlib.util
        if importlib.util.find_spec("matplotlib") is None:
            raise ModuleNotFoundError("No module named 'matplotlib'", name="matplotlib")
        suffix = Path(str(plot)).suffix.lower().lstrip(".")
        if suffix and not Path(str(plot)).is_dir():  # a file (eval broad's --plot is a folder)
            from matplotlib.backend_bases import FigureCanvasBase
            kinds = FigureCanvasBase.get_supported_filetypes()
            if suffix not in kinds:
                raise UsageError(f"--plot {plot}: matplotlib cannot write .{suffix} files "
                                 f"(it writes {', '.join(sorted(kinds))})")


def _small_pages() -> None:
    """Numpy's large arrays without ``madvise(MADV_HUGEPAGE)``, unless NUMPY_MADVISE_HUGEPAGE says;
    pyarrow's ``system`` allocator, unless ARROW_DEFAULT_MEMORY_POOL says.

    Where transparent huge pages are on ``madvise``, numpy asks for them for every array of 4 MB
    or more, and pyarrow's default allocator (mimalloc) uses them too. A command makes and drops
    many large temporaries, each faulted in and zeroed 2 MB at a time: on the 1-hour 200 Hz log
    of ``bench/make_long_log.py``, ``ins run`` spent 3.1-4.0 s in the kernel with numpy's huge
    pages and 1.0 s without (wall 8.9-10.2 s against 6.8 s); with Parquet output, mimalloc's
    cost another second of system time. Only the command line does this (pyarrow is not yet
    imported when it starts, and reads the variable on its first allocation); ``import quatnav``
    leaves both settings alone."""
    os.environ.setdefault("ARROW_DEFAULT_MEMORY_POOL", "system")
    if "NUMPY_MADVISE_HUGEPAGE" in os.environ:
        return
    try:
        from numpy._core.multiarray import _set_madvise_hugepage
    except ImportError:  # numpy 1.x
        try:
            from numpy.core.multiarray import _set_madvise_hugepage
        except ImportError:
            return
    _set_madvise_hugepage(False)


def main(argv=None) -> int:
    _small_pages()
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.version:
        from .. import __version__
        print(__version__)
        return 0
    prog = getattr(args, "_prog", "quatnav")
    if not args.func:
        choices = getattr(args, "_choices", None) or []
        print(f"{prog}: error: give a command ({', '.join(choices)}; see '{prog} -h')", file=sys.stderr)
        return 2
    command = getattr(args, "_command", None)
    debug = os.environ.get("QUATNAV_TRACEBACK", "") not in ("", "0")
    with warnings.catch_warnings():
        # The library's own warnings about the user's data as one line each, not source lines;
        # each time it is issued (a command run twice in one process warns twice).
        from ..filters._base import AidWarning
        from ..filters.gpsins import NavigationWarning
        from ..pipeline.recording import RECORDED
        ours = (*RECORDED, AidWarning, NavigationWarning)
        for category in ours:
            warnings.simplefilter("always", category)
        shown = warnings.showwarning

        def one_line(message, category, *rest, **kw):
            if issubclass(category, ours):
                print(f"{prog}: warning: {message}", file=sys.stderr)
            else:
                shown(message, category, *rest, **kw)

        warnings.showwarning = one_line
        return _run(args, prog, command, debug)


def _run(args, prog, command, debug) -> int:
    try:
        _preflight(args)
        if getattr(args, "json", None) == "-":
            args._json_stdout = sys.stdout
            with contextlib.redirect_stdout(sys.stderr):
                return int(args.func(args) or 0)
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. piped into head
        with contextlib.suppress(Exception):
            sys.stdout = open(os.devnull, "w")
        return 0
    except ImportError as exc:
        mod = _missing_module(exc)
        if mod is None or debug:
            raise
        extra = missing_extra(mod, command)
        what = "--plot" if mod == "matplotlib" and getattr(args, "plot", None) else "this command"
        print(f"{prog}: error: {what} needs the optional package {mod}, which is not installed: "
              f"pip install 'quatnav[{extra}]' (or pip install {mod})", file=sys.stderr)
        return 2
    except UsageError as exc:
        if debug:
            raise
        print(f"{prog}: error: {_plain(exc)}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, NotADirectoryError, PermissionError) as exc:
        if debug:
            raise
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"{prog}: error: {where}{_plain(exc.strerror or exc)}", file=sys.stderr)
        return 2
    except ValueError as exc:
        if debug or not _raised_by_quatnav(exc):
            raise
        print(f"{prog}: error: {_plain(exc)}", file=sys.stderr)
        return 2

