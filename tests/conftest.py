"""Shared test set-up: the helper modules on ``sys.path`` and hypothesis' profiles.

Tests live in folders named like the packages they test (``tests/planning``, ``tests/synthesis``,
...); the helpers they share (``oracle``, ``routes``, ``strategies``, ``backends``) live in
``tests/helpers`` and are imported by their plain names (``from strategies import ...``), as the
suite runs with ``--import-mode=importlib``.
"""

import os
import sys

from hypothesis import HealthCheck, settings

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "helpers"))

settings.register_profile(
    "default", max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)
settings.register_profile("quick", max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))
