"""The ``petsc`` backend under MPI: n = 4 field on a torus surface with 1 and 2 ranks vs the default backend.

Usage (from the MPI environment of docs/mpi.md)::

    python benchmarks/bench_mpi.py [--faces 200000] [--ranks 1 2] [--json OUT.json]

For each rank count P it runs ``mpirun -n P python bench_mpi.py --worker`` (which times
``direction_field(V, F, n=4, solver="petsc")`` and reports the peak resident memory of every
rank and MUMPS' factor statistics) and, in one plain process, the default backend.  It prints
time, peak memory per rank and the ratio to the default backend, then a *projection* (a model,
not a measurement) to 16 and 64 ranks on 10M and 100M faces: factor entries ``∝ N log N`` and
factorization flops ``∝ N^{3/2}`` (nested dissection of a 2-D mesh, George 1973), anchored at
the measured MUMPS figures; memory per rank = (factor + matrices) / P, time = flops / (P × the
measured flop rate × a parallel efficiency of 0.5).
"""

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def torus_mesh(faces: int):
    """A (3:1) torus triangulated by a ``2 m × m`` grid, about ``faces`` triangles."""
    m = max(8, round(np.sqrt(faces / 4)))
    u, v = np.meshgrid(np.arange(2 * m) * 2 * np.pi / (2 * m), np.arange(m) * 2 * np.pi / m, indexing="ij")
    V = np.column_stack([((3 + np.cos(v)) * np.cos(u)).ravel(), ((3 + np.cos(v)) * np.sin(u)).ravel(),
                         np.sin(v).ravel()])
    i, j = np.meshgrid(np.arange(2 * m), np.arange(m), indexing="ij")
    a = (i * m + j).ravel()
    b = (((i + 1) % (2 * m)) * m + j).ravel()
    c = (((i + 1) % (2 * m)) * m + (j + 1) % m).ravel()
    d = (i * m + (j + 1) % m).ravel()
    return V, np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux: kilobytes


def worker(faces: int) -> None:
    from mpi4py import MPI

    from dhlb.fields import direction_field
    from dhlb.linalg import backends
    from dhlb.linalg.backends_petsc import PetscBackend

    made = []

    def factory():
        made.append(PetscBackend())
        return made[-1]

    backends.register_backend("petsc", factory, ("petsc4py", "slepc4py", "mpi4py"))
    V, F = torus_mesh(faces)
    MPI.COMM_WORLD.Barrier()
    t = time.perf_counter()
    res = direction_field(V, F, n=4, solver="petsc")
    elapsed = MPI.COMM_WORLD.allreduce(time.perf_counter() - t, op=MPI.MAX)
    mem = MPI.COMM_WORLD.gather(peak_mb(), root=0)
    if MPI.COMM_WORLD.rank == 0:
        print(json.dumps({"ranks": MPI.COMM_WORLD.size, "faces": len(F), "unknowns": len(V), "seconds": elapsed,
                          "peak_mb_per_rank": mem, "eigenvalue": float(res.eigenvalue),
                          "mumps": made[-1].stats if made else {}}))


def default_worker(faces: int) -> None:
    from dhlb.fields import direction_field

    V, F = torus_mesh(faces)
    t = time.perf_counter()
    res = direction_field(V, F, n=4)
    seconds = time.perf_counter() - t
    print(json.dumps({"seconds": seconds, "peak_mb": peak_mb(), "eigenvalue": float(res.eigenvalue),
                      "backend": res.solver.get("backend") if isinstance(res.solver, dict) else str(res.solver)}))


def default_run(faces: int) -> dict:
    cmd = [sys.executable, __file__, "--default-worker", "--faces", str(faces)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def projection(run: dict) -> list[dict]:
    """Model (not a measurement): nested-dissection scaling of the measured MUMPS figures."""
    st = run["mumps"]
    n0, fill0, flops0 = run["unknowns"], st["factor_entries"], st["factor_flops"]
    rate = flops0 / run["seconds"] / run["ranks"]  # flop/s per rank, whole solve (an underestimate)
    rows = []
    for faces in (10_000_000, 100_000_000):
        n = faces / 2  # a closed surface has about F/2 vertices
        fill = fill0 * (n * np.log(n)) / (n0 * np.log(n0))
        flops = flops0 * (n / n0) ** 1.5
        for p in (16, 64):
            bytes_ = (fill * 16 + n * 14 * (16 + 8) * 2) / p  # complex factor + A, M in AIJ
            rows.append({"faces": faces, "ranks": p, "gb_per_rank": bytes_ / 2**30,
                         "hours": flops / (p * rate * 0.5) / 3600, "label": "projection (model, not measured)"})
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--faces", type=int, default=200_000)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--json", default=None)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--default-worker", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return worker(args.faces)
    if args.default_worker:
        return default_worker(args.faces)
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        sys.exit("bench_mpi: mpirun not found (see docs/mpi.md)")
    ref = default_run(args.faces)
    print(f"default backend ({ref['backend']}), 1 process: {ref['seconds']:.2f} s, peak {ref['peak_mb']:.0f} MB")
    runs = []
    for p in args.ranks:
        cmd = [mpirun, "-n", str(p)] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + \
              [sys.executable, __file__, "--worker", "--faces", str(args.faces)]
        out = subprocess.run(cmd, capture_output=True, text=True, check=True,
                             env={**os.environ, "OMPI_MCA_rmaps_base_oversubscribe": "1"})
        run = json.loads(out.stdout.strip().splitlines()[-1])
        run["ratio_to_default"] = run["seconds"] / ref["seconds"]
        run["eigenvalue_rel_diff"] = abs(run["eigenvalue"] / ref["eigenvalue"] - 1)
        runs.append(run)
        st = run["mumps"]
        print(f"petsc, {p} rank(s): {run['faces']:,} faces, {run['unknowns']:,} unknowns: {run['seconds']:.2f} s "
              f"(x{run['ratio_to_default']:.2f} default), "
              f"peak MB per rank {[round(m) for m in run['peak_mb_per_rank']]}, "
              f"MUMPS factor {st.get('factor_entries', 0):.3g} entries, {st.get('factor_flops', 0):.3g} flops, "
              f"eigenvalue rel. diff {run['eigenvalue_rel_diff']:.1e}")
    proj = projection(runs[-1])
    print("PROJECTION (model from the last measured run, not a measurement):")
    for r in proj:
        print(f"  {r['faces']:>11,} faces, {r['ranks']:>2} ranks: {r['gb_per_rank']:.2f} GB per rank, "
              f"~{r['hours']:.2f} h factorization")
    if args.json:
        Path(args.json).write_text(json.dumps({"default": ref, "petsc": runs, "projection": proj}, indent=1))


if __name__ == "__main__":
    main()
