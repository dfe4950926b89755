"""The log pipelines: what ``quatnav ins run`` and ``quatnav ahrs run`` do, as library calls
(:func:`run_ins`, :func:`run_ahrs`).

A GNSS/INS run reads a user's log (or arrays), checks it for implausible units, axes and clocks,
coasts the IMU's gaps, aligns, runs :class:`quatnav.GpsInsFilter` and returns the result with
its alignment, warnings and per-aid diagnostics::

    import quatnav
    from quatnav.pipeline import run_ins, write_ins_table

    run = run_ins(quatnav.io.read("flight.ulg"), params={"lever_arm_b": [0.1, 0.0, -0.1]}, smooth=True)
    run.result            # quatnav.GpsInsResult; run.rows: the navigating samples
    run.alignment         # method, heading source, start of navigation (or why it never started)
    run.warnings          # quatnav.UnitWarning, AxesWarning, ClockWarning, ... objects
    run.diagnostics()     # one row per aiding sample
    write_ins_table(run, "nav.csv")

An attitude run is the same with QuaternionEKF, EulerEKF or MargFilter::

    run = run_ahrs(quatnav.io.read("flight.ulg"), filter="qekf", declination="auto")
    run.result.quat, run.summary()

The warnings are also issued with :func:`warnings.warn` as the run ends: filter them by category
(:mod:`quatnav.plausibility`). Input errors raise :class:`InputError` (a ``ValueError``) whose
message names the file, the line and the column.
"""
from __future__ import annotations

from .._command import InputError
from .ahrs import AhrsRun, read_ahrs_log, run_ahrs
from .config import load_config
from .inputs import InsInputs, read_ins_inputs
from .ins import InsRun, run_ins
from .outputs import (DIAGNOSTICS_COLUMNS, OUTPUT_COLUMNS, SCALE_COLUMNS, ahrs_table, diagnostics_table, ins_table,
                      write_ahrs_table, write_diagnostics, write_ins_table)
from .recording import PipelineWarning

__all__ = ["run_ins", "InsRun", "read_ins_inputs", "InsInputs", "load_config", "ins_table", "write_ins_table",
           "diagnostics_table", "write_diagnostics", "OUTPUT_COLUMNS", "SCALE_COLUMNS", "DIAGNOSTICS_COLUMNS",
           "run_ahrs", "AhrsRun", "read_ahrs_log", "ahrs_table", "write_ahrs_table", "InputError", "PipelineWarning"]
