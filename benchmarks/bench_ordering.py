"""Fill-reducing orderings for SuperLU on the matrices of dhlb's direction fields (issue 41, "ordering").

For every mesh of /work/shared/meshes that dhlb reads as a surface (rounded_cube, spot, kitten,
Stanford bunny, watertight bunny, fertility), for the kitten midpoint-subdivided twice
(``kitten-x16``, 302k faces, vertices in subdivision order: a badly numbered mesh) and for each of
these with a random vertex permutation (``+shuf``, badly numbered too), the benchmark builds the
matrix the field factorizes — ``K = A + εM`` of the smoothest cross field (n = 4, s = 0,
:func:`dhlb.fields.energy_matrices`, ``ε`` = :func:`dhlb.linalg.default_shift`), as
:func:`dhlb.linalg.smallest_eigenpairs` does — and measures, for each candidate ordering,

``order``
    Seconds to compute the ordering from ``K`` (graph extraction included).  For SuperLU's own
    orderings (``COLAMD``, ``MMD_AT_PLUS_A``, ``MMD_ATA``) the ordering runs inside ``splu`` and
    is included in ``factor`` (shown as ``-``).
``factor``
    Seconds of ``scipy.sparse.linalg.splu`` as :class:`dhlb.linalg.backends.SuperLUBackend` calls
    it: ``K[q][:, q]`` in canonical CSC, ``permc_spec="NATURAL"``, ``SymmetricMode``,
    ``diag_pivot_thresh=0`` (the positive-definite factorization of the eigensolver).
``fill``
    ``nnz(L) + nnz(U)`` divided by that of dhlb's current ordering (row ``dhlb``) on the same
    matrix: :func:`dhlb.linalg.ordering.nested_dissection`, METIS with
    :data:`~dhlb.linalg.ordering.METIS_OPTIONS`; below :data:`~dhlb.linalg.ordering.ND_MIN`
    unknowns dhlb leaves the ordering to SuperLU's ``MMD_AT_PLUS_A`` and so does that row.
``solve``
    Seconds of one solve with a complex right-hand side (permutations included); the relative
    residual is checked.
``total``
    ``order + factor + 20 solve``: the cost of one factorization that serves 20 solves.

Times are the best of ``--repeat`` runs (ordering and factorization repeated together; a
candidate that needs more than 10 s is run once).  Each candidate runs in a forked child process
with a time limit (``--timeout``, default 60 s: minimum degree can take minutes on badly numbered
meshes) and a memory limit (``--mem-gb``, default 6 GB above the parent's address space); such a
run is reported as ``timeout`` / ``out of memory``.

Candidates:

``dhlb``
    :func:`dhlb.linalg.ordering.nested_dissection` as it is (METIS ``niter=1, ufactor=300``).
``metis-default``
    ``pymetis.nested_dissection`` with METIS's default options.
``metis-rm``, ``metis-rm-u500``
    METIS with speed options: random matching coarsening (``ctype=0``) instead of sorted heavy edge,
    one refinement pass, no compression test; separators up to 30 % / 50 % unbalanced.
``metis-coarse2``, ``metis-coarse4``
    METIS (dhlb's options) on a coarsened graph: one or two rounds of a vectorized matching
    (locally dominant edges of a symmetric hash, 6 handshake passes), the quotient graph ordered
    with vertex weights = number of fine vertices, each coarse vertex expanded in place.
``amd``
    SuiteSparse AMD through ``cvxopt.amd.order`` (a pip wheel with SuiteSparse inside, no system
    library; ``n/a`` when cvxopt is not importable), on the lower triangle of ``K``'s pattern.
``rcm``
    ``scipy.sparse.csgraph.reverse_cuthill_mckee`` (profile-reducing; a cheap baseline).
``COLAMD``, ``MMD_AT_PLUS_A``, ``MMD_ATA``
    SuperLU's own column orderings (``permc_spec``), same options otherwise.

The summary at the end gives, over the matrices with at least ``ND_MIN`` unknowns (those dhlb
orders with METIS), each candidate's worst fill ratio, worst and geometric-mean ``total`` ratio
against ``dhlb``, the sum of its ``total`` seconds (``-`` if it failed anywhere) and its number of failures
(timeout, out of memory).  The machine may be shared: the load average is printed before and after.

Run::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_ordering.py [--quick] [--json out.json]

``--quick`` skips ``kitten-x16``; ``--mesh NAME`` (repeatable) and ``--only CANDIDATE``
(repeatable) restrict the run.
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import json
import multiprocessing
import resource
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import reverse_cuthill_mckee

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bench_field import load

from dhlb.fields import energy_matrices
from dhlb.linalg import default_shift
from dhlb.linalg.backends import canonical_csc
from dhlb.linalg.ordering import METIS_OPTIONS, ND_MIN, nested_dissection

MESHES = ["rounded_cube.obj", "spot.obj", "kitten.obj", "stanford-bunny.obj", "bunny-watertight.off",
          "fertility.off", "kitten-x16"]
SOLVES = 20


# ---------------------------------------------------------------------- graphs and orderings
def pattern_graph(K) -> sp.csr_matrix:
    """The graph of ``K + Kᵀ`` without the diagonal (int8 CSR, sorted indices)."""
    P = sp.csr_matrix((np.ones(K.nnz, np.int8), K.indices, K.indptr), shape=K.shape)
    G = (P + P.T).tocsr()
    G.setdiag(0)
    G.eliminate_zeros()
    G.sort_indices()
    return G


def metis_order(G, options, vweights=None) -> np.ndarray:
    """``METIS_NodeND`` of the graph ``G`` (pymetis) with the given options dict."""
    import pymetis

    adjacency = pymetis.CSRAdjacency(G.indptr.astype(np.int32), G.indices.astype(np.int32))
    perm, _ = pymetis.nested_dissection(adjacency, vweights=vweights, options=pymetis.Options(**options))
    return np.asarray(perm, dtype=np.int64)


def matching(G, passes=6):
    """Coarse labels of a matching of ``G``: locally dominant edges of a symmetric hash, ``passes`` handshakes.

    Every free vertex proposes to its free neighbour of largest key; mutual proposals are matched.
    O(nnz) per pass, no sort.  Returns ``(labels, n_coarse)``.
    """
    n = G.shape[0]
    row = np.repeat(np.arange(n), np.diff(G.indptr))
    col = G.indices.astype(np.int64)
    lo, hi = np.minimum(row, col).astype(np.uint64), np.maximum(row, col).astype(np.uint64)
    key = ((lo * np.uint64(0x9E3779B97F4A7C15)) ^ (hi * np.uint64(0xC2B2AE3D27D4EB4F))) >> np.uint64(2)
    key = key.astype(np.int64) + 1  # > 0
    mate = np.full(n, -1, np.int64)
    nonempty = np.diff(G.indptr) > 0
    for _ in range(passes):
        free = mate < 0
        k = np.where(free[row] & free[col], key, 0)
        if not k.any():
            break
        best = np.zeros(n, np.int64)
        best[nonempty] = np.maximum.reduceat(k, G.indptr[:-1][nonempty])
        hit = (k > 0) & (k == best[row])
        prop = np.full(n, -1, np.int64)
        prop[row[hit]] = col[hit]
        i = np.flatnonzero(prop >= 0)
        j = prop[i]
        ok = prop[j] == i
        mate[i[ok]] = j[ok]
    rep = np.where(mate < 0, np.arange(n), np.minimum(np.arange(n), mate))
    roots = np.flatnonzero(rep == np.arange(n))
    label = np.empty(n, np.int64)
    label[roots] = np.arange(len(roots))
    return label[rep], len(roots)


def coarse_metis_order(K, levels) -> np.ndarray:
    """METIS (dhlb's options) on the graph coarsened ``levels`` times by :func:`matching`, expanded in place."""
    G = pattern_graph(K)
    n = G.shape[0]
    lab = np.arange(n)
    for _ in range(levels):
        l, nc = matching(G)
        C = G.tocoo()
        r, c = l[C.row], l[C.col]
        off = r != c
        G = sp.csr_matrix((np.ones(int(off.sum()), np.int8), (r[off], c[off])), shape=(nc, nc))
        G.data[:] = 1  # duplicates were summed
        G.sort_indices()
        lab = l[lab]
    nc = G.shape[0]
    weights = np.bincount(lab, minlength=nc).astype(np.int64)  # pymetis reads idx_t = int64 buffers
    p = metis_order(G, METIS_OPTIONS, vweights=weights)
    rank = np.empty(nc, np.int64)
    rank[p] = np.arange(nc)
    return np.argsort(rank[lab], kind="stable")


def amd_order(K) -> np.ndarray:
    """SuiteSparse AMD (``cvxopt.amd.order``) of the pattern of ``K`` (lower triangle)."""
    import cvxopt
    from cvxopt import amd

    L = sp.tril(pattern_graph(K) + sp.identity(K.shape[0], np.int8, format="csr"), format="coo")
    A = cvxopt.spmatrix(1.0, cvxopt.matrix(L.row.astype(np.int64)), cvxopt.matrix(L.col.astype(np.int64)),
                        K.shape)
    return np.asarray(amd.order(A, "L"), dtype=np.int64).ravel()


def rcm_order(K) -> np.ndarray:
    return np.asarray(reverse_cuthill_mckee(pattern_graph(K), symmetric_mode=True), dtype=np.int64)


_FAST = {"niter": 1, "ufactor": 300, "ctype": 0, "compress": 0}
CANDIDATES = {  # name -> (ordering function of K or None, permc_spec of splu)
    "dhlb": (nested_dissection, None),
    "metis-default": (lambda K: metis_order(pattern_graph(K), {}), None),
    "metis-rm": (lambda K: metis_order(pattern_graph(K), _FAST), None),
    "metis-rm-u500": (lambda K: metis_order(pattern_graph(K), {**_FAST, "ufactor": 500}), None),
    "metis-coarse2": (lambda K: coarse_metis_order(K, 1), None),
    "metis-coarse4": (lambda K: coarse_metis_order(K, 2), None),
    "amd": (amd_order, None),
    "rcm": (rcm_order, None),
    "COLAMD": (None, "COLAMD"),
    "MMD_AT_PLUS_A": (None, "MMD_AT_PLUS_A"),
    "MMD_ATA": (None, "MMD_ATA"),
}


def amd_available() -> bool:
    try:
        import cvxopt.amd  # noqa: F401
    except ImportError:
        return False
    return True


# ---------------------------------------------------------------------- one measurement (child process)
def measure_once(K, name, b):
    """Order, factorize and solve once; returns a dict (times in seconds)."""
    order_fn, spec = CANDIDATES[name]
    kw = {"diag_pivot_thresh": 0.0, "options": {"SymmetricMode": True}}
    t0 = time.perf_counter()
    q = order_fn(K) if order_fn is not None else None
    t1 = time.perf_counter()
    if q is None:  # SuperLU orders (dhlb below ND_MIN: MMD_AT_PLUS_A, as the backend)
        lu = spla.splu(K, permc_spec=spec or "MMD_AT_PLUS_A", **kw)
    else:
        assert np.array_equal(np.sort(q), np.arange(K.shape[0])), "not a permutation"
        lu = spla.splu(canonical_csc(K[q][:, q]), permc_spec="NATURAL", **kw)
    t2 = time.perf_counter()
    solves = []
    for _ in range(3):
        s0 = time.perf_counter()
        if q is None:
            x = lu.solve(b)
        else:
            x = np.empty_like(b)
            x[q] = lu.solve(b[q])
        solves.append(time.perf_counter() - s0)
    res = float(np.linalg.norm(K @ x - b) / np.linalg.norm(b))
    return {"order": (t1 - t0) if order_fn is not None else None, "factor": t2 - t1, "fill": int(lu.L.nnz + lu.U.nnz),
            "solve": min(solves), "residual": res, "superlu_orders": q is None}


def _child(conn, K, name, b, repeat, mem_bytes):
    try:
        with open("/proc/self/statm") as f:
            vm = int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        resource.setrlimit(resource.RLIMIT_AS, (vm + mem_bytes, vm + mem_bytes))
        for _ in range(repeat):
            r = measure_once(K, name, b)
            conn.send(r)
            if (r["order"] or 0.0) + r["factor"] > 10.0:
                break
    except (MemoryError, SystemError):
        conn.send({"error": "out of memory"})
    except Exception as err:  # report and go on with the next candidate
        conn.send({"error": f"{type(err).__name__}: {str(err)[:60]}"})
    finally:
        conn.close()


def measure(K, name, b, repeat, timeout, mem_bytes):
    """Best of ``repeat`` runs of ``name`` on ``K`` in a forked child, within ``timeout`` seconds."""
    ctx = multiprocessing.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(child, K, name, b, repeat, mem_bytes))
    proc.start()
    child.close()
    runs, error = [], None
    deadline = time.perf_counter() + timeout
    while True:
        left = deadline - time.perf_counter()
        if left <= 0 or not parent.poll(left):
            if proc.is_alive():
                error = "timeout"
            break
        try:
            msg = parent.recv()
        except EOFError:  # child finished (or died)
            break
        if "error" in msg:
            error = msg["error"]
        else:
            runs.append(msg)
    if proc.is_alive():
        proc.kill()
    proc.join()
    if not runs and error is None:
        error = f"child died (exit code {proc.exitcode})"
    if not runs:
        return {"error": error}
    best = min(runs, key=lambda r: (r["order"] or 0.0) + r["factor"])
    best = dict(best)
    best["order"] = min(r["order"] for r in runs) if best["order"] is not None else None
    best["factor"] = min(r["factor"] for r in runs)
    best["solve"] = min(r["solve"] for r in runs)
    best["runs"] = len(runs)
    if error == "timeout":  # some runs finished before the limit
        best["note"] = "timeout after these runs"
    return best


