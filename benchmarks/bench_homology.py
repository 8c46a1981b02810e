"""Homology at scale (issue 40): dhlb's integer homology against gudhi's Z/2 persistence, in one run.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_homology.py [--quick] [--json out.json]``.
gudhi is optional (``pip install gudhi``); without it only dhlb's column is filled.

Every case runs in a fresh process per tool (so peak memory is the case's own), end to end from
the same input: the graph or the top simplices.  dhlb builds the complex
(:meth:`SimplicialComplex.from_graph` or the constructor) and computes the integer groups
(``homology``: ranks and torsion, no bases); gudhi builds a ``SimplexTree`` (``expansion`` for flag
complexes) and runs ``compute_persistence(homology_coeff_field=2)``.  Columns: simplices, seconds,
peak resident memory, the time ratio, whether dhlb's integer groups give gudhi's Z/2 Betti numbers
through the universal coefficient theorem (``=``), the groups.  The cases:

* random flag complexes ``gnp_random_graph(n, p, seed=3)`` of 200–2,000 vertices, up to
  dimension 2 or 3 (the largest has 1.01M simplices), and one of 32 vertices cut at dimension 4;
* a Rips complex: 1,500 random points in the unit cube, the ε-neighbourhood graph, dimension 3;
* triangulated manifolds: the Freudenthal 3-torus 40³ (384k tetrahedra, 1.66M simplices), the
  1M-tetrahedron cube 55³ of ``bench_complex.py`` (4.4M simplices) and the 2-torus with a
  cross-cap (torsion: H_1 = Z² ⊕ Z/2, 100k triangles);
* bases: the generator cycles of H_1 for b_1 = 1,041 (dhlb only: gudhi has no integer bases).

A case gudhi cannot finish within the time or memory limit (``--limit-s``, ``--limit-gb``) is
reported as such; so is one of dhlb's.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def freudenthal_torus(N: int, d: int) -> np.ndarray:
    """Top simplices of the Freudenthal triangulation of the d-torus on an N^d grid (N >= 3)."""
    grid = np.stack(np.meshgrid(*[np.arange(N)] * d, indexing="ij"), -1).reshape(-1, d)
    weights = N ** np.arange(d)[::-1]
    out = []
    for perm in itertools.permutations(range(d)):
        pts = [grid]
        cur = grid.copy()
        for axis in perm:
            cur = cur.copy()
            cur[:, axis] += 1
            pts.append(cur)
        out.append(np.stack([(p % N) @ weights for p in pts], axis=1))
    return np.concatenate(out)


def torus_with_crosscap(N: int) -> np.ndarray:
    """The non-orientable surface T² # RP², with H_1 = Z² ⊕ Z/2.

    The N×N grid torus with one square replaced by an annulus glued to a 6-vertex RP² minus a
    triangle.
    """
    T = freudenthal_torus(N, 2)
    a, b, c, d = 0, 1, N + 1, N  # the square of grid cell (0, 0)
    quad = {tuple(sorted(t)) for t in ([a, b, c], [a, c, d], [a, b, d])}
    T = T[np.array([tuple(sorted(t)) not in quad for t in T.tolist()])]
    M = N * N
    rp2 = np.array([(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 1, 5),
                    (1, 2, 4), (2, 3, 5), (1, 3, 4), (1, 3, 5), (2, 4, 5)])[1:] + M  # hole M, M+1, M+2
    x, y, z = M, M + 1, M + 2
    annulus = np.array([(a, b, x), (b, x, y), (b, c, y), (c, y, z), (c, d, z), (d, z, x), (d, a, x)])
    return np.concatenate([T, rp2, annulus])


def rips_graph(n: int, eps: float, seed: int = 0):
    """The ε-neighbourhood graph of ``n`` uniform points in the unit cube: ``(n, edges)``."""
    from scipy.spatial import cKDTree

    P = np.random.default_rng(seed).random((n, 3))
    return n, cKDTree(P).query_pairs(eps, output_type="ndarray"), P


CASES = {  # name: (kind, parameters, max_dim)
    "flag 200/0.03": ("gnp", (200, 0.03), 2),
    "flag 300/0.02": ("gnp", (300, 0.02), 2),
    "flag 32/0.65 to dim 4": ("gnp", (32, 0.65), 4),
    "flag 1000/0.10": ("gnp", (1000, 0.10), 3),
    "flag 1000/0.13": ("gnp", (1000, 0.13), 3),
    "flag 2000/0.07": ("gnp", (2000, 0.07), 3),
    "flag 2000/0.08 (1M)": ("gnp", (2000, 0.08), 3),
    "rips 1500 pts": ("rips", (1500, 0.12), 3),
    "3-torus 40^3": ("tops", ("torus3", 40), 3),
    "cube 55^3 (1M tets)": ("tops", ("cube", 55), 3),
    "T^2 # RP^2 224^2": ("tops", ("crosscap", 224), 2),
    "bases b1=1041": ("bases", (500, 0.012), 2),
}
QUICK = ["flag 200/0.03", "flag 300/0.02", "flag 32/0.65 to dim 4", "flag 1000/0.10", "rips 1500 pts",
         "bases b1=1041"]


def _input(kind, params):
    import networkx as nx

    if kind in ("gnp", "bases"):
        G = nx.gnp_random_graph(*params, seed=3)
        return G.number_of_nodes(), np.array(list(G.edges()), dtype=np.int64).reshape(-1, 2)
    if kind == "rips":
        n, edges, _ = rips_graph(*params)
        return n, edges
    name, N = params
    if name == "cube":
        from dhlb.examples import cube_nd

        X = cube_nd(3, N)
        return np.asarray(X.vertex_labels[X.simplices(3)])
    return freudenthal_torus(N, 3) if name == "torus3" else torus_with_crosscap(N)


def run_dhlb(kind, params, max_dim) -> dict:
    import dhlb
    from dhlb.topology.homology import homology

    data = _input(kind, params)
    t0 = time.perf_counter()
    if kind == "tops":
        X = dhlb.SimplicialComplex(data)
    else:
        n, edges = data

        class G:  # what from_graph reads: .nodes and .edges()
            nodes = range(n)

            @staticmethod
            def edges():
                return edges.tolist()

        X = dhlb.SimplicialComplex.from_graph(G, max_dim=max_dim)
    t1 = time.perf_counter()
    H = homology(X)
    groups = [str(h) for h in H]
    t2 = time.perf_counter()
    even = [sum(1 for t in h.torsion if t % 2 == 0) for h in H]  # universal coefficients over Z/2
    mod2 = [h.rank + even[k] + (even[k - 1] if k else 0) for k, h in enumerate(H)]
    out = dict(simplices=int(sum(X.counts)), build_s=t1 - t0, homology_s=t2 - t1, total_s=t2 - t0,
               groups=[g if len(g) < 40 else g[:37] + "…" for g in groups], mod2=mod2)
    if kind == "bases":
        t3 = time.perf_counter()
        g = H[1].generators
        out["bases_s"] = time.perf_counter() - t3
        out["b1"] = int(g.shape[1])
    return out


def run_gudhi(kind, params, max_dim) -> dict:
    import gudhi

    data = _input(kind, params)
    t0 = time.perf_counter()
    st = gudhi.SimplexTree()
    if kind == "tops":
        for s in data.tolist():
            st.insert(s)
    else:
        n, edges = data
        st.insert_batch(np.arange(n)[None, :], np.zeros(n))
        if len(edges):
            st.insert_batch(edges.T, np.zeros(len(edges)))
        st.expansion(max_dim)
    t1 = time.perf_counter()
    st.compute_persistence(homology_coeff_field=2, persistence_dim_max=True)
    b = st.betti_numbers()
    t2 = time.perf_counter()
    return dict(simplices=int(st.num_simplices()), build_s=t1 - t0, homology_s=t2 - t1, total_s=t2 - t0,
                groups=[f"(Z/2)^{x}" for x in b], mod2=list(b))


def _child(tool: str, name: str) -> None:
    kind, params, max_dim = CASES[name]
    out = (run_dhlb if tool == "dhlb" else run_gudhi)(kind, params, max_dim)
    out["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(out))


def measure(tool: str, name: str, limit_s: float, limit_gb: float) -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")

    def cap():
        lim = int(limit_gb * 2**30)
        resource.setrlimit(resource.RLIMIT_AS, (lim, lim))

    try:
        r = subprocess.run([sys.executable, __file__, "--child", tool, name], capture_output=True, text=True,
                           timeout=limit_s, env=env, preexec_fn=cap)
    except subprocess.TimeoutExpired:
        return dict(failed=f"not done in {limit_s:.0f} s")
    if r.returncode:
        tail = (r.stderr.strip().splitlines() or ["?"])[-1]
        return dict(failed=f"exit {r.returncode}: {tail[:80]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the small cases only")
    ap.add_argument("--limit-s", type=float, default=300.0, help="time limit per case and tool (default 300)")
    ap.add_argument("--limit-gb", type=float, default=8.0, help="address-space limit per case and tool (default 8)")
    ap.add_argument("--json", help="also write the table here")
    ap.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        _child(*a.child)
        return
    try:
        import gudhi  # noqa: F401

        tools = ["dhlb", "gudhi"]
    except ImportError:
        tools = ["dhlb"]
        print("gudhi is not installed (pip install gudhi): dhlb only")
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    rows = {}
    names = QUICK if a.quick else list(CASES)
    print(f"{'case':22s} {'simplices':>10s} | {'dhlb s':>7s} {'MB':>6s} | {'gudhi s':>7s} {'MB':>6s} | ratio | Z/2 | "
          "groups (dhlb, over Z)")
    for name in names:
        peers = [t for t in tools if not (t == "gudhi" and name.startswith("bases"))]  # gudhi has no integer bases
        res = {t: measure(t, name, a.limit_s, a.limit_gb) for t in peers}
        rows[name] = res
        d, g = res["dhlb"], res.get("gudhi", {})

        def cell(r):
            if not r:
                return f"{'—':>7s} {'':>6s}"
            if "failed" in r:
                return f"{'fail':>7s} {'':>6s}"
            return f"{r['total_s']:7.3f} {r['peak_mb']:6.0f}"

        ratio = f"{d['total_s'] / g['total_s']:5.1f}" if "total_s" in d and "total_s" in g else "  —  "
        if "mod2" in d and "mod2" in g:  # gudhi lists Betti numbers up to its last nonzero one
            n = max(len(d["mod2"]), len(g["mod2"]))
            same = d["mod2"] + [0] * (n - len(d["mod2"])) == g["mod2"] + [0] * (n - len(g["mod2"]))
            agree = " = " if same else " ≠ "
        else:
            agree = " — "
        simp = d.get("simplices", g.get("simplices", 0))
        extra = f" bases {d['bases_s']:.3f} s" if "bases_s" in d else ""
        why = "; ".join(f"{t}: {r['failed']}" for t, r in res.items() if "failed" in r)
        groups = d.get("groups", "")
        print(f"{name:22s} {simp:10,d} | {cell(d)} | {cell(g)} | {ratio} | {agree} | {groups}{extra} {why}", flush=True)
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
