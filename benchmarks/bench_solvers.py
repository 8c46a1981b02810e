"""Benchmark of the solver backends (issue 8): every installed backend on a surface and a tet mesh.

For each problem and each available backend (:func:`dhlb.linalg.available_backends`):

* ``real``  — factorization + one solve of the plain real cotangent Laplacian ``L + εM``
  (``L_ref`` is this figure for the fastest direct backend, measured in the same run);
* ``cplx``  — factorization + one solve of ``A + εM`` for the complex line-bundle matrix ``A``;
* ``eig``   — :func:`dhlb.fem.smallest_eigenpairs` (k = 1, tol = 1e-9) end to end, with its
  iteration count and ratio ``eig / L_ref``.

Problems: the 69k-face Stanford bunny with its n = 4 tangent bundle (unreferenced vertices
compacted away), and a box tet mesh (``--m`` cells per axis; 32 gives 196,608 tets) with the
bundle of a vortex ring's velocity field.  For an iterative backend ``real``/``cplx`` are the
AMG setup plus one preconditioned CG solve to 1e-12.

Then, side by side in the same run (issue 30): dhlb's shift-and-invert Lanczos
(:mod:`dhlb.linalg._lanczos`) against ARPACK, which it replaced, on the bunny with k = 1 and k = 6
and on a Landau level of multiplicity 12 (flat torus, degree 12, k = 12), both on SuperLU with
tol = 1e-10.  The ARPACK solver is dhlb.linalg as of commit ``ARPACK_COMMIT``, taken from git
history into a temporary package, so the package itself carries no dead code.

Run:  python benchmarks/bench_solvers.py [--m 32] [--skip-direct-3d] [--json PATH] [--only-compare]
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

from dhlb.fem import bundle_matrices
from dhlb.geometry import EuclideanComplex
from dhlb.linalg import SolverOptions, default_shift, smallest_eigenpairs
from dhlb.linalg.backends import available_backends, clear_cache, get_backend

BUNNY = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "meshes", "stanford-bunny.obj")


def bunny_problem(path=BUNNY):
    from dhlb.io import compact_mesh, read_surface
    from dhlb.mesh import tangent_bundle

    V, F = read_surface(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        V, F, _ = compact_mesh(V, F)
    tb = tangent_bundle(V, F, n=4)
    A, M = bundle_matrices(tb.bundle, tb.geometry)
    return f"bunny ({len(F)} faces)", A, M, tb.geometry.stiffness_matrix(), tb.geometry.mass_matrix()


def box_problem(m):
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import FilamentField, velocity_bundle, vortex_ring

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
            return smallest_eigenpairs(A, M, k=1, solver=SolverOptions(tol=1e-9, backend=name))

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


ARPACK_COMMIT = "6991b1b"  # the last commit whose dhlb.linalg ran ARPACK


def arpack_solver():
    """``smallest_eigenpairs``, ``SolverOptions``, ``clear_cache`` of dhlb 0.3 (ARPACK), as a throw-away package."""
    import importlib
    import subprocess
    import tempfile

    root = os.path.join(os.path.dirname(__file__), "..")
    tmp = tempfile.mkdtemp()
    pkg = os.path.join(tmp, "_arpack_linalg")
    os.makedirs(pkg)
    names = subprocess.run(["git", "-C", root, "ls-tree", "--name-only", ARPACK_COMMIT, "dhlb/linalg/"], check=True,
                           capture_output=True, text=True).stdout.split()
    for path in names:
        src = subprocess.run(["git", "-C", root, "show", f"{ARPACK_COMMIT}:{path}"], check=True,
                             capture_output=True, text=True).stdout
        with open(os.path.join(pkg, os.path.basename(path)), "w") as fh:
            fh.write(src.replace("dhlb.linalg.", "_arpack_linalg.").replace("from dhlb.linalg import",
                                                                             "from _arpack_linalg import"))
    sys.path.insert(0, tmp)
    return (importlib.import_module("_arpack_linalg.eigen").smallest_eigenpairs,
            importlib.import_module("_arpack_linalg.options").SolverOptions,
            importlib.import_module("_arpack_linalg.backends").clear_cache)


def compare_lanczos(repeat):
    """Lanczos (dhlb) vs ARPACK (dhlb 0.3) on bunny k = 1, 6 and a 12-fold Landau level; prints and returns rows."""
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
    from tests.fem_fixtures import flat_torus_landau

    old, OldOptions, old_clear_cache = arpack_solver()
    _, A, M, *_ = bunny_problem()
    L, geo, _ = flat_torus_landau(2, 60, 12)
    Al, Ml = bundle_matrices(L, geo)
    cases = {"bunny k=1": (A, M, 1), "bunny k=6": (A, M, 6), "Landau d=12, k=12": (Al, Ml, 12)}
    rows = []
    print(f"\nLanczos (dhlb) vs ARPACK (git {ARPACK_COMMIT}), SuperLU, tol 1e-10, best of {repeat}")
    print(f"{'case':<20}{'n':>8}{'ARPACK s':>10}{'solves':>8}{'Lanczos s':>11}{'solves':>8}{'max |Δλ|/λ':>12}")
    for label, (AA, MM, k) in cases.items():
        def run_old(AA=AA, MM=MM, k=k):
            old_clear_cache()   # its own ordering cache: both start cold
            return old(AA, MM, k, solver=OldOptions(tol=1e-10, backend="superlu"))

        def run_new(AA=AA, MM=MM, k=k):
            clear_cache()
            return smallest_eigenpairs(AA, MM, k, solver=SolverOptions(tol=1e-10, backend="superlu"))

        t_old, r_old = best_of(run_old, repeat)
        t_new, r_new = best_of(run_new, repeat)
        d = float(np.max(np.abs(r_old.eigenvalues - r_new.eigenvalues) / np.abs(r_new.eigenvalues).clip(1e-300)))
        rows.append({"case": label, "n": AA.shape[0], "arpack": t_old, "arpack_solves": int(r_old.solves),
                     "lanczos": t_new, "lanczos_solves": int(r_new.solves), "rel_diff": d})
        print(f"{label:<20}{AA.shape[0]:>8}{t_old:>10.3f}{r_old.solves:>8}{t_new:>11.3f}{r_new.solves:>8}{d:>12.1e}",
              flush=True)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--m", type=int, default=32, help="cells per axis of the tet box (32: 196,608 tets)")
    ap.add_argument("--repeat", type=int, default=2, help="best of this many runs")
    ap.add_argument("--skip-direct-3d", action="store_true", help="only the iterative backend on the tet box")
    ap.add_argument("--json", default=os.path.join(os.path.dirname(__file__), "bench_solvers.json"))
    ap.add_argument("--only-compare", action="store_true", help="only the Lanczos vs ARPACK table")
    args = ap.parse_args(argv)
    if args.only_compare:
        compare_lanczos(args.repeat)
        return
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
    out["lanczos_vs_arpack"] = compare_lanczos(args.repeat)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