# ---------------------------------------------------------------------- driver
def field_matrix(name):
    """``K = A + εM`` of the n = 4, s = 0 field of a mesh, as the eigensolver factorizes it."""
    V, F = load(name)
    A, M = energy_matrices(V, F, n=4, s=0.0)
    return canonical_csc(A + default_shift(A, M) * M), len(F)


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip the 302k-face kitten-x16")
    ap.add_argument("--json", help="write the rows to this file")
    ap.add_argument("--mesh", action="append", help="only these meshes (names as in MESHES)")
    ap.add_argument("--only", action="append", help="only these candidates")
    ap.add_argument("--no-shuffle", action="store_true", help="skip the randomly permuted copies")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per candidate and matrix")
    ap.add_argument("--mem-gb", type=float, default=6.0, help="memory limit of a candidate's process")
    ap.add_argument("--seed", type=int, default=0, help="of the random vertex permutation")
    args = ap.parse_args()
    names = args.mesh or [m for m in MESHES if not (args.quick and m == "kitten-x16")]
    cands = args.only or list(CANDIDATES)
    has_amd = amd_available()
    load0 = os.getloadavg()
    print(f"orderings for splu(SymmetricMode, diag_pivot_thresh=0) of K = A + εM (n = 4, s = 0 field); "
          f"OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}; best of {args.repeat}; timeout "
          f"{args.timeout:g} s; load average {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}")
    head = (f"{'matrix':<26}{'n':>8}{'ordering':>15}{'order':>8}{'factor':>8}{'fill':>7}{'nnz(L+U)':>11}"
            f"{'solve':>8}{'total':>8}{'vs dhlb':>8}")
    print(head)
    print("-" * len(head))
    rows = []
    for name in names:
        K0, faces = field_matrix(name)
        n = K0.shape[0]
        variants = [("", K0)]
        if not args.no_shuffle:
            p = np.random.default_rng(args.seed).permutation(n)
            variants.append(("+shuf", canonical_csc(K0[p][:, p])))
        for tag, K in variants:
            b = np.random.default_rng(1).standard_normal(n) + 1j * np.random.default_rng(2).standard_normal(n)
            ref = None
            for cand in cands:
                if cand == "amd" and not has_amd:
                    r = {"error": "n/a (pip install cvxopt)"}
                else:
                    r = measure(K, cand, b, args.repeat, args.timeout, int(args.mem_gb * 2**30))
                row = {"mesh": name + tag, "faces": faces, "n": n, "ordering": cand, **r}
                if "error" not in r:
                    row["total"] = (r["order"] or 0.0) + r["factor"] + SOLVES * r["solve"]
                    if cand == "dhlb":
                        ref = row
                    if ref is not None:
                        row["fill_ratio"] = r["fill"] / ref["fill"]
                        row["total_ratio"] = row["total"] / ref["total"]
                    if r["residual"] > 1e-8:
                        row["note"] = f"residual {r['residual']:.1e}"
                    print(f"{name + tag:<26}{n:>8}{cand:>15}{fmt(r['order'], '8.3f')}{r['factor']:>8.3f}"
                          f"{fmt(row.get('fill_ratio'), '7.3f')}{r['fill']:>11}{r['solve']:>8.4f}{row['total']:>8.2f}"
                          f"{fmt(row.get('total_ratio'), '8.2f')}{'  ' + row['note'] if 'note' in row else ''}",
                          flush=True)
                else:
                    print(f"{name + tag:<26}{n:>8}{cand:>15}  {r['error']}", flush=True)
                rows.append(row)
        print(flush=True)
    load1 = os.getloadavg()
    print(f"load average before {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}, after {load1[0]:.2f} {load1[1]:.2f} "
          f"{load1[2]:.2f}")
    print(f"\nsummary over the matrices with n ≥ ND_MIN = {ND_MIN} (ratios to dhlb on the same matrix):")
    print(f"{'ordering':<15}{'max fill':>9}{'max total':>10}{'geo total':>10}{'sum total s':>12}{'failures':>9}")
    big = [r for r in rows if r["n"] >= ND_MIN]
    for cand in cands:
        rs = [r for r in big if r["ordering"] == cand]
        ok = [r for r in rs if "total_ratio" in r]
        fails = len(rs) - len(ok)
        if not ok:
            print(f"{cand:<15}{'':>41}{fails:>9}")
            continue
        fr, tr = [r["fill_ratio"] for r in ok], [r["total_ratio"] for r in ok]
        total = f"{sum(r['total'] for r in ok):.2f}" if not fails else "-"  # a sum without the failures misleads
        print(f"{cand:<15}{max(fr):>9.3f}{max(tr):>10.2f}{np.exp(np.mean(np.log(tr))):>10.2f}{total:>12}{fails:>9}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"load_before": load0, "load_after": load1, "timeout": args.timeout, "repeat": args.repeat,
                       "solves_in_total": SOLVES, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
