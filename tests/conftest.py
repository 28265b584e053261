"""Hypothesis profiles: "ci" (the default: 200 examples a test, derandomized so that a CI run
is reproducible) and "long" for fuzzing runs, random and 5000 examples a test.

    HYPOTHESIS_PROFILE=long python3 -m pytest -q tests/test_hardening.py
"""

import os

from hypothesis import HealthCheck, settings

settings.register_profile("ci", max_examples=200, deadline=None, derandomize=True, print_blob=True)
settings.register_profile("long", max_examples=5000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
