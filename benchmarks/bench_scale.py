"""Scaling benchmark (issue 8): direction fields from 5k to > 1M faces, vortex filaments from 20k to 1M tets.

One command; every size runs in a fresh child process (peak memory = the child's
``ru_maxrss``, interpreter and libraries included, ~150 MB).

* ``L_ref``: one factorization + solve of the real cotangent Laplacian ``L + εM`` of the 69k-face
  Stanford bunny with the fastest installed direct backend (CHOLMOD if installed), best of 3,
  measured first in this run; every time below is also given as a multiple of it.
* Surfaces: spot, kitten, bunny from ``/work/shared/meshes`` and midpoint (1 → 4) subdivisions
  of kitten and bunny (:func:`midpoint_subdivide`, generated in the child, not timed).  For each
  backend (``--surface-backends``; default ``auto`` and the pip-only ``superlu``, the latter up to
  ``--superlu-max-faces``, default 350,000) the smoothest
  n = 4 direction field :func:`dhlb.fields.direction_field` end to end = reading the file +
  its ``setup`` (validation, tangent bundle, matrices) + ``solve`` (eigen solve) + ``indices``
  (directions and singularities).  ``lap`` is the Laplacian factorization + solve of that mesh.
  With ``--breakdown`` (default on) the setup is split by timing :func:`validate_surface`,
  :func:`tangent_bundle` (its bundle + geometry) and :func:`energy_matrices` once more.
* Tets: the Kuhn-triangulated box ``[-1, 1]³`` (:func:`dhlb.mesh.box_tet_mesh`, ``6 m³``
  tets) with the vortex-ring demo field of ``dhlb vortex`` (:func:`dhlb.cli.vortex.demo_velocity`,
  ħ = 1) through :func:`dhlb.vortex.vortex_filaments`, phases ``mesh``, ``omega`` (Biot–Savart
  line integrals and the bundle), ``assembly``, ``solve``, ``extraction``; backend
  ``--tet-backends`` (default ``amg-lobpcg``).
* Scaling exponent: least-squares slope of log(end-to-end time) against log(size) per
  (kind, backend), over the sizes >= ``--fit-from`` (default 50,000 elements).

Writes ``bench_scale.json`` and ``bench_scale.png`` next to this file (``--out`` prefix).
Run:  python benchmarks/bench_scale.py [--max-faces 1200000] [--max-tets 1100000] [--quick] [--issue15] [--issue30]
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy (inherited by the children)

import argparse
import json
import platform
import resource
import subprocess
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

MESHES = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "meshes")
HERE = os.path.dirname(os.path.abspath(__file__))
# (label, file, subdivision levels); faces: 5,856 / 18,894 / 69,451 / 75,576 / 277,804 / 302,304 / 1,111,216
SURFACES = [("spot", "spot.obj", 0), ("kitten", "kitten.obj", 0), ("bunny", "stanford-bunny.obj", 0),
            ("kitten x4", "kitten.obj", 1), ("bunny x4", "stanford-bunny.obj", 1),
            ("kitten x16", "kitten.obj", 2), ("bunny x16", "stanford-bunny.obj", 2)]
FACES = {"spot": 5856, "kitten": 18894, "bunny": 69451}
TET_M = [15, 20, 26, 32, 40, 50, 55]          # 6 m³ tets: 20,250 ... 998,250


def midpoint_subdivide(V, F, levels=1):
    """Split every triangle ``(a, b, c)`` into four at its edge midpoints, keeping the orientation.

    Examples
    --------
    >>> V, F = midpoint_subdivide(np.eye(3), np.array([[0, 1, 2]]))
    >>> V.shape, F.tolist()
    ((6, 3), [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]])
    """
    V, F = np.asarray(V, float), np.asarray(F, np.int64)
    for _ in range(levels):
        m = len(F)
        E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
        key = E[:, 0] * len(V) + E[:, 1]
        uniq, inv = np.unique(key, return_inverse=True)
        mid = len(V) + inv.reshape(3, m)          # midpoints of ab, bc, ca
        V = np.vstack([V, 0.5 * (V[uniq // len(V)] + V[uniq % len(V)])])
        a, b, c = F.T
        ab, bc, ca = mid
        F = np.concatenate([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1), np.stack([ca, bc, c], 1),
                            np.stack([ab, bc, ca], 1)])
    return V, F


def _rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _load(file, levels):
    from dhlb.io import compact_mesh, read_surface

    V, F = read_surface(os.path.join(MESHES, file))
    with warnings.catch_warnings():          # the bunny has unreferenced vertices
        warnings.simplefilter("ignore")
        V, F, _ = compact_mesh(V, F)
    return V, F


def laplace_time(V, F, backend, repeat=1):
    """Seconds for one (first, cold-cache) factorization + solve of ``L + εM`` (real cotangent Laplacian)."""
    from dhlb.geometry import EuclideanComplex
    from dhlb.linalg import default_shift
    from dhlb.linalg.backends import clear_cache, get_backend
    from dhlb.mesh import validate_surface

    geo = EuclideanComplex(validate_surface(V, F).complex, points=V)
    L, M = geo.stiffness_matrix().tocsr(), geo.mass_matrix(lumped=True).tocsr()
    K = (L + default_shift(L, M) * M).tocsc()
    be = get_backend(backend)
    be.factorize(sp_eye(3), positive_definite=True)  # import the backend's library outside the timing
    best = np.inf
    for _ in range(repeat):
        clear_cache()
        t = time.perf_counter()
        x = be.factorize(K, positive_definite=True).solve(M @ np.ones(K.shape[0]))
        best = min(best, time.perf_counter() - t)
    assert np.all(np.isfinite(x))
    return best


def sp_eye(n):
    import scipy.sparse as sp

    return sp.identity(n, format="csc")


def child_lref():
    from dhlb.linalg.backends import available_backends

    name = "cholmod" if "cholmod" in available_backends() else "superlu"
    V, F = _load("stanford-bunny.obj", 0)
    return {"L_ref": laplace_time(V, F, name, repeat=3), "L_ref_backend": name, "faces": len(F)}


def child_surface(label, backend, breakdown):
    from dhlb.fields import direction_field, energy_matrices
    from dhlb.mesh import tangent_bundle, validate_surface

    _, file, levels = next(s for s in SURFACES if s[0] == label)
    t0 = time.perf_counter()
    V, F = _load(file, 0)
    t_read = time.perf_counter() - t0
    t1 = time.perf_counter()
    V, F = midpoint_subdivide(V, F, levels)
    t_sub = time.perf_counter() - t1
    be = None if backend == "auto" else backend
    res = direction_field(V, F, n=4, solver=be)
    T = res.timings
    out = {"kind": "surface", "label": label, "size": len(F), "vertices": len(V), "backend": res.solver["backend"],
           "requested": backend, "iterations": res.solver["iterations"], "read": t_read, "subdivide": t_sub,
           "setup": T["setup"], "solve": T["solve"], "indices": T["indices"], "e2e": t_read + T["total"],
           "peak_mb": _rss_mb(), "index_sum": int(res.index_sum), "eigenvalue": res.eigenvalue}
    if breakdown:
        t = time.perf_counter()
        validate_surface(V, F)
        out["validate"] = time.perf_counter() - t
        t = time.perf_counter()
        tb = tangent_bundle(V, F, n=4)
        _ = (tb.bundle, tb.geometry)
        out["tangent"] = time.perf_counter() - t - out["validate"]
        t = time.perf_counter()
        energy_matrices(tb, s=0.0)
        out["matrices"] = time.perf_counter() - t
    out["lap"] = laplace_time(V, F, res.solver["backend"] if res.solver["backend"] != "amg-lobpcg" else "superlu")
    return out


def child_tets(m, backend):
    from dhlb.cli.vortex import demo_velocity
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import vortex_filaments

    t0 = time.perf_counter()
    mesh = box_tet_mesh(m, lower=-1.0, upper=1.0)
    t_gen = time.perf_counter() - t0
    field, _ = demo_velocity("ring", mesh.points)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = vortex_filaments(mesh.points, mesh.tets, field, 1.0, solver=None if backend == "auto" else backend)
    s, T = res.statistics, res.timings
    return {"kind": "tets", "label": f"box m={m}", "size": int(s["n_tets"]), "vertices": int(s["n_vertices"]),
            "backend": s["solver"]["backend"], "requested": backend, "iterations": s["solver"]["iterations"],
            "generate": t_gen, **{k: float(v) for k, v in T.items() if k != "total"}, "e2e": float(T["total"]),
            "peak_mb": _rss_mb(), "filaments": int(s["n_filaments"])}


def icosphere(level):
    """The icosahedron midpoint-subdivided ``level`` times and projected to the unit sphere, in subdivision order."""
    t = (1 + 5**0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                  [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
                  [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    for _ in range(level):
        V, F = midpoint_subdivide(V, F, 1)
        V = V / np.linalg.norm(V, axis=1)[:, None]
    return V, F


def child_icosphere(level, order, backend):
    """Issue 15: the n = 4 field on an icosphere (subdivision or shuffled vertex order), its L_ref, peak memory."""
    import scipy.sparse.linalg as spla

    from dhlb.fields import direction_field

    V, F = icosphere(level)
    if order == "shuffled":
        p = np.random.default_rng(1).permutation(len(V))
        inv = np.empty_like(p)
        inv[p] = np.arange(len(V))
        V, F = V[p], inv[F]
    t = time.perf_counter()
    res = direction_field(V, F, n=4, solver=None if backend == "auto" else backend)
    total = time.perf_counter() - t
    rss = _rss_mb()
    from dhlb.fem import bundle_matrices  # noqa: F401  (L_ref below: plain cotangent Laplacian, splu defaults)
    from dhlb.geometry import EuclideanComplex
    from dhlb.mesh import validate_surface

    geo = EuclideanComplex(validate_surface(V, F).complex, points=V)
    L, M = geo.stiffness_matrix().tocsc(), geo.mass_matrix(lumped=True).tocsc()
    t = time.perf_counter()
    spla.splu((L + 1e-8 * M).tocsc()).solve(np.ones(len(V)))
    lref = time.perf_counter() - t
    return {"kind": "icosphere", "label": f"ico{level} {order}", "size": len(F), "backend": res.solver["backend"],
            "e2e": total, "setup": res.timings["setup"], "solve": res.timings["solve"],
            "indices": res.timings["indices"], "peak_mb": rss, "L_ref": lref, "solves": res.solver.get("solves"),
            "factorizations": res.solver.get("factorizations"), "note": res.solver.get("note", ""),
            "index_sum": int(res.index_sum)}


def issue30(timeout):
    """Issue 30's row: the n = 4 field on the 1.31M-face icosphere (level 8, subdivision order), default backend."""
    r = run_child(["icosphere", "8", "subdivision", "auto"], timeout)
    avg = os.getloadavg()
    print(f"issue 30 (load average {avg[0]:.2f} {avg[1]:.2f} {avg[2]:.2f}; each run in a fresh process):", flush=True)
    print(f"{'case':<44}{'now':>34}{'target':>18}{'met':>5}")
    if "error" in r:
        print(f"{'icosphere level 8 n = 4 field':<44}  FAILED: {r['error']}")
        return r
    ok = r["e2e"] < 25.0 and r["peak_mb"] < 4 * 1024
    now = f"{r['e2e']:.1f} s, peak {r['peak_mb'] / 1024:.2f} GB"
    case = f"icosphere level 8 ({r['size'] / 1e6:.2f}M faces) n = 4 field"
    print(f"{case:<44}"
          f"{now:>34}{'< 25 s, < 4 GB':>18}{'yes' if ok else 'NO':>5}")
    print(f"  setup {r['setup']:.2f} s, solve {r['solve']:.2f} s ({r['factorizations']} factorization, {r['solves']} "
          f"solves, backend {r['backend']}), indices {r['indices']:.2f} s; L_ref {r['L_ref']:.2f} s", flush=True)
    return r


