"""Shared pytest configuration: hypothesis profiles.

The "ci" profile (loaded by default) is deterministic and modest; select another with
``HYPOTHESIS_PROFILE=dev pytest ...``.
"""

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    deadline=None,
    derandomize=True,
    max_examples=25,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
settings.register_profile("dev", deadline=None, max_examples=200,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

# tests/mpi holds scripts run under mpirun by tests/test_linalg_petsc.py (they need mpi4py), not test modules
collect_ignore = ["mpi"]
