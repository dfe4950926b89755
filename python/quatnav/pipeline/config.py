"""The TOML configuration of a GNSS/INS run: the ``[filter]`` table (parameters of
:class:`quatnav.GpsInsFilter`, checked against its parameter table) and the optional
``[initial]`` table (a given initial state instead of the alignment)."""
from __future__ import annotations

import math

from .._command import InputError
from .._validate import did_you_mean

__all__ = ["load_config"]


def load_config(path, initial: dict | None = None) -> dict:
    """Parameters of :class:`quatnav.GpsInsFilter` from the ``[filter]`` table of a TOML file
    (the ``[parameters]`` and ``[allan]`` tables of a ``quatnav allan`` noise file are ignored).
    With a dict ``initial``, the ``[initial]`` table (a given initial state) is put in it."""
    try:
        import tomllib as toml  # Python 3.11+
    except ModuleNotFoundError:  # pragma: no cover - depends on the Python version
        try:
            import tomli as toml
        except ModuleNotFoundError:
            raise InputError(f"config {path}: reading TOML needs Python 3.11+ or the 'tomli' package") from None
    try:
        with open(path, "rb") as fh:
            doc = toml.load(fh)
    except OSError as e:
        raise InputError(f"config {path}: cannot open ({e.strerror})") from None
    except toml.TOMLDecodeError as e:
        raise InputError(f"config {path}: not valid TOML ({e})") from None
    from ..filters.gpsins import PARAM_NAMES
    from ..filters.tables import GPSINS_PARAMS
    kinds = {q.name: q.kind for q in GPSINS_PARAMS}
    # a noise file of 'quatnav allan' also holds [parameters.NAME] (other filters) and [allan] (read-outs)
    unknown = [k for k in doc if k not in ("filter", "initial", "parameters", "allan")]
    if unknown:
        raise InputError(f"config {path}: unknown table or key {unknown[0]!r}"
                         f"{did_you_mean(unknown[0], ('filter', 'initial'))} (expected a [filter] table)")
    params = doc.get("filter", {})
    if not isinstance(params, dict):
        raise InputError(f"config {path}: 'filter' must be a table")

    def numbers(v, n):
        return isinstance(v, list) and len(v) == n and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                           for x in v)
    for k, v in params.items():
        if k not in PARAM_NAMES:
            raise InputError(f"config {path}: [filter] unknown parameter {k!r}{did_you_mean(k, PARAM_NAMES)}; the "
                             "parameters with their units and defaults: quatnav ins run -h")
        kind = kinds[k]
        if kind == "vec3":
            if not numbers(v, 3):
                raise InputError(f"config {path}: [filter] {k} must be a list of 3 numbers (m)")
        elif kind == "mat3":
            if not (numbers(v, 3) or (isinstance(v, list) and len(v) == 3 and all(numbers(r, 3) for r in v))):
                raise InputError(f"config {path}: [filter] {k} must be [roll, pitch, yaw] (rad) or a 3x3 matrix "
                                 "(a list of 3 rows)")
            if numbers(v, 3):
                _check_radians(v, f"config {path}: [filter] {k}", pitch_limit=False)
        elif kind == "bool":
            if not isinstance(v, bool):
                raise InputError(f"config {path}: [filter] {k} must be true or false")
        elif kind in ("int1", "iter"):
            if isinstance(v, bool) or not isinstance(v, int):
                raise InputError(f"config {path}: [filter] {k} must be an integer")
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"config {path}: [filter] {k} must be a number")
    init = doc.get("initial", {})
    if not isinstance(init, dict):
        raise InputError(f"config {path}: 'initial' must be a table")
    sizes = {"euler": 3, "q_nb": 4, "v_n": 3, "acc_bias": 3, "gyro_bias": 3}
    for k, v in init.items():
        if k not in sizes:
            raise InputError(f"config {path}: [initial] unknown key {k!r}{did_you_mean(k, sizes)} (known: "
                             f"{', '.join(sizes)})")
        if not numbers(v, sizes[k]):
            raise InputError(f"config {path}: [initial] {k} must be a list of {sizes[k]} numbers")
    if "euler" in init:
        _check_radians(init["euler"], f"config {path}: [initial] euler", pitch_limit=True)
    if init and ("euler" in init) == ("q_nb" in init):
        raise InputError(f"config {path}: [initial] needs exactly one of euler (rad) and q_nb")
    if initial is not None:
        initial.update(init)
    return dict(params)


def _check_radians(rpy, where, pitch_limit):
    """Refuse [roll, pitch, yaw] that cannot be radians (beyond 2 pi, or a pitch beyond pi/2 where
    ``pitch_limit``): most likely degrees, which the message converts."""
    bad = any(abs(float(x)) > 2 * math.pi + 1e-9 for x in rpy)
    if pitch_limit and abs(float(rpy[1])) > math.pi / 2 + 1e-9:
        bad = True
    if bad:
        rad = ", ".join(f"{math.radians(float(x)):.6g}" for x in rpy)
        raise InputError(f"{where} = {list(rpy)} is not [roll, pitch, yaw] in radians"
                         f"{' (pitch within +-pi/2)' if pitch_limit else ''}; if these are degrees: [{rad}]")
