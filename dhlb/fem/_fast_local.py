r"""Fast local FEM matrices for stacks of triangles (n = 2) and tetrahedra (n = 3).

Same result as :func:`dhlb.fem.integrals.local_matrices` (formulas and conventions in
:mod:`dhlb.fem.integrals`), about 20 times faster (more through :func:`fast_local_entries`,
which skips the (m, k, k) layout); the moment functions are evaluated by :mod:`dhlb.fem._fast_moments`.

Reduction.  For the pair ``(a, b)`` the exponent ``-i Σ_m Ω_abm x_m`` involves only the other
vertices ``c (, d)``, so a moment ``(1/vol) ∫ x^p e^{...}`` is ``n! Π p_m! F(α, β(, γ))`` with
``F = exp[0^α, z_c^β(, z_d^γ)]``, ``z_c = -iΩ_abc``, ``α = p_a + p_b + 2``, ``β = p_c + 1``.
``W^a`` has the entries ``±Ω_akl`` (k, l ≠ a) only, so with ``A1 = Ω_abc``, ``A2 = Ω_abd``,
``A3 = Ω_acd``, ``B3 = Ω_bcd`` the Dirichlet entry of Theorem 17 is (n = 3)::

    A[b, a] / (r_ab vol) = G_ab Λ + Q_ba X611 + (Q_bc + Q_ca) X521 + (Q_bd + Q_da) X512
                           + Q_cc X431 + Q_dd X413 + (Q_cd + Q_dc) X422
                           + i [(P^a_b - P^b_a) T411 + (P^a_c - P^b_c) T321 + (P^a_d - P^b_d) T312]

with ``Q = W^aᵀ G W^b``, ``P^a = (G W^a)_b``, ``P^b = (G W^b)_a`` written out in :func:`_block_3d`
and ``Λ = 6F211``, ``T411 = 6F411 = Θ_ab(a, b)`` (also the mass entry), ``T321 = 6F321``,
``X611 = 24F611``, ``X521 = 12F521``, ``X431 = 12F431``, ``X422 = 6F422`` (c <-> d alike).  For
n = 2 (no d) all depends on ``w = Ω_abc``: ``A[b, a] / (r vol) = G_ab φ1 + (G_ac + G_bc) φ2
+ (G_aa + G_bb) φ3 + G_cc φ4`` and ``Θ_ab(a, b) = φ0`` with ``φ(-w) = conj φ(w)``, one evaluation
per triangle.  The diagonal has no exponential: ``A[a, a] = vol (G_aa + Σ (W^aᵀ G W^a)_{ll'}
Ξ_aa(l, l'))`` with the constants ``Ξ_aa``.  The symbolic check of these identities against
the formulas of :mod:`dhlb.fem.integrals` is ``proofs/fast_local_closed_forms.py``.

Validation is that of :func:`~dhlb.fem.integrals.local_matrices` (same typed errors), done by
cheap conservative tests with a fall-back to the exact checks of :mod:`dhlb.fem._local_data`.
"""

from __future__ import annotations

from functools import cache
from itertools import combinations
from math import comb

import numpy as np

from dhlb.errors import InvalidMetricError, NonFiniteError, ShapeError
from dhlb.fem._fast_moments import moments_3d, phi_2d
from dhlb.fem._local_data import (
    HOLONOMY_ATOL,
    UNIT_ATOL,
    check_closed,
    local_edges,
    local_triangles,
    parse_connection,
    parse_gram,
    parse_omega,
    parse_volume,
)
from dhlb.fem._local_matrices import local_matrices

__all__ = ["fast_local_entries", "fast_local_matrices"]

_CHUNKS = {2: 16384, 3: 4096}   # simplices per block: the per-pair arrays stay in cache

# --------------------------------------------------------------------------- validation


@cache
def _tri_index(n: int, x: int, y: int, z: int) -> tuple[int, int]:
    """(row in local_triangles(n), sign) of Ω_xyz."""
    inv = sum(1 for i, j in combinations((x, y, z), 2) if i > j)
    rows = [tuple(t) for t in local_triangles(n)]
    return rows.index(tuple(sorted((x, y, z)))), (-1) ** inv


@cache
def _projector(n: int) -> np.ndarray:
    """``(n(n+1)/2, k²)``: flattened G -> upper triangle of the symmetric part of QᵀGQ, Q ⊥ 1."""
    k = n + 1
    q = np.linalg.svd(np.eye(k) - 1.0 / k)[0][:, :n]           # orthonormal basis of 1^⊥
    pairs = [(i, j) for i in range(n) for j in range(i, n)]
    return np.array([0.5 * (np.outer(q[:, i], q[:, j]) + np.outer(q[:, j], q[:, i])).ravel() for i, j in pairs])


