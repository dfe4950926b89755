"""What the command line and its subcommand modules share: :class:`UsageError` (a user mistake:
one line on stderr, exit status 2), :func:`write_json` (the ``--json FILE`` of every command) and
the table of optional packages and the extras that provide them. A module of its own, so that
:mod:`quatnav.cli` imports the subcommands and they import this, without a cycle."""
from __future__ import annotations

import json
import sys
from pathlib import Path

__all__ = ["UsageError", "write_json", "missing_extra"]

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
    """A mistake of the user (bad argument, bad input file): :func:`main` prints its message as
    one line and exits with status 2."""


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
