"""Hypothesis profiles: "ci" (the default: 200 examples a test, derandomized so that a CI run
is reproducible) and "long" for fuzzing runs, random and 5000 examples a test.

    HYPOTHESIS_PROFILE=long python3 -m pytest -q tests/test_sweep_random_linkages.py

Tests marked ``numba`` need the optional numba (the ``fast`` extra): they are skipped, with the
reason, where it cannot be imported.
"""

import os

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile("ci", max_examples=200, deadline=None, derandomize=True, print_blob=True)
settings.register_profile("long", max_examples=5000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def _numba_missing():
    try:
        import numba  # noqa: F401
    except ImportError as e:
        return str(e) or "numba cannot be imported"
    return None


def pytest_collection_modifyitems(config, items):
    marked = [item for item in items if item.get_closest_marker("numba")]
    why = _numba_missing() if marked else None
    if why:
        skip = pytest.mark.skip(reason=f"needs numba (pip install '.[fast]'): {why}")
        for item in marked:
            item.add_marker(skip)
