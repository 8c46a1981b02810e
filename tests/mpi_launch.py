"""Start ``mpirun -n P python ARGS`` from a test: one launcher for every MPI test file."""

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MPIRUN = shutil.which("mpirun")


def mpirun(size: int, args: list, timeout: float = 600):
    """``(CompletedProcess, seconds)`` of ``mpirun -n size python *args`` in the repository (oversubscribed).

    The ranks run this checkout (``PYTHONPATH``) with one BLAS thread; as root, ``--allow-run-as-root``.
    """
    cmd = [MPIRUN, "-n", str(size)] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + [sys.executable]
    env = {**os.environ, "OMPI_MCA_rmaps_base_oversubscribe": "1", "OPENBLAS_NUM_THREADS": "1",
           "PYTHONPATH": str(ROOT)}
    t = time.perf_counter()
    proc = subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=timeout, env=env, cwd=ROOT)
    return proc, time.perf_counter() - t
