"""The warnings of a run, kept as objects: the steps of a pipeline issue them with
:func:`warnings.warn`; :func:`recorded` keeps those of quatnav's categories (each text once, in
order) for the run's result and issues them again to the caller when the run ends, where the
caller's warning filters decide what is shown, ignored or raised."""
from __future__ import annotations

import contextlib
import warnings

from ..plausibility.categories import AidWarning, PlausibilityWarning, issue

__all__ = ["PipelineWarning", "recorded", "issue"]


class PipelineWarning(UserWarning):
    """A step of a pipeline that did other than asked: an estimate that replaces a configured
    value, one at the end of its search interval, a calibration that could not be made, a
    magnetic model used outside its validity. The message names what to change."""


#: The categories a run records (the others pass through to the caller as they come).
RECORDED = (PlausibilityWarning, AidWarning, PipelineWarning)


@contextlib.contextmanager
def recorded(ignore=()):
    """Collect the warnings of :data:`RECORDED` issued inside (each text once) into the list this
    yields; ``ignore``: categories dropped (e.g. the filter's NavigationWarning, which the run
    reports otherwise). Warnings of other categories are shown as usual."""
    kept, seen = [], set()
    with warnings.catch_warnings():
        shown = warnings.showwarning
        for category in RECORDED:
            warnings.simplefilter("always", category)
        for category in ignore:
            warnings.simplefilter("ignore", category)

        def keep(message, category, filename, lineno, file=None, line=None):
            if issubclass(category, RECORDED):
                key = (category, str(message))
                if key not in seen:
                    seen.add(key)
                    kept.append(message if isinstance(message, Warning) else category(message))
            else:
                shown(message, category, filename, lineno, file, line)

        warnings.showwarning = keep
        yield kept
