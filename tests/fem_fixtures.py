"""Shared builders for the FEM tests: flat tori with uniform magnetic fields, jittered grids."""

from __future__ import annotations

import numpy as np

from dhlb import Chain, EuclideanComplex, HermitianLineBundle, line_bundle_with_curvature
from dhlb.examples import cube_nd, torus_nd


def wrap(d):
    return d - np.round(d)


def flat_torus_landau(n: int, m: int, degree: int):
    """Unit flat n-torus (n = 2, 3) with the uniform field B = 2π·degree along the last-but-n... z.

    The field is ``B dx∧dy``: flux ``2π·degree`` through each xy-cross-section. For n = 3 the
    holonomy around the straight z-loop is set to 1, as for the continuum potential with
    ``A_z = 0``; the continuum spectrum is then ``B(2k+1) + (2πl)²`` with the lowest level ``B``
    of multiplicity ``degree``.
    """
    X, P = torus_nd(n, m, return_points=True)
    E = X.simplices(1)
    D = wrap(P[E[:, 1]] - P[E[:, 0]])
    geo = EuclideanComplex(X, edge_lengths=np.linalg.norm(D, axis=1))
    T = X.simplices(2)
    e1, e2 = wrap(P[T[:, 1]] - P[T[:, 0]]), wrap(P[T[:, 2]] - P[T[:, 0]])
    B = 2 * np.pi * degree
    L = line_bundle_with_curvature(X, B * 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]))
    if n == 3:
        loop = Chain.path(X, list(range(m)) + [0])  # vertices (0, 0, k) are labelled k
        phi = L.holonomy(loop)
        L = HermitianLineBundle.from_angles(X, L.connection_angles - phi * D[:, 2], L.curvature)
    return L, geo, B


def jittered_grid(n: int, m: int, seed: int = 0, amount: float = 0.25):
    """cube_nd(n, m) with interior vertices moved randomly (still a valid triangulation)."""
    X, P = cube_nd(n, m, return_points=True)
    rng = np.random.default_rng(seed)
    interior = np.all((P > 1e-9) & (P < 1 - 1e-9), axis=1)
    P = P.copy()
    P[interior] += amount / m * (rng.random((interior.sum(), n)) - 0.5)
    return X, P


def random_bundle(X, rng, scale: float = 3.0):
    """A bundle with curvature of random size (up to several π per face) and random flat part."""
    if X.dim >= 3:
        # a closed Ω: Ω = dα for a random real 1-form (exact, hence integral), plus nothing else
        alpha = scale * rng.standard_normal(X.n_simplices(1))
        Om = X.coboundary(1) @ alpha
    else:
        Om = scale * rng.standard_normal(X.n_simplices(2))
        if X.boundary_complex() is None:  # closed surface: make the total integral
            o = X.orientation()
            total = float(o @ Om)
            Om = Om - o * (total - 2 * np.pi * np.round(total / (2 * np.pi))) / Om.size
    L = line_bundle_with_curvature(X, Om)
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices))
    return L.gauge(g)
