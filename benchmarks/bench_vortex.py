"""Benchmark of the vortex-filament pipeline (issue 7): time per phase and peak memory, end to end.

For each mesh size a fresh child process runs :func:`dhlb.vortex.vortex_filaments` on the
Kuhn-triangulated cube ``[-1, 1]³`` with ``m`` cells per axis (``6 m³`` tetrahedra; ``m = 20``:
48 000, ``m = 32``: 196 608) and a velocity field (default: one vortex ring of radius 0.6,
circulation 2π, core radius 0.08, 64 Biot–Savart segments; ħ = 1), and reports the seconds spent
in each phase (mesh validation + geometry, ω = ∫v·dl and the bundle, assembly of the Theorem
15/17 matrices, eigen solve, filament extraction + linking numbers) and the peak resident memory
of the child (``resource.getrusage(RUSAGE_SELF).ru_maxrss``, which includes the interpreter and
the imported libraries, ~100 MB). Target of the issue: 200k tets in < 20 s with the best backend.

With ``--per-vertex`` the field is first sampled at the vertices (as a fluid solver would deliver
it; the sampling is reported as ``sample`` and not part of ``total``), so ``omega`` is the exact
line integral of the piecewise-linear field instead of 4 Biot–Savart evaluations per edge.

Run:  OPENBLAS_NUM_THREADS=1 python benchmarks/bench_vortex.py [--sizes 20 32] [--backend NAME]
      [--field ring|linked-rings] [--per-vertex] [--order Q] [--json]
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy is imported (also in the children)

import argparse
import json
import resource
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

SHIFT = (0.013, 0.007, 0.011)


def field(name: str):
    import numpy as np

    from dhlb.vortex import FilamentField, hopf_link, vortex_ring

    if name == "ring":
        curves = [vortex_ring(0.6, center=SHIFT, n=64)]
    elif name == "linked-rings":
        R = 0.55
        curves = [c + np.array(SHIFT) - [0.5 * R, 0, 0] for c in hopf_link(R, n=64)]
    else:
        raise SystemExit(f"unknown field {name!r}")
    return FilamentField(curves, 2 * np.pi, core_radius=0.08)


def single(m: int, backend, name: str, per_vertex: bool = False, order: int = 4) -> dict:
    """One run in this process; returns the figures."""
    import warnings

    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import VortexOptions, vortex_filaments

    t0 = time.perf_counter()
    mesh = box_tet_mesh(m, lower=-1.0, upper=1.0)
    t_gen = time.perf_counter() - t0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        v = field(name)
        t1 = time.perf_counter()
        if per_vertex:  # a sampled field, as from a fluid solver: ω is then the exact PL line integral
            v = v(mesh.points)
        t_sample = time.perf_counter() - t1
        res = vortex_filaments(mesh.points, mesh.tets, v, 1.0, solver=backend, options=VortexOptions(order=order))
    s = res.statistics
    return {
        "m": m, "tets": s["n_tets"], "vertices": s["n_vertices"], "field": name,
        "backend": s["solver"]["backend"], "iterations": s["solver"]["iterations"],
        "velocity_input": "per-vertex" if per_vertex else f"callable, order {order}",
        "generate": t_gen, "sample": t_sample, **dict(res.timings.items()),
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "filaments": s["n_filaments"], "closed": s["n_closed"], "linking": res.linking_numbers.tolist(),
        "max_flux": s["max_flux"], "warnings": len(caught),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[20, 32], help="cells per axis (default 20 32)")
    ap.add_argument("--backend", default=None, help="eigen-solver backend (default: dhlb's default)")
    ap.add_argument("--field", default="ring", choices=["ring", "linked-rings"])
    ap.add_argument("--per-vertex", action="store_true",
                    help="sample the field at the vertices first (not timed in 'total'; ω exact for the PL field)")
    ap.add_argument("--order", type=int, default=4, help="Gauss-Legendre nodes per edge for the callable field")
    ap.add_argument("--json", action="store_true", help="print one JSON object per size")
    ap.add_argument("--single", type=int, help=argparse.SUPPRESS)  # child mode
    args = ap.parse_args(argv)
    if args.single is not None:
        print(json.dumps(single(args.single, args.backend, args.field, args.per_vertex, args.order)))
        return 0
    cols = ("mesh", "omega", "assembly", "solve", "extraction", "total")
    if not args.json:
        print(f"{'tets':>8} {'verts':>7} {'backend':>11} " + " ".join(f"{c:>10}" for c in cols)
              + f" {'peak MB':>8} {'filaments':>9}")
    for m in args.sizes:
        cmd = [sys.executable, __file__, "--single", str(m), "--field", args.field, "--order", str(args.order)]
        if args.per_vertex:
            cmd.append("--per-vertex")
        if args.backend:
            cmd += ["--backend", args.backend]
        out = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if out.returncode != 0:
            print(f"m = {m}: failed\n{out.stderr.strip()}", file=sys.stderr)
            continue
        r = json.loads(out.stdout.strip().splitlines()[-1])
        if args.json:
            print(json.dumps(r))
        else:
            print(f"{r['tets']:>8} {r['vertices']:>7} {r['backend']:>11} " + " ".join(f"{r[c]:>9.2f}s" for c in cols)
                  + f" {r['peak_rss_mb']:>8.0f} {r['filaments']:>9}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
