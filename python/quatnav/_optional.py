"""Import optional dependencies with an error that says which extra provides them."""

from __future__ import annotations

import importlib

_EXTRA = {"scipy": "sim", "matplotlib": "eval", "h5py": "eval", "tqdm": "eval", "pandas": "io"}


def require(module: str, feature: str):
    """Import ``module`` (e.g. ``"scipy.signal"``) or raise ``ImportError`` naming the extra.

    Parameters
    ----------
    module : str
        Dotted module name.
    feature : str
        What needs it, for the message (e.g. ``"quatnav.sim sensor models"``).
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:  # pragma: no cover - depends on the environment
        top = module.split(".")[0]
        extra = _EXTRA.get(top, "eval")
        raise ImportError(
            f"{feature} needs {top}; install it with `pip install quatnav[{extra}]` "
            f"(or `pip install {top}`)") from exc
