"""Checks of a run's aids after the filter: a heading aid (magnetometer, compass) that the filter
gated out in most samples."""
from __future__ import annotations

import numpy as np

from .categories import AidWarning

__all__ = ["check_heading_aids"]


def check_heading_aids(r, min_tested=50, max_rejected=0.2) -> list:
    """Warnings for a magnetometer or compass whose headings the filter gated out in more than
    ``max_rejected`` of the samples it tested (at least ``min_tested``): the aid disagrees with the
    heading that the GNSS and the IMU give, and the part that passed the gate still pulls on it."""
    out = []
    for name, what, fix in (("mag", "magnetometer", "an uncalibrated hard-iron offset or a declination "
                             "(--mag-calibrate fits both on this log; or quatnav calibrate mag with --calibration, "
                             "--declination DEG or auto) or a field the vehicle disturbs (--no-mag)"),
                            ("compass", "compass", "a declination (--declination DEG or auto), a compass mounted "
                             "turned, or one the vehicle disturbs")):
        a = r.aids.get(name)
        if a is None:
            continue
        d = a.decisions()
        tested = sum(d.get(k, 0) for k in ("accepted", "rejected", "inflated", "reset", "weighted"))
        bad = d.get("rejected", 0)
        if tested < min_tested or not bad > max_rejected * tested:
            continue
        inn = np.asarray(a.innovation, float)[:, 0]
        rms = float(np.degrees(np.sqrt(np.nanmean(inn[np.isfinite(inn)] ** 2))))
        out.append(AidWarning(
            f"{what}: {bad} of {tested} headings gated out ({100 * bad / tested:.0f} %; innovations "
            f"{rms:.1f} deg RMS): it disagrees with the heading of the GNSS and the IMU, and the samples that "
            f"pass pull the heading towards it: {fix}"))
    return out
