"""Evaluation: the attitude error metrics and the alignment fit (:mod:`~quatnav.evaluation.metrics`),
the attitude benchmark across data sets and modes (:mod:`~quatnav.evaluation.benchmark`, its
estimators :mod:`~quatnav.evaluation.algorithms`, its figures
:mod:`~quatnav.evaluation.benchmark_plot`), ``quatnav eval`` (:mod:`~quatnav.evaluation.evaluate`),
the parameter search (:mod:`~quatnav.evaluation.tuning`, :mod:`~quatnav.evaluation.optimize`) and the
throughput benchmark ``quatnav bench`` (:mod:`~quatnav.evaluation.bench`)."""
from . import metrics  # noqa: F401  (numpy only; evaluate, tuning and bench load on use)
