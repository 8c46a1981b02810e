"""Run every script in ``proofs/`` (sympy derivations of the closed forms) and require exit code 0.

Each script asserts its identities and exits non-zero on failure; files whose name starts with
``_`` are shared helpers, not scripts.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

PROOFS = Path(__file__).resolve().parent.parent / "proofs"
SCRIPTS = sorted(p.name for p in PROOFS.glob("*.py") if not p.name.startswith("_"))
TIMEOUT = 120  # seconds per script; each is designed to run in well under 60 s


def test_there_are_proof_scripts():
    assert any(name.startswith("derive_") for name in SCRIPTS)


@pytest.mark.parametrize("name", SCRIPTS)
def test_proof_script_succeeds(name):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONHASHSEED="0")
    try:
        res = subprocess.run([sys.executable, str(PROOFS / name)], cwd=PROOFS.parent, env=env,
                             capture_output=True, text=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:  # pragma: no cover - reported as a failure
        pytest.fail(f"proofs/{name} did not finish within {TIMEOUT} s")
    assert res.returncode == 0, (f"proofs/{name} failed (exit {res.returncode}):\n"
                                 f"{res.stdout[-3000:]}\n{res.stderr[-5000:]}")
    assert res.stdout.strip(), f"proofs/{name} printed no summary"
