"""A small TOML writer for calibration and noise files (read back with the stdlib ``tomllib``).

Writes what those files hold: tables of strings, booleans, integers, floats (shortest text
that reads back to the same float, ``nan``/``inf`` as TOML spells them) and lists of them,
nested tables as dotted headers.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["dumps", "loads"]


def _value(v) -> str:
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        x = float(v)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _key(k: str) -> str:
    k = str(k)
    return k if k and all(c.isalnum() or c in "_-" for c in k) else _value(k)


def dumps(doc: dict, header: str = "") -> str:
    """TOML text of ``doc`` (a dict of values and dicts); ``header``: leading ``#`` comment lines."""
    out = [f"# {ln}" if ln else "#" for ln in header.splitlines()]

    def table(d, path):
        plain = [(k, v) for k, v in d.items() if not isinstance(v, dict) and v is not None]
        subs = [(k, v) for k, v in d.items() if isinstance(v, dict)]
        if path and (plain or not subs):
            out.append("")
            out.append("[" + ".".join(_key(p) for p in path) + "]")
        for k, v in plain:
            out.append(f"{_key(k)} = {_value(v)}")
        for k, v in subs:
            table(v, path + [k])

    table(doc, [])
    return "\n".join(out).lstrip("\n") + "\n"


def loads(text: str) -> dict:
    import tomllib
    return tomllib.loads(text)