def issue15(timeout, memory_limit="2.5G"):
    """The table of issue 15 for icosphere levels 6 and 8 (default install: SuperLU) and a memory-limited run."""
    print("issue 15 (default install, SuperLU): n = 4 field on icospheres", flush=True)
    rows = {}
    for args in (["6", "subdivision", "superlu"], ["6", "shuffled", "superlu"], ["8", "subdivision", "superlu"]):
        r = run_child(["icosphere", *args], timeout)
        rows[" ".join(args[:2])] = r
        if "error" in r:
            print(f"  ico{args[0]} {args[1]}: FAILED: {r['error']}", flush=True)
            continue
        print(f"  ico{args[0]} {args[1]:<12} {r['size']:>9} faces: {r['e2e']:7.2f} s (setup {r['setup']:.2f}, solve "
              f"{r['solve']:.2f}, indices {r['indices']:.2f}; {r['solves']} solves), "
              f"peak {r['peak_mb'] / 1024:.2f} GB, "
              f"L_ref {r['L_ref']:.2f} s, ratio {r['e2e'] / r['L_ref']:.1f}", flush=True)
    a, b = rows.get("6 subdivision", {}), rows.get("6 shuffled", {})
    if "e2e" in a and "e2e" in b:
        print(f"  subdivision order ÷ shuffled (level 6): {a['e2e'] / b['e2e']:.2f} (target ≤ 1.5)", flush=True)
    env = dict(os.environ, DHLB_MEMORY_LIMIT=memory_limit)
    cmd = [sys.executable, os.path.abspath(__file__), "--child", "icosphere", "8", "subdivision", "auto"]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, check=False)
    last = (out.stderr.strip().splitlines() or out.stdout.strip().splitlines() or ["?"])[-1]
    if out.returncode == 0:
        r = json.loads(out.stdout.strip().splitlines()[-1])
        last = f"ran with backend {r['backend']}: {r['note']}"
    print(f"  ico8 under DHLB_MEMORY_LIMIT={memory_limit}: exit {out.returncode}: {last[:300]}", flush=True)
    rows["memory-limited"] = {"exit": out.returncode, "message": last}
    return rows