def _gram_surely_ok(gt: np.ndarray, n: int) -> np.ndarray:
    """Simplices whose Gram matrix certainly passes :func:`parse_gram` (``gt`` of shape (k², mc)).

    Half its tolerances for symmetry and row sums, relative to ``s = max G_ii <= λ_max``.  Rank and
    sign by bounds on the eigenvalues of ``K``, the restriction to ``1^⊥``: with ``δ = max |row sum
    of the symmetric part|``, Weyl's inequality puts those of G within δ of ``{s', eig K}``,
    ``|s'| <= δ``; ``λ_min(K) >= det K / tr K`` (n = 2), ``>= 4 det K / tr² K`` (n = 3).  NaN and
    inf fail the comparisons.
    """
    k = n + 1
    sq = gt.reshape(k, k, -1)
    with np.errstate(all="ignore"):
        dg = np.array([sq[i, i] for i in range(k)])
        scale, dmin = dg.max(axis=0), dg.min(axis=0)
        asym = np.zeros(gt.shape[1])
        for i, j in combinations(range(k), 2):
            np.maximum(asym, np.abs(sq[i, j] - sq[j, i]), out=asym)
        rows, cols = sq.sum(axis=1), sq.sum(axis=0)
        delta = np.abs(rows + cols).max(axis=0) * 0.5
        kk = _projector(n) @ gt
        if n == 2:
            tr, det = kk[0] + kk[2], kk[0] * kk[2] - kk[1] ** 2
            lam = det / tr
        else:
            a, b, c, d, e, f = kk                              # [[a b c] [b d e] [c e f]]
            tr = a + d + f
            det = a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d)
            lam = 4.0 * det / (tr * tr)
        ok = (dmin > 0) & np.isfinite(scale) & (asym <= 0.5e-10 * scale)
        ok &= (np.abs(rows).max(axis=0) <= 0.5e-8 * scale) & (delta <= 0.25e-8 * scale)
        ok &= (det > 0) & (lam - delta > 1e-12 * (tr + 2 * delta))
    return ok


def _conn_surely_ok(ot: np.ndarray, re: np.ndarray, im: np.ndarray, n: int) -> np.ndarray:
    """Simplices whose connection certainly passes :func:`parse_connection` (half its tolerances)."""
    with np.errstate(all="ignore"):
        ok = (np.abs(re * re + im * im - 1.0) <= UNIT_ATOL).all(axis=0)     # ||r| - 1| <= UNIT_ATOL / 2
        edge = {tuple(e): i for i, e in enumerate(local_edges(n))}
        for t, (a, b, c) in enumerate(local_triangles(n)):
            i, j, l = edge[a, b], edge[b, c], edge[a, c]
            pr, pi = re[i] * re[j] - im[i] * im[j], re[i] * im[j] + im[i] * re[j]
            hr, hi = pr * re[l] + pi * im[l], pi * re[l] - pr * im[l]          # r_ab r_bc conj(r_ac)
            ok &= (hr - np.cos(ot[t])) ** 2 + (hi - np.sin(ot[t])) ** 2 <= (0.5 * HOLONOMY_ATOL) ** 2
    return ok


def _exact_checks(g, arr, connection, gram_bad) -> None:
    """Run the exact checks where the fast ones had doubts (they raise the precise typed error)."""
    if gram_bad is not None:
        try:
            parse_gram(g[gram_bad])
        except (InvalidMetricError, NonFiniteError):
            parse_gram(g)            # the same error, naming the first offending simplex
            raise
    if connection is not None:
        parse_connection(connection, arr.shape[0], g.shape[1] - 1, arr)


