"""Benchmark of the solver backends (issue 8): every installed backend on a surface and a tet mesh.

For each problem and each available backend (:func:`dhlb.fem.backends.available_backends`):

* ``real``  — factorization + one solve of the plain real cotangent Laplacian ``L + εM``
  (``L_ref`` is this figure for the fastest direct backend, measured in the same run);
* ``cplx``  — factorization + one solve of ``A + εM`` for the complex line-bundle matrix ``A``;
* ``eig``   — :func:`dhlb.fem.smallest_eigenpairs` (k = 1, tol = 1e-9) end to end, with its
  iteration count and ratio ``eig / L_ref``.

Problems: the 69k-face Stanford bunny with its n = 4 tangent bundle (unreferenced vertices
compacted away), and a box tet mesh (``--m`` cells per axis; 32 gives 196,608 tets) with the
bundle of a vortex ring's velocity field.  For an iterative backend ``real``/``cplx`` are the
AMG setup plus one preconditioned CG solve to 1e-12.

Run:  python benchmarks/bench_solvers.py [--m 32] [--skip-direct-3d] [--json PATH]
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import json
import platform
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from dhlb.fem import bundle_matrices, smallest_eigenpairs
from dhlb.fem.backends import available_backends, clear_cache, get_backend
from dhlb.fem.solvers import default_shift
from dhlb.geometry import EuclideanComplex

BUNNY = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "meshes", "stanford-bunny.obj")


def bunny_problem(path=BUNNY):
    from dhlb.io import compact_mesh, read_surface
    from dhlb.surface import tangent_bundle

    V, F = read_surface(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        V, F, _ = compact_mesh(V, F)
    tb = tangent_bundle(V, F, n=4)
    A, M = bundle_matrices(tb.bundle, tb.geometry)
    return f"bunny ({len(F)} faces)", A, M, tb.geometry.stiffness_matrix(), tb.geometry.mass_matrix()


def box_problem(m):
    from dhlb.volume import FilamentField, box_tet_mesh, velocity_bundle, vortex_ring

    mesh = box_tet_mesh(m, lower=-1.0, upper=1.0)
    v = FilamentField([vortex_ring(0.5, n=64)], circulation=1.0, core_radius=0.1)
    bundle = velocity_bundle(mesh.complex, mesh.points, v, hbar=1 / (2 * np.pi), order=2)
    E = EuclideanComplex(mesh.complex, points=mesh.points)
    A, M = bundle_matrices(bundle, E)
    return f"box tets ({len(mesh.tets)} tets)", A, M, E.stiffness_matrix(), E.mass_matrix()


def best_of(f, repeat):
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t)
    return min(ts), out


def factor_solve(name, K):
    be = get_backend(name)
    b = np.random.default_rng(0).standard_normal(K.shape[0])
    clear_cache()                                   # time the first factorization (analysis included)
    return be.factorize(K.tocsc(), positive_definite=True).solve(b.astype(K.dtype))


def run_problem(label, A, M, L, M0, backends, repeat):
    n = A.shape[0]
    KA = (A + default_shift(A.tocsr(), M.tocsr()) * M).tocsc()
    KL = (L + default_shift(L.tocsr(), M0.tocsr()) * M0).tocsc()
    rows = []
    for name in backends:
        t_real, _ = best_of(lambda name=name: factor_solve(name, KL), repeat)
        t_cplx, _ = best_of(lambda name=name: factor_solve(name, KA), repeat)

        def eig(name=name):
            clear_cache()
            return smallest_eigenpairs(A, M, k=1, tol=1e-9, backend=name)

        t_eig, res = best_of(eig, repeat)
        rows.append({"problem": label, "n": n, "nnz": int(A.nnz), "backend": name, "real": t_real, "cplx": t_cplx,
                     "eig": t_eig, "iterations": int(res.iterations), "eigenvalue": float(res.eigenvalues[0])})
        print(f"  {name:<11} real {t_real:8.3f} s   cplx {t_cplx:8.3f} s   eig {t_eig:8.3f} s "
              f"({res.iterations} it, λ₁ = {res.eigenvalues[0]:.10g})", flush=True)
    direct = [r for r in rows if r["backend"] != "amg-lobpcg"]
    l_ref = min(r["real"] for r in (direct or rows))
    for r in rows:
        r["L_ref"] = l_ref
        r["eig_over_L_ref"] = r["eig"] / l_ref
    auto = get_backend(None, n=n, nnz=A.nnz, eigen=True).name
    print(f"  L_ref = {l_ref:.3f} s; auto chooses {auto!r}; eig / L_ref: "
          + ", ".join(f"{r['backend']} {r['eig_over_L_ref']:.1f}" for r in rows), flush=True)
    return rows, auto


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--m", type=int, default=32, help="cells per axis of the tet box (32: 196,608 tets)")
    ap.add_argument("--repeat", type=int, default=2, help="best of this many runs")
    ap.add_argument("--skip-direct-3d", action="store_true", help="only the iterative backend on the tet box")
    ap.add_argument("--json", default=os.path.join(os.path.dirname(__file__), "bench_solvers.json"))
    args = ap.parse_args(argv)
    backends = available_backends()
    print(f"backends available: {backends}; OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}")
    out = {"machine": platform.machine(), "cpus": os.cpu_count(), "backends": backends, "results": [], "auto": {}}
    for make, bes in ((bunny_problem, backends),
                      (lambda: box_problem(args.m),
                       [b for b in backends if b == "amg-lobpcg"] if args.skip_direct_3d else backends)):
        t = time.perf_counter()
        label, A, M, L, M0 = make()
        print(f"{label}: n = {A.shape[0]}, nnz = {A.nnz}, assembly {time.perf_counter() - t:.2f} s", flush=True)
        rows, auto = run_problem(label, A, M, L, M0, bes, args.repeat)
        out["results"] += rows
        out["auto"][label] = auto
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
