"""Issue 31: the distributed field and vortex at 1 and 2 MPI ranks — wall time per phase, peak memory per rank.

Usage (from the MPI environment of docs/mpi.md)::

    python benchmarks/bench_mpi.py [--cases torus200k ico8 box56] [--ranks 1 2] [--json OUT.json]

Cases: ``torus200k`` the n = 4 field on a 200,704-face torus grid; ``ico8`` the n = 4 field on the
icosphere of level 8 (1,310,720 faces, subdivision order); ``box56`` the linked-rings vortex on the
Freudenthal–Kuhn box with 56 cells per axis (1,053,696 tetrahedra). For each case and rank count P
it runs ``mpirun -n P python bench_mpi.py --worker CASE``: rank 0 builds the surface (the box: every
rank builds its own slab, :func:`dhlb.mesh.distribute.distribute_box`, as ``dhlb vortex --box``), then
every rank runs :func:`dhlb.fields.distributed.distributed_direction_field` or
:func:`dhlb.vortex.distributed.distributed_vortex_filaments`, which report the seconds and the peak
resident memory (``VmHWM``, reset at every phase) of every phase on every rank. It prints one row per
run and the issue's two memory ratios:

* the assembly-phase peak per rank at 2 ranks ÷ that of 1 rank (target ≤ 0.6, every case), also above
  the baseline: the resident memory of the loaded interpreter and libraries before any data (~90 MB);
* the whole run's peak per rank at 2 ranks ÷ that of 1 rank on ``ico8`` (target ≤ 0.6).

Speed-up on a 2-core machine shared with other work is not a target; it is printed. Run with
``OPENBLAS_NUM_THREADS=1``; the load average is printed with every run.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

CASES = {"torus200k": "n = 4 field, torus grid 200,704 faces", "ico8": "n = 4 field, icosphere level 8 (1.31M faces)",
         "box56": "vortex linked rings, box 56³ (1.05M tets)", "torus20k": "n = 4 field, torus grid 20k faces (smoke)",
         "box16": "vortex linked rings, box 16³ (smoke)"}


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


def icosphere(level: int):
    from benchmarks.bench_scale import icosphere as ico

    return ico(level)


def worker(case: str) -> None:
    from mpi4py import MPI
    from petsc4py import PETSc  # noqa: F401
    from slepc4py import SLEPc  # noqa: F401

    import dhlb.fields.distributed
    import dhlb.linalg.distributed
    import dhlb.vortex.distributed  # noqa: F401 -- loaded before the baseline is read
    from dhlb._phases import rss_mb

    comm = MPI.COMM_WORLD
    baseline = comm.gather(rss_mb(), root=0)   # interpreter, numpy/scipy, MPI, PETSc, SLEPc, dhlb: before any data
    t = time.perf_counter()
    if case.startswith(("torus", "ico")):
        from dhlb.fields.distributed import distributed_direction_field

        if comm.rank == 0:
            V, F = torus_mesh(200_000 if case == "torus200k" else 20_000) if case.startswith("torus") else icosphere(8)
        else:
            V = F = None
        build = time.perf_counter() - t
        comm.Barrier()
        t = time.perf_counter()
        res = distributed_direction_field(V, F, n=4)
        size = None if res is None else {
            "faces": int(res.mesh.n_faces), "unknowns": int(res.mesh.n_vertices), "eigenvalue": float(res.eigenvalue),
            "singularities": len(res.singularities.faces)}
    else:
        from dhlb.cli.vortex import demo_velocity
        from dhlb.mesh.distribute import distribute_box
        from dhlb.vortex.distributed import distributed_vortex_filaments

        m = int(case[3:])
        field, _ = demo_velocity("linked-rings", np.array([[-1.0, -1, -1], [1, 1, 1]]))
        build = 0.0
        comm.Barrier()
        t = time.perf_counter()
        loc = distribute_box(m, -1.0, 1.0, comm=comm)      # as dhlb vortex --box: each rank builds its slab
        t_box = time.perf_counter() - t
        res = distributed_vortex_filaments(loc, None, field, 1.0)
        if res is not None:
            res.timings["box"] = t_box
        size = None if res is None else {
            "tets": int(res.statistics["n_tets"]), "unknowns": int(res.statistics["n_vertices"]),
            "eigenvalue": float(res.eigenvalue), "filaments": len(res.filaments),
            "linking": res.linking_numbers.tolist()}
    elapsed = comm.allreduce(time.perf_counter() - t, op=MPI.MAX)
    if comm.rank == 0:
        st = res.solver if hasattr(res, "solver") else res.statistics["solver"]
        par = st["parallel"]
        print(json.dumps({"case": case, "ranks": comm.size, "seconds": elapsed, "build_mesh_seconds": build,
                          "baseline_mb": baseline,
                          "timings": res.timings, "peak_mb": par["peak_mb"], "start_mb": par["start_mb"],
                          "method": par["method"],
                          "owned": par["owned_vertices"], "local": par["local_vertices"], "mumps": st.get("mumps", {}),
                          "iterations": st["iterations"], "residual": st["residual"], **size}))


def run_case(mpirun: str, case: str, ranks: int, timeout: float) -> dict:
    cmd = [mpirun, "-n", str(ranks)] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + \
          [sys.executable, __file__, "--worker", case]
    env = {**os.environ, "OMPI_MCA_rmaps_base_oversubscribe": "1", "OPENBLAS_NUM_THREADS": "1",
           "PYTHONPATH": str(ROOT)}
    load = os.getloadavg()[0]
    t = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    if out.returncode != 0:
        return {"case": case, "ranks": ranks, "error": (out.stderr or out.stdout).strip().splitlines()[-3:],
                "load": load}
    run = json.loads(out.stdout.strip().splitlines()[-1])
    run["load"], run["wall"] = load, time.perf_counter() - t
    return run


def _peak(run: dict, phase: str | None = None) -> float:
    """The largest peak over the ranks (and over the phases unless ``phase`` is given), MB."""
    return max(max(p.values()) if phase is None else p.get(phase, 0.0) for p in run["peak_mb"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=["torus200k", "ico8", "box56"], choices=sorted(CASES))
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--timeout", type=float, default=1800)
    ap.add_argument("--json", default=None)
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return worker(args.worker)
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        sys.exit("bench_mpi: mpirun not found (see docs/mpi.md)")
    results = []
    for case in args.cases:
        runs = {}
        for p in args.ranks:
            r = run_case(mpirun, case, p, args.timeout)
            results.append(r)
            runs[p] = r
            if "error" in r:
                print(f"{CASES[case]}, {p} rank(s): FAILED {r['error']} (load {r['load']:.1f})", flush=True)
                continue
            assembly = "assembly"
            phases = ", ".join(f"{k} {v:.2f}" for k, v in r["timings"].items() if k not in ("total", "setup"))
            print(f"{CASES[case]}, {p} rank(s) [{r['method']}], load {r['load']:.1f}: {r['seconds']:.2f} s ({phases}); "
                  f"peak MB per rank {[round(max(q.values())) for q in r['peak_mb']]}, assembly-phase peak "
                  f"{[round(q.get(assembly, 0)) for q in r['peak_mb']]}; owned {r['owned']}, local {r['local']}",
                  flush=True)
        if 1 in runs and 2 in runs and "error" not in runs[1] and "error" not in runs[2]:
            a = _peak(runs[2], "assembly") / _peak(runs[1], "assembly")
            w = _peak(runs[2]) / _peak(runs[1])
            base = [max(runs[p]["baseline_mb"]) for p in (1, 2)]
            a_net = (_peak(runs[2], "assembly") - base[1]) / (_peak(runs[1], "assembly") - base[0])
            grown = [max(q["assembly"] - s["assembly"] for q, s in zip(runs[p]["peak_mb"], runs[p]["start_mb"]))
                     for p in (1, 2)]
            target = " (target <= 0.6)" if case == "ico8" else ""
            print(f"  {case}: 2 ranks / 1 rank: assembly-phase peak per rank {a:.2f} (target <= 0.6; above the "
                  f"{base[0]:.0f} MB baseline of the libraries: {a_net:.2f}; allocated by the assembly itself "
                  f"{grown[1]:.0f} / {grown[0]:.0f} MB = {grown[1] / grown[0]:.2f}), whole-run peak per rank "
                  f"{w:.2f}{target}, time {runs[2]['seconds'] / runs[1]['seconds']:.2f}", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
