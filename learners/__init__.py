"""Thermal-error models and sensor-selection methods on the scikit-learn contract.

Importing the package registers every learner and selector (see :mod:`learners.registry`).
"""

from learners.registry import LEARNERS, SELECTORS, make_learner, make_selector

# Modules that register estimators (each helper/module adds its own import line below).
from learners import anfis, ar_temp, combination, linear, lssvm, neural, selection_stats  # noqa: F401,E402
from learners import gnnmci, grey, grey_gmc, selection_grey  # noqa: F401,E402

__all__ = ["LEARNERS", "SELECTORS", "make_learner", "make_selector"]
