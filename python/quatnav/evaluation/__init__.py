"""Evaluation: BROAD's attitude error metrics (:mod:`~quatnav.evaluation.metrics`), ``quatnav eval``
(:mod:`~quatnav.evaluation.evaluate`), the parameter search (:mod:`~quatnav.evaluation.tuning`) and
the throughput benchmark ``quatnav bench`` (:mod:`~quatnav.evaluation.bench`)."""
from . import metrics  # noqa: F401  (numpy only; evaluate, tuning and bench load on use)