def run_child(args, timeout):
    cmd = [sys.executable, os.path.abspath(__file__), "--child", *map(str, args)]
    t = time.perf_counter()
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return {"error": f"timeout after {timeout} s"}
    if out.returncode != 0:
        return {"error": (out.stderr.strip().splitlines() or ["?"])[-1]}
    r = json.loads(out.stdout.strip().splitlines()[-1])
    r["wall"] = time.perf_counter() - t
    return r


def fit_exponent(rows, fit_from):
    pts = [(r["size"], r["e2e"]) for r in rows if "e2e" in r and r["size"] >= fit_from]
    if len(pts) < 2:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def plot(results, lref, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, kind, xlabel in ((axes[0], "surface", "faces"), (axes[1], "tets", "tetrahedra")):
        groups = {}
        for r in results:
            if r.get("kind") == kind and "e2e" in r:
                groups.setdefault(r["backend"], []).append(r)
        for name, rows in sorted(groups.items()):
            rows.sort(key=lambda r: r["size"])
            ax.loglog([r["size"] for r in rows], [r["e2e"] for r in rows], "o-", label=f"{name} (end to end)")
            if kind == "surface":
                ax.loglog([r["size"] for r in rows], [r["solve"] for r in rows], "x:", label=f"{name} (eigen solve)")
        ax.axhline(lref, color="gray", lw=0.8, ls="--", label="L_ref (bunny Laplacian)")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("seconds")
        ax.set_title("smoothest n = 4 direction field" if kind == "surface" else "vortex filaments (ring)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-faces", type=int, default=1_200_000)
    ap.add_argument("--max-tets", type=int, default=1_100_000)
    ap.add_argument("--surface-backends", nargs="+", default=["auto", "superlu"])
    ap.add_argument("--tet-backends", nargs="+", default=["amg-lobpcg"])
    ap.add_argument("--superlu-max-faces", type=int, default=350_000,
                    help="largest surface for the superlu backend (its factorizations grow fastest)")
    ap.add_argument("--no-breakdown", action="store_true", help="do not split the surface setup phase")
    ap.add_argument("--fit-from", type=int, default=50_000, help="smallest size in the exponent fit")
    ap.add_argument("--quick", action="store_true", help="up to 100k faces and 200k tets")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per child")
    ap.add_argument("--out", default=os.path.join(HERE, "bench_scale"), help="prefix of the .json/.png outputs")
    ap.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    ap.add_argument("--issue15", action="store_true", help="only the icosphere table of issue 15")
    ap.add_argument("--issue30", action="store_true", help="only the 1.31M-face row of issue 30")
    args = ap.parse_args(argv)
    if args.issue15:
        issue15(args.timeout)
        return 0
    if args.issue30:
        issue30(args.timeout)
        return 0
    if args.child:
        kind, *rest = args.child
        r = (child_lref() if kind == "lref" else child_surface(rest[0], rest[1], rest[2] == "1") if kind == "surface"
             else child_icosphere(int(rest[0]), rest[1], rest[2]) if kind == "icosphere"
             else child_tets(int(rest[0]), rest[1]))
        print(json.dumps(r))
        return 0
    if args.quick:
        args.max_faces, args.max_tets = min(args.max_faces, 100_000), min(args.max_tets, 200_000)
    from dhlb.linalg.backends import available_backends

    t_start = time.perf_counter()
    lref = run_child(["lref"], args.timeout)
    if "error" in lref:
        raise SystemExit(f"L_ref failed: {lref['error']}")
    L = lref["L_ref"]
    print(f"backends: {available_backends()}; OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}; "
          f"{os.cpu_count()} cpus; L_ref = {L:.3f} s ({lref['L_ref_backend']}, bunny Laplacian)", flush=True)
    results = []
    head = (f"{'case':<12}{'size':>9}{'backend':>12}{'its':>5}{'read/gen':>9}{'setup':>8}{'solve':>8}"
            f"{'rest':>8}{'e2e':>8}{'×L_ref':>8}{'peak MB':>9}  notes")
    print(head + "\n" + "-" * len(head), flush=True)
    cases = [("surface", label, be) for label, file, lev in SURFACES for be in args.surface_backends
             if FACES["bunny" if "bunny" in label else label.split()[0]] * 4**lev
             <= (min(args.max_faces, args.superlu_max_faces) if be == "superlu" else args.max_faces)]
    cases += [("tets", m, be) for m in TET_M for be in args.tet_backends if 6 * m**3 <= args.max_tets]
    for kind, what, be in cases:
        extra = [("0" if args.no_breakdown else "1")] if kind == "surface" else []
        r = run_child([kind, what, be, *extra], args.timeout)
        r.setdefault("kind", kind)
        r.setdefault("requested", be)
        r.setdefault("label", what if kind == "surface" else f"box m={what}")
        results.append(r)
        if "error" in r:
            print(f"{r['label']:<12} {be}: FAILED: {r['error']}", flush=True)
            continue
        r["ratio"] = r["e2e"] / L
        if kind == "surface":
            pre, setup, solve, rest = r["read"], r["setup"], r["solve"], r["indices"]
            notes = (f"lap {r['lap']:.2f}s" + (f"; validate {r['validate']:.2f} tangent {r['tangent']:.2f} "
                                               f"matrices {r['matrices']:.2f}" if "validate" in r else ""))
        else:
            pre, setup, solve, rest = r["generate"], r["mesh"] + r["omega"] + r["assembly"], r["solve"], r["extraction"]
            notes = (f"mesh {r['mesh']:.2f} omega {r['omega']:.2f} assembly {r['assembly']:.2f}; "
                     f"{r['filaments']} filament(s)")
        print(f"{r['label']:<12}{r['size']:>9}{r['backend']:>12}{r['iterations']:>5}{pre:>9.2f}{setup:>8.2f}"
              f"{solve:>8.2f}{rest:>8.2f}{r['e2e']:>8.2f}{r['ratio']:>8.1f}{r['peak_mb']:>9.0f}  {notes}", flush=True)
    exps = {}
    for kind in ("surface", "tets"):
        for be in sorted({r["backend"] for r in results if r["kind"] == kind and "backend" in r}):
            e = fit_exponent([r for r in results if r["kind"] == kind and r.get("backend") == be], args.fit_from)
            if e is not None:
                exps[f"{kind}/{be}"] = e
    print(f"scaling exponents (end-to-end time ∝ size^p, sizes >= {args.fit_from}): "
          + ", ".join(f"{k} p = {v:.2f}" for k, v in exps.items()))
    out = {"machine": platform.machine(), "cpus": os.cpu_count(), "python": platform.python_version(),
           "backends": available_backends(), "L_ref": lref, "results": results, "exponents": exps,
           "wall_seconds": time.perf_counter() - t_start}
    with open(args.out + ".json", "w") as fh:
        json.dump(out, fh, indent=1)
    plot(results, L, args.out + ".png")
    print(f"wrote {args.out}.json and {args.out}.png ({out['wall_seconds']:.0f} s in all)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
