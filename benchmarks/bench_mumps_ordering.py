"""MUMPS ordering (ICNTL(7)) and parallel analysis (ICNTL(28/29)) on the matrices dhlb factorizes (issue 31.4).

Usage (from the MPI environment of docs/mpi.md, ``PYTHONPATH`` at the repository root)::

    python benchmarks/bench_mumps_ordering.py --cases torus200k tet40 [--ranks 1 2] [--json OUT.json]

For each case it builds ``K = A + εM`` once (``ε`` = :func:`dhlb.linalg.eigen.default_shift`) and
saves it to ``/tmp/dhlb_mumps_<case>.npz``; then, for every configuration and rank count, it runs
``mpirun -n P python bench_mumps_ordering.py --worker ...`` which loads ``K`` on every rank, copies
its contiguous row block into a PETSc AIJ matrix (as ``_petsc_mat``), sets KSP ``preonly`` + PC LU
with MUMPS (options on the KSP prefix, as ``_direct_pc``) and times, with PETSc's log events, the
analysis (``MatLUFactorSym``: conversion to MUMPS' triples + MUMPS analysis phase) and the
factorization (``MatLUFactorNum``) of ``ksp.setUp()``, then the median of three solves.  It reads
back ``ICNTL(7)``, ``ICNTL(28)``, ``ICNTL(29)`` (the options applied; MUMPS' own
warnings, e.g. "SCOTCH not available", are collected from its ``ICNTL(4) = 2`` output), ``INFOG(7)`` (the ordering
MUMPS used), ``INFOG(32)`` (the analysis actually run: 1 sequential, 2 parallel), ``INFOG(29)``
(factor entries), ``INFOG(21)`` (MB used during factorization, largest rank), ``INFO(22)`` (MB on
each rank) and the peak resident memory (maxrss) of each rank.

Cases: ``torus200k`` (n = 4 field, :func:`bench_mpi.torus_mesh` with 200,000 faces), ``ico8``
(n = 4 field on the 1.31M-face icosphere of :func:`bench_scale.icosphere`), ``tetM`` (vortex
matrices of ``box_tet_mesh(M)``, 6 M³ tets, with the vortex-ring velocity of the doctest of
:mod:`dhlb.vortex.pipeline`).
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
sys.path.insert(0, str(ROOT / "benchmarks"))

ORDERINGS = {0: "AMD", 2: "AMF", 3: "SCOTCH", 4: "PORD", 5: "METIS", 6: "QAMD", 7: "auto"}
PAR_ORDERINGS = {1: "PT-Scotch", 2: "ParMETIS"}
# (label, ICNTL(28), ICNTL(7) or None, ICNTL(29) or None)
CONFIGS = [(f"seq {k} {v}", 1, k, None) for k, v in ORDERINGS.items()] + \
          [(f"par {k} {v}", 2, None, k) for k, v in PAR_ORDERINGS.items()]


def matrix_path(case: str) -> Path:
    return Path(f"/tmp/dhlb_mumps_{case}.npz")


def build(case: str) -> dict:
    """Assemble ``K = A + εM`` of ``case`` and save it (CSR, complex) to :func:`matrix_path`."""
    import scipy.sparse as sp

    from dhlb.linalg.eigen import default_shift

    t = time.perf_counter()
    if case in ("torus200k", "ico8"):
        from dhlb.fields import energy_matrices

        if case == "torus200k":
            from bench_mpi import torus_mesh
            V, F = torus_mesh(200_000)
        else:
            from bench_scale import icosphere
            V, F = icosphere(8)
        A, M = energy_matrices(V, F, n=4)
        size = {"faces": len(F)}
    elif case.startswith("tet"):
        from dhlb.fem import bundle_matrices
        from dhlb.geometry import EuclideanComplex
        from dhlb.mesh import box_tet_mesh
        from dhlb.vortex import FilamentField, velocity_bundle, vortex_ring

        mesh = box_tet_mesh(int(case[3:]), lower=-1.5, upper=1.5)
        v = FilamentField([vortex_ring(0.8, center=(0.01, 0.02, 0.03), n=48)], 2 * np.pi, core_radius=0.15)
        X, P = mesh.complex, mesh.points
        L = velocity_bundle(X, P, v, 1.0)
        A, M = bundle_matrices(L, EuclideanComplex(X, points=P))
        size = {"tets": int(X.n_simplices(3))}
    else:
        raise SystemExit(f"unknown case {case!r}")
    eps = default_shift(A, M)
    K = sp.csr_matrix(A + eps * M)
    K.sort_indices()
    np.savez(matrix_path(case), data=K.data, indices=K.indices, indptr=K.indptr, shape=K.shape)
    return {"case": case, **size, "unknowns": K.shape[0], "nnz": K.nnz, "eps": eps,
            "build_seconds": time.perf_counter() - t}


def load(case: str):
    import scipy.sparse as sp

    z = np.load(matrix_path(case))
    return sp.csr_matrix((z["data"], z["indices"], z["indptr"]), shape=tuple(z["shape"]))


def worker(case: str, icntl28: int, icntl7: int | None, icntl29: int | None) -> None:
    from mpi4py import MPI
    from petsc4py import PETSc

    from dhlb.linalg.backends_petsc import _petsc_mat

    comm = MPI.COMM_WORLD
    PETSc.Log.begin()
    K = load(case)
    Kp = _petsc_mat(K)
    n = K.shape[0]
    del K
    prefix = "bench_"
    opts = PETSc.Options(prefix)
    opts.setValue("mat_mumps_icntl_24", 1)   # as _direct_pc
    opts.setValue("mat_mumps_icntl_28", icntl28)
    if icntl7 is not None:
        opts.setValue("mat_mumps_icntl_7", icntl7)
    if icntl29 is not None:
        opts.setValue("mat_mumps_icntl_29", icntl29)
    opts.setValue("mat_mumps_icntl_4", 2)     # MUMPS' warnings and its own timings, parsed by run()
    ksp = PETSc.KSP().create(comm=PETSc.COMM_WORLD)
    ksp.setOptionsPrefix(prefix)
    ksp.setOperators(Kp)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    pc.setFactorSolverType("mumps")
    ksp.setFromOptions()
    sym, num = PETSc.Log.Event("MatLUFactorSym"), PETSc.Log.Event("MatLUFactorNum")
    out = {"case": case, "ranks": comm.size, "unknowns": n, "icntl28_req": icntl28, "icntl7_req": icntl7,
           "icntl29_req": icntl29}
    comm.Barrier()
    t = time.perf_counter()
    try:
        ksp.setUp()
    except PETSc.Error as err:
        F = pc.getFactorMatrix()
        out.update(error=f"PETSc error {err.ierr}", infog1=F.getMumpsInfog(1), infog2=F.getMumpsInfog(2))
        if comm.rank == 0:
            print(json.dumps(out), flush=True)
        return
    setup = comm.allreduce(time.perf_counter() - t, op=MPI.MAX)
    F = pc.getFactorMatrix()
    if F.getMumpsInfog(1) < 0:   # PETSc 3.18 does not raise here; the KSP would report DIVERGED_PC_FAILED
        out.update(error="MUMPS failed", setup_s=setup, infog1=F.getMumpsInfog(1), infog2=F.getMumpsInfog(2),
                   icntl7=F.getMumpsIcntl(7), icntl28=F.getMumpsIcntl(28), icntl29=F.getMumpsIcntl(29))
        if comm.rank == 0:
            print(json.dumps(out), flush=True)
        return
    si, ni = sym.getPerfInfo(), num.getPerfInfo()
    b = Kp.createVecRight()
    x = Kp.createVecLeft()
    b.setRandom()
    solves = []
    for _ in range(3):
        comm.Barrier()
        t = time.perf_counter()
        ksp.solve(b, x)
        solves.append(comm.allreduce(time.perf_counter() - t, op=MPI.MAX))
    r = Kp.createVecLeft()
    Kp.mult(x, r)
    r.axpy(-1, b)
    entries = F.getMumpsInfog(29)
    out.update(
        setup_s=setup,
        analysis_s=comm.allreduce(si["time"], op=MPI.MAX), factor_s=comm.allreduce(ni["time"], op=MPI.MAX),
        sym_count=si["count"], num_count=ni["count"], solve_s=float(np.median(solves)), solves_s=solves,
        rel_residual=r.norm() / b.norm(), reason=ksp.getConvergedReason(),
        icntl7=F.getMumpsIcntl(7), icntl28=F.getMumpsIcntl(28), icntl29=F.getMumpsIcntl(29),
        infog1=F.getMumpsInfog(1), infog2=F.getMumpsInfog(2), infog7=F.getMumpsInfog(7),
        infog32=F.getMumpsInfog(32), factor_entries=float(entries if entries >= 0 else -entries * 1e6),
        factor_flops=float(F.getMumpsRinfog(3)), infog21_mb=F.getMumpsInfog(21), infog22_mb=F.getMumpsInfog(22),
        info22_mb_per_rank=comm.gather(F.getMumpsInfo(22), root=0),
        maxrss_mb_per_rank=comm.gather(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, root=0))
    if comm.rank == 0:
        print(json.dumps(out), flush=True)


def run(case, ranks, label, i28, i7, i29, timeout) -> dict:
    mpirun = shutil.which("mpirun")
    cmd = [mpirun, "-n", str(ranks)] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + \
          [sys.executable, __file__, "--worker", "--case", case, "--icntl28", str(i28)] + \
          (["--icntl7", str(i7)] if i7 is not None else []) + (["--icntl29", str(i29)] if i29 is not None else [])
    env = {**os.environ, "OMPI_MCA_rmaps_base_oversubscribe": "1", "OPENBLAS_NUM_THREADS": "1",
           "OMP_NUM_THREADS": "1", "PYTHONPATH": str(ROOT)}
    load1 = os.getloadavg()[0]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"case": case, "ranks": ranks, "label": label, "error": f"timeout {timeout} s", "load1": load1}
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
    res = json.loads(lines[-1]) if lines else {"error": f"rc {p.returncode}: " + " | ".join(
        (p.stderr + p.stdout).strip().splitlines()[-4:])}
    res.update(case=case, ranks=ranks, label=label, load1=load1,
               mumps_warnings=sorted({ln.strip() for ln in p.stdout.splitlines()
                                      if "WARNING" in ln or "not available" in ln}))
    for key, text in (("mumps_analysis_s", "Elapsed time in analysis driver="),
                      ("mumps_factor_s", "Elapsed time in factorization driver=")):
        hits = [float(ln.split("=")[-1]) for ln in p.stdout.splitlines() if text in ln]
        if hits:
            res[key] = hits[0]
    return res


def fmt(r) -> str:
    head = f"{r['case']:<10} {r['ranks']}  {r['label']:<16}"
    if "error" in r:
        return (f"{head} ERROR {r['error']} (INFOG(1..2) = {r.get('infog1')}, {r.get('infog2')}) "
                f"load {r['load1']:.2f} {'; '.join(r.get('mumps_warnings', []))}")
    return (f"{head} ana {r['analysis_s']:7.2f}  fac {r['factor_s']:7.2f}  sol {r['solve_s']:6.3f}  "
            f"entries {r['factor_entries']:.3e}  INFOG21 {r['infog21_mb']:6d} MB  "
            f"rss {'/'.join(f'{m:.0f}' for m in r['maxrss_mb_per_rank'])} MB  "
            f"ICNTL7 {r['icntl7']} INFOG7 {r['infog7']} ICNTL28 {r['icntl28']} ICNTL29 {r['icntl29']} "
            f"INFOG32 {r['infog32']} INFOG1 {r['infog1']}  res {r['rel_residual']:.1e}  load {r['load1']:.2f}  "
            f"(MUMPS: ana {r.get('mumps_analysis_s')} fac {r.get('mumps_factor_s')}) {'; '.join(r['mumps_warnings'])}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=["torus200k", "tet40"])
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--configs", nargs="*", default=None, help="labels' first two words, e.g. 'seq 5' 'par 1'")
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--json", default=None)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--build", action="store_true", help="only build the matrices")
    ap.add_argument("--case")
    ap.add_argument("--icntl28", type=int, default=1)
    ap.add_argument("--icntl7", type=int, default=None)
    ap.add_argument("--icntl29", type=int, default=None)
    args = ap.parse_args()
    if args.worker:
        return worker(args.case, args.icntl28, args.icntl7, args.icntl29)
    results = []
    for case in args.cases:
        if not matrix_path(case).exists():
            print(json.dumps(build(case)), flush=True)
        if args.build:
            continue
        for label, i28, i7, i29 in CONFIGS:
            if args.configs and " ".join(label.split()[:2]) not in args.configs:
                continue
            for p in args.ranks:
                r = run(case, p, label, i28, i7, i29, args.timeout)
                results.append(r)
                print(fmt(r), flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