def _parse(gram, volume, omega, connection, check):
    try:
        g = np.asarray(gram, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidMetricError(f"gram must be a real array: {exc}") from None
    if g.ndim != 3 or g.shape[1] != g.shape[2] or g.shape[1] not in (3, 4):
        raise ShapeError(f"gram must have shape (m, 3, 3) or (m, 4, 4) (stacks of triangles or tetrahedra), "
                         f"got {g.shape}; use local_matrices for single simplices or other dimensions")
    n, m = g.shape[1] - 1, g.shape[0]
    if m == 0 and np.shape(omega) == (0, comb(n + 1, 3)) and np.shape(volume) == (0,):
        omega, volume = np.zeros((0, comb(n + 1, 3))), np.zeros(0)      # parse_omega needs a row
        return g, volume, omega, None if connection is None else np.zeros((0, comb(n + 1, 2)), complex), n
    arr, _, batched = parse_omega(omega, n)
    vol, b_v = parse_volume(volume)
    if not batched or not b_v or arr.shape[0] != m or vol.size != m:
        raise ShapeError(f"fast_local_matrices needs one row per simplex in every argument: gram {g.shape}, "
                         f"volume {np.shape(volume)}, curvature {np.shape(omega)}; use local_matrices otherwise")
    if check:
        check_closed(arr, n)
    r = None
    if connection is not None:
        r, ne = np.asarray(connection), comb(n + 1, 2)
        if r.shape != (m, ne):
            raise ShapeError(f"connection must have shape (m, {ne}) = one unit complex number per local edge "
                             f"in lexicographic order (m = {m}), got {r.shape}")
        try:
            r = np.ascontiguousarray(r, dtype=complex)
        except (TypeError, ValueError):
            parse_connection(connection, m, n, arr)
            raise
    return g, vol, arr, r, n


# --------------------------------------------------------------------------- local matrices
#
# Inside a block the simplex axis is last: G (k², mc), Ω (T, mc), r (E, mc), per-pair arrays (E, mc).


@cache
def _tables(n: int):
    """Index tables: pairs (a, b) with their others, Ω-index and sign of the needed triangles, G indices."""
    k = n + 1
    pairs = [tuple(int(v) for v in e) for e in local_edges(n)]
    others = [[v for v in range(k) if v not in e] for e in pairs]
    tris = [[(a, b, c) for c in o] + ([(a, o[0], o[1]), (b, o[0], o[1])] if n == 3 else [])
            for (a, b), o in zip(pairs, others)]
    oi = np.array([[_tri_index(n, *t)[0] for t in row] for row in tris]).T
    os = np.array([[_tri_index(n, *t)[1] for t in row] for row in tris], dtype=float).T[:, :, None]
    names = ["aa", "bb", "ab"] + ([f"{x}{y}" for x in "abcd" for y in "abcd" if x <= y and y in "cd"]
                                  if n == 3 else ["ac", "bc", "cc"])
    gi = {}
    for nm in names:
        col = []
        for (a, b), o in zip(pairs, others):
            lab = {"a": a, "b": b, "c": o[0], "d": o[-1]}
            col.append(k * lab[nm[0]] + lab[nm[1]])
        gi[nm] = np.array(col)
    lower = np.array([k * b + a for a, b in pairs])
    upper = np.array([k * a + b for a, b in pairs])
    return oi, os, gi, lower, upper


def _off(out, xr, xi, re, im):
    """``out = r vol (re + i im)`` (complex, (pairs, mc))."""
    np.multiply(xr, re, out=out.real)
    out.real -= xi * im
    np.multiply(xr, im, out=out.imag)
    out.imag += xi * re


def _block_2d(G, vol, om, rr, ri, out):
    mo, md, ao, ad = out
    _, os, gi, _, _ = _tables(2)
    w = om[0]
    fre, fim = phi_2d(w)
    sgn = os[0]                                                  # w_pair = ±ω; φ(-w) = conj φ(w)
    gab, gcc = G[gi["ab"]], G[gi["cc"]]
    u1, s1 = G[gi["ac"]] + G[gi["bc"]], G[gi["aa"]] + G[gi["bb"]]
    vre = gab * fre[1] + u1 * fre[2] + s1 * fre[3] + gcc * fre[4]
    vim = (gab * fim[1] + u1 * fim[2] + s1 * fim[3] + gcc * fim[4]) * sgn
    xr, xi = rr * vol, ri * vol
    _off(mo, xr, xi, fre[0], fim[0] * sgn)
    _off(ao, xr, xi, vre, vim)
    md[:] = vol / 6.0
    ad[::-1] = vol * (gcc + (w * w / 90.0) * (s1 - gab))         # vertex c of the pair p is 2 - p


def _diag_tables_3d():
    idx, sgn, gi = np.empty((3, 4), dtype=int), np.empty((3, 4, 1)), np.empty((7, 4), dtype=int)
    for a in range(4):
        b, c, d = [v for v in range(4) if v != a]
        for q, t in enumerate(((a, b, c), (a, b, d), (a, c, d))):
            idx[q, a], sgn[q, a, 0] = _tri_index(3, *t)
        gi[:, a] = [5 * a, 5 * b, 5 * c, 5 * d, 4 * b + c, 4 * b + d, 4 * c + d]
    return idx, sgn, gi


_DIAG3 = _diag_tables_3d()


def _block_3d(G, vol, om, rr, ri, out):
    mo, md, ao, ad = out
    mc = vol.size
    oi, os, gi, _, _ = _tables(3)
    A1, A2, A3, B3 = om[oi] * os                                 # (4, 6, mc): Ω_abc, Ω_abd, Ω_acd, Ω_bcd
    fre, fim = moments_3d(A1.ravel(), A2.ravel())
    fre, fim = fre.reshape(10, 6, mc), fim.reshape(10, 6, mc)
    gab, gcc, gdd, gcd = G[gi["ab"]], G[gi["cc"]], G[gi["dd"]], G[gi["cd"]]
    gac, gad, gbc, gbd = G[gi["ac"]], G[gi["ad"]], G[gi["bc"]], G[gi["bd"]]
    u1, u2, sab = gac + gbc, gad + gbd, G[gi["aa"]] + G[gi["bb"]]
    a11, a22, a12, a33, dd = A1 * A1, A2 * A2, A1 * A2, A3 * B3, B3 - A3
    b1, b2, b3, b4 = A1 * B3, A1 * A3, A2 * B3, A2 * A3
    c_re = (gab,
            -(a11 * gcc + 2.0 * a12 * gcd + a22 * gdd),                          # Q_ba
            a11 * u1 + a12 * u2 + dd * (A1 * gcd + A2 * gdd),                    # Q_bc + Q_ca
            a12 * u1 + a22 * u2 - dd * (A1 * gcc + A2 * gcd),                    # Q_bd + Q_da
            b2 * gad - b1 * gbd + a33 * gdd - a11 * gab,                         # Q_cc
            b3 * gbc - b4 * gac + a33 * gcc - a22 * gab,                         # Q_dd
            b1 * gbc - b2 * gac + b4 * gad - b3 * gbd - 2.0 * (a12 * gab + a33 * gcd))   # Q_cd + Q_dc
    c_im = (-(A1 * u1 + A2 * u2), A1 * sab - A3 * gbd + B3 * gad, A2 * sab + A3 * gbc - B3 * gac)
    vre, vim = gab * fre[0], gab * fim[0]
    for c, f in zip(c_re[1:], (4, 5, 6, 7, 8, 9)):
        vre += c * fre[f]
        vim += c * fim[f]
    for c, f in zip(c_im, (1, 2, 3)):
        vre -= c * fim[f]
        vim += c * fre[f]
    # diagonal: vol (G_aa + (tr(G W Wᵀ) + (W1)ᵀ G (W1)) / 420), W = W^a on the others b < c < d
    di, ds, dg = _DIAG3
    x, y, z = om[di] * ds
    Ga, Gb, Gc, Gd, Gbc, Gbd, Gcd = G[dg]
    xx, yy, zz = x * x, y * y, z * z
    s1, s2, s3 = x + y, z - x, -(y + z)
    q = (Gb * (xx + yy + s1 * s1) + Gc * (xx + zz + s2 * s2) + Gd * (yy + zz + s3 * s3)
         + 2.0 * (Gbc * (y * z + s1 * s2) + Gbd * (s1 * s3 - x * z) + Gcd * (x * y + s2 * s3)))
    xr, xi = rr * vol, ri * vol
    _off(mo, xr, xi, fre[1], fim[1])
    _off(ao, xr, xi, vre, vim)
    md[:] = vol / 10.0
    ad[:] = vol * (Ga + q / 420.0)


def fast_local_entries(gram, volume, omega, connection=None, *, check: bool = True):
    """The entries of the local matrices in a compact layout, simplex axis last (for assembly).

    Parameters
    ----------
    gram, volume, omega, connection :
        As in :func:`fast_local_matrices` (n = 2 or 3 only).
    check : bool
        Validate the values (Gram matrices, closedness, connection) as
        :func:`~dhlb.fem.integrals.local_matrices` does; ``False`` skips this for data taken from
        validated objects (shapes and finiteness of Ω and volumes are always checked).

    Returns
    -------
    M_off, M_diag, A_off, A_diag : ndarray
        ``X_off[p, s] = X_s[b, a]`` for the local edge ``p = (a, b)`` (order of
        :func:`~dhlb.fem.integrals.local_edges`), shape ``(C(n+1, 2), m)`` complex (``X_s[a, b]``
        is its conjugate); ``X_diag[a, s] = X_s[a, a]``, shape ``(n+1, m)`` real.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[[2., -1, -1], [-1, 1, 0], [-1, 0, 1]]])
    >>> Mo, Md, Ao, Ad = fast_local_entries(G, [0.5], [[0.0]])
    >>> Ao.real.ravel().tolist(), Ad.ravel().tolist()
    ([-0.5, -0.5, 0.0], [1.0, 0.5, 0.5])
    """
    g, vol, arr, r, n = _parse(gram, volume, omega, connection, check)
    m, k, ne = vol.size, n + 1, comb(n + 1, 2)
    gauge = [(p, *_tri_index(n, 0, int(a), int(b))) for p, (a, b) in enumerate(local_edges(n)) if a > 0]
    out = (np.empty((ne, m), dtype=complex), np.empty((k, m)), np.empty((ne, m), dtype=complex), np.empty((k, m)))
    step, ch = (_block_2d if n == 2 else _block_3d), _CHUNKS[n]
    for s in range(0, m, ch):
        sl = slice(s, s + ch)
        G = np.ascontiguousarray(g[sl].reshape(-1, k * k).T)
        om = np.ascontiguousarray(arr[sl].T)
        if r is None:                                            # local gauge r_ab = exp(iΩ_0ab)
            ang = np.zeros((ne, om.shape[1]))
            for p, t, sg in gauge:
                ang[p] = sg * om[t]
            rr, ri = np.cos(ang), np.sin(ang)
        else:
            rt = np.ascontiguousarray(r[sl].view(float).T)       # rows Re r_0, Im r_0, Re r_1, ...
            rr, ri = rt[0::2], rt[1::2]
        if check:
            gram_ok = _gram_surely_ok(G, n)
            conn_ok = True if r is None else _conn_surely_ok(om, rr, ri, n).all()
            if not (gram_ok.all() and conn_ok):
                bad = None if gram_ok.all() else s + np.flatnonzero(~gram_ok)
                _exact_checks(g, arr, None if conn_ok else connection, bad)
        step(G, vol[sl], om, rr, ri, [x[:, sl] for x in out])
    return out


def fast_local_matrices(gram, volume, omega, connection=None, *, check: bool = True):
    """Local mass and Dirichlet matrices ``(M, A)`` of a stack of triangles or tetrahedra.

    Same arguments and result as :func:`dhlb.fem.integrals.local_matrices` (Theorems 15, 17),
    batched arrays only; other dimensions are passed on to it.

    Parameters
    ----------
    gram : array_like, shape (m, n+1, n+1)
        ``<∇x_a, ∇x_b>`` per simplex.
    volume : array_like, shape (m,)
        Positive volumes.
    omega : array_like, shape (m, C(n+1, 3))
        Curvature on the local triangles in lexicographic order, closed per simplex.
    connection : array_like, shape (m, C(n+1, 2)), optional
        Unit complex ``r_ab`` on the local edges; omitted: the local gauge ``r_ab = exp(iΩ_0ab)``.
    check : bool
        See :func:`fast_local_entries`.

    Returns
    -------
    M, A : ndarray, shape (m, n+1, n+1), complex
        ``M[s, b, a] = r_ab vol Θ_ab(a, b)`` and the Dirichlet matrix, Hermitian.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.fem.integrals import local_matrices
    >>> G = np.array([[[2., -1, -1], [-1, 1, 0], [-1, 0, 1]]] * 2)
    >>> M, A = fast_local_matrices(G, [0.5, 0.5], [[0.3], [40.0]])
    >>> Mr, Ar = local_matrices(G, [0.5, 0.5], [[0.3], [40.0]])
    >>> bool(np.abs(M - Mr).max() < 1e-15 and np.abs(A - Ar).max() < 1e-13)
    True
    """
    if np.ndim(gram) != 3 or np.shape(gram)[-1] not in (3, 4):
        return local_matrices(gram, volume, omega, connection)
    entries = fast_local_entries(gram, volume, omega, connection, check=check)
    k, m = entries[1].shape
    lower, upper = _tables(k - 1)[3:]
    res = []
    for off, diag in (entries[:2], entries[2:]):
        out = np.empty((m, k * k), dtype=complex)
        for s in range(0, m, 8192):                             # blocks: the strided writes stay in cache
            o, sl = out[s: s + 8192], slice(s, s + 8192)
            for p in range(lower.size):
                o[:, lower[p]] = off[p, sl]
                o[:, upper[p]] = off[p, sl].conj()
            for a in range(k):
                o[:, (k + 1) * a] = diag[a, sl]
        res.append(out.reshape(m, k, k))
    return res[0], res[1]
