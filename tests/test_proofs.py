"""Run every script in ``proofs/`` (sympy derivations of the closed forms) and require exit code 0.

Each script asserts its identities and exits non-zero on failure; files whose name starts with
``_`` are shared helpers, not scripts.

A script's budget is **CPU time** (:data:`CPU_LIMIT`, enforced by ``RLIMIT_CPU`` in the child), not
wall-clock time: on a machine loaded by other work the wall time of the same computation grows
several-fold (issue 42: at load 6–7 two scripts ran into a 120 s wall-clock timeout, one taking
51 s of wall time that it needs 16 s for on a quiet machine), while its CPU time does not.  A
wall-clock limit (:data:`WALL_LIMIT`) remains only against a script that hangs without computing.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

PROOFS = Path(__file__).resolve().parent.parent / "proofs"
SCRIPTS = sorted(p.name for p in PROOFS.glob("*.py") if not p.name.startswith("_"))
CPU_LIMIT = 120      # CPU seconds per script; each needs well under 60 s of CPU
WALL_LIMIT = 1800    # wall-clock seconds: only a hung script reaches this, whatever the machine's load


def run_script(path, *, cpu_limit=CPU_LIMIT, wall_limit=WALL_LIMIT):
    """``(returncode, stdout, stderr, why)`` of ``python path``; ``why`` names an exceeded budget, else ``""``."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONHASHSEED="0")
    limit = None
    if hasattr(os, "fork"):   # POSIX: the kernel stops the child after cpu_limit seconds of CPU (SIGXCPU)
        def limit():
            import resource

            resource.setrlimit(resource.RLIMIT_CPU, (int(cpu_limit), int(cpu_limit) + 5))
    try:
        res = subprocess.run([sys.executable, str(path)], cwd=PROOFS.parent, env=env, capture_output=True,
                             text=True, timeout=wall_limit, preexec_fn=limit)
    except subprocess.TimeoutExpired:  # pragma: no cover - reported as a failure
        return None, "", "", f"did not finish within {wall_limit} s of wall-clock time (hung?)"
    stopped = {-signal.SIGXCPU, -signal.SIGKILL} if hasattr(signal, "SIGXCPU") else set()   # soft, hard limit
    why = f"used more than its {cpu_limit} s of CPU time" if res.returncode in stopped else ""
    return res.returncode, res.stdout, res.stderr, why


def test_there_are_proof_scripts():
    assert any(name.startswith("derive_") for name in SCRIPTS)


@pytest.mark.skipif(not hasattr(signal, "SIGXCPU"), reason="no RLIMIT_CPU on this platform")
def test_the_budget_is_cpu_time_not_wall_time(tmp_path):
    idle = tmp_path / "idle.py"          # 3 s of wall time, almost no CPU: a loaded machine's slow script
    idle.write_text("import time\ntime.sleep(3)\nprint('done')\n")
    code, out, _, why = run_script(idle, cpu_limit=1, wall_limit=60)
    assert code == 0 and out.strip() == "done" and not why
    busy = tmp_path / "busy.py"          # a script that computes past its CPU budget is stopped, and said so
    busy.write_text("while True:\n    pass\n")
    code, _, _, why = run_script(busy, cpu_limit=1, wall_limit=60)
    assert code != 0 and "1 s of CPU time" in why


@pytest.mark.parametrize("name", SCRIPTS)
def test_proof_script_succeeds(name):
    code, out, err, why = run_script(PROOFS / name)
    assert not why, f"proofs/{name} {why}"
    assert code == 0, f"proofs/{name} failed (exit {code}):\n{out[-3000:]}\n{err[-5000:]}"
    assert out.strip(), f"proofs/{name} printed no summary"
