"""What every command shares, wherever its parser lives (``quatnav.cli``, and the tools that add
their own subcommand from their package: ``sim``, ``evaluation``, ``experiments``, ``demo``):
:class:`UsageError` (a user mistake: one line on stderr, exit status 2), :func:`write_json` (the
``--json FILE`` of every command) and the table of optional packages and the extras that provide
them. Below every command (it imports nothing of quatnav), so that none of them imports from
:mod:`quatnav.cli`."""
from __future__ import annotations

import json
import sys
from pathlib import Path

__all__ = ["UsageError", "InputError", "write_json", "missing_extra"]

#: optional package -> extra of ``pip install 'quatnav[EXTRA]'`` that provides it, per command
#: (``None``: any command). scipy is in both [sim] and [eval]; the command decides which to name.
_EXTRAS = {
    "scipy": {"simulate": "sim", "bench": "sim", None: "eval"},
    "matplotlib": {None: "eval"}, "h5py": {None: "eval"}, "tqdm": {None: "eval"},
    "pandas": {None: "io"}, "distributed": {None: "cluster"}, "dask": {None: "cluster"},
    "pyulog": {None: "logs"}, "rosbags": {None: "logs"}, "pyarrow": {None: "logs"},
    "vqf": {None: "peers"}, "imufusion": {None: "peers"}, "ahrs": {None: "peers"}, "filterpy": {None: "peers"},
}


class UsageError(Exception):
    """A mistake of the user (bad argument, bad input file): :func:`quatnav.cli.main` prints its
    message as one line and exits with status 2."""


class InputError(UsageError, ValueError):
    """A problem with an input file or a configuration, raised by the library's pipeline
    (:mod:`quatnav.pipeline`): a ``ValueError`` for a Python caller, whose message names the file,
    the line and the column; a one-line report with exit status 2 on the command line."""


def missing_extra(module: str, command: str | None = None) -> str | None:
    """The extra that provides ``module`` (top-level name), for ``command``; None if not optional."""
    table = _EXTRAS.get(module.split(".")[0])
    if table is None:
        return None
    return table.get(command, table[None])


def write_json(obj, args, path: str | None = None) -> None:
    """Write ``obj`` as JSON to ``path`` (default ``args.json``); ``-`` is standard output.

    With ``--json -`` :func:`main` sends the command's human-readable output to stderr, so that
    stdout holds only the JSON document.
    """
    dest = path if path is not None else getattr(args, "json", None)
    if not dest:
        return
    text = json.dumps(obj, indent=1, default=_json_default, allow_nan=True)
    if dest == "-":
        out = getattr(args, "_json_stdout", None) or sys.stdout
        out.write(text + "\n")
        out.flush()
        return
    with open(dest, "w") as fh:
        fh.write(text + "\n")
    print(f"wrote {dest}")


def _json_default(o):
    import numpy as np
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"cannot write {type(o).__name__} as JSON")
