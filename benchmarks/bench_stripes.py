"""Benchmark of stripe patterns (issue 6): per-phase and end-to-end times on spot, kitten and the bunny.

For each mesh and case (n = 1 vector field, n = 2 line field; cotan and fem energy) it prints the
times of ``stripe_pattern`` (setup = mesh + form + matrices, solve = smallest eigenpair,
texture) with the direction field given (the field's own time is printed apart), and the ratio
of the end-to-end stripe time to **one factorization + one solve of the plain real cotangent
Laplacian** ``K + εM`` of the same mesh with the same backend, measured in the same run
(target <= 2.5). Each figure is the best of ``REPEAT`` runs.

Run:  python benchmarks/bench_stripes.py [backend]      (reads ../shared/meshes)
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from dhlb.fem.solvers import _get_backend, default_shift
from dhlb.io import read_surface
from dhlb.stripes import stripe_pattern
from dhlb.surface import direction_field, validate_surface
from dhlb.surface.tangent import TangentBundle

MESHES = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "meshes")
FILES = ["spot.obj", "kitten.obj", "stanford-bunny.obj"]
REPEAT = 2
CASES = [(1, "cotan"), (2, "cotan"), (2, "fem")]


def best(fn, repeat=REPEAT):
    out, t = None, np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        t = min(t, time.perf_counter() - t0)
    return out, t


def baseline(V, F, backend):
    """One factorization + solve of the plain real cotangent Laplacian (the mesh is not timed)."""
    geo = TangentBundle(validate_surface(V, F), 1).geometry
    K, M = geo.stiffness_matrix(), geo.mass_matrix(lumped=True)
    be = _get_backend(backend)

    def run():
        eps = default_shift(K, M)
        fac = be.factorize((K + eps * M).tocsc(), positive_definite=True)
        return fac.solve(M @ np.ones(K.shape[0]))

    return best(run, 3)[1]


def main(backend=None):
    warnings.simplefilter("ignore")
    rows = []
    for name in FILES:
        path = os.path.join(MESHES, name)
        if not os.path.exists(path):
            print(f"skipping {name}: not found in {MESHES}")
            continue
        V, F = read_surface(path)
        t_base = baseline(V, F, backend)
        for n, energy in CASES:
            fld, t_field = best(lambda: direction_field(V, F, n=n, backend=backend), 1)
            res, t_all = best(lambda: stripe_pattern(V, F, fld, spacing=8.0, n=n, energy=energy, backend=backend))
            t = res.timings
            rows.append((name, res.mesh.n_faces, n, energy, t_field, t["setup"], t["solve"], t["texture"], t_all,
                         t_base, t_all / t_base, res.solver["iterations"], res.solver["unknowns"],
                         res.zero_faces.size, res.branch_faces.size))
    head = ("mesh", "faces", "n", "energy", "field s", "setup s", "solve s", "texture s", "stripes s",
            "K fact+solve s", "ratio", "iters", "unknowns", "zeros", "branch")
    fmt = "{:<18} {:>6} {:>2} {:>6} {:>8} {:>8} {:>8} {:>9} {:>9} {:>14} {:>6} {:>5} {:>8} {:>5} {:>6}"
    print(f"backend: {rows[0] and _get_backend(backend).name if rows else backend}; OPENBLAS_NUM_THREADS="
          f"{os.environ.get('OPENBLAS_NUM_THREADS')}; best of {REPEAT}")
    print(fmt.format(*head))
    for r in rows:
        print(fmt.format(r[0], r[1], r[2], r[3], *(f"{x:.3f}" for x in r[4:10]), f"{r[10]:.2f}", *r[11:]))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
