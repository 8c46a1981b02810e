r"""Closed-form element kernels for triangles (n = 2) and tetrahedra (n = 3).

The kernels of the registry in :mod:`dhlb.fem.kernels` for n = 2, 3: same interface and result as
:func:`dhlb.fem.kernels.generic_kernel` (formulas and conventions in :mod:`dhlb.fem.integrals`),
vectorised over blocks of simplices (simplex axis last, no loop over simplices or pairs); the
moment functions are evaluated by :mod:`dhlb.fem._fast_moments`, only those the requested
matrices need (the mass needs one per pair: ``Θ_ab(a, b)``).

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

The kernels trust their input (validated at the public boundary: ``EuclideanComplex``,
``HermitianLineBundle``, :func:`dhlb.fem.integrals.local_matrices`).
"""

from __future__ import annotations

from functools import cache
from itertools import combinations
from math import comb

import numpy as np

from dhlb.fem._fast_moments import moments_3d, phi_2d
from dhlb.fem._local_data import local_edges, local_triangles

__all__ = ["kernel_2d", "kernel_3d", "split_entries"]

_CHUNKS = {2: 16384, 3: 4096}   # simplices per block: the per-pair arrays stay in cache


@cache
def _tri_index(n: int, x: int, y: int, z: int) -> tuple[int, int]:
    """(row in local_triangles(n), sign) of Ω_xyz."""
    inv = sum(1 for i, j in combinations((x, y, z), 2) if i > j)
    rows = [tuple(t) for t in local_triangles(n)]
    return rows.index(tuple(sorted((x, y, z)))), (-1) ** inv


# --------------------------------------------------------------------------- local matrices
#
# Inside a block the simplex axis is last: G (k², mc), Ω (T, mc), r (E, mc), per-pair arrays (E, mc).


@cache
def _tables(n: int):
    """Index tables: Ω-index and sign of the triangles each pair (a, b) needs, and G indices by role."""
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
    return oi, os, gi


def _off(out, xr, xi, re, im):
    """``out = r vol (re + i im)``; ``out`` the pair (real part, imaginary part) of ``(pairs, mc)`` arrays."""
    o_re, o_im = out
    np.multiply(xr, re, out=o_re)
    o_re -= xi * im
    np.multiply(xr, im, out=o_im)
    o_im += xi * re


def _block_2d(G, vol, om, rr, ri, out):
    mo, md, ao, ad = out
    _, os, gi = _tables(2)
    w = om[0]
    sgn = os[0]                                                  # w_pair = ±ω; φ(-w) = conj φ(w)
    xr, xi = rr * vol, ri * vol
    if ao is None:                                               # mass only: φ0
        fre, fim = phi_2d(w, (0,))
        _off(mo, xr, xi, fre[0], fim[0] * sgn)
        md[:] = vol / 6.0
        return
    fre, fim = phi_2d(w)
    gab, gcc = G[gi["ab"]], G[gi["cc"]]
    u1, s1 = G[gi["ac"]] + G[gi["bc"]], G[gi["aa"]] + G[gi["bb"]]
    vre = gab * fre[1] + u1 * fre[2] + s1 * fre[3] + gcc * fre[4]
    vim = (gab * fim[1] + u1 * fim[2] + s1 * fim[3] + gcc * fim[4]) * sgn
    if mo is not None:
        _off(mo, xr, xi, fre[0], fim[0] * sgn)
        md[:] = vol / 6.0
    _off(ao, xr, xi, vre, vim)
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
    oi, os, gi = _tables(3)
    xr, xi = rr * vol, ri * vol
    if ao is None:                                               # mass only: T411 = Θ_ab(a, b)
        A1, A2 = om[oi[:2]] * os[:2]
        fre, fim = moments_3d(A1.ravel(), A2.ravel(), (1,))
        _off(mo, xr, xi, fre[0].reshape(6, mc), fim[0].reshape(6, mc))
        md[:] = vol / 10.0
        return
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
    if mo is not None:
        _off(mo, xr, xi, fre[1], fim[1])
        md[:] = vol / 10.0
    _off(ao, xr, xi, vre, vim)
    ad[:] = vol * (Ga + q / 420.0)


def _closed_kernel(n, gram, volume, omega, connection, mass, dirichlet, split=False, rows=None):
    """The kernel of n = 2, 3; with ``split`` the off-diagonal entries are ``(2, pairs, m)`` float (real, imaginary).

    With ``rows`` the connection is given per edge of the complex, ``connection[rows]`` per simplex.
    """
    m, k, ne = volume.size, n + 1, comb(n + 1, 2)
    gauge = [(p, *_tri_index(n, 0, int(a), int(b))) for p, (a, b) in enumerate(local_edges(n)) if a > 0]
    off_shape, off_type = ((2, ne, m), float) if split else ((ne, m), complex)
    out = [np.empty(off_shape, off_type), np.empty((k, m))] if mass else [None, None]
    out += [np.empty(off_shape, off_type), np.empty((k, m))] if dirichlet else [None, None]
    if not (mass or dirichlet):
        return tuple(out)
    parts = [None if x is None else ((x[0], x[1]) if split else (x.real, x.imag)) for x in out[0::2]]
    step, ch = (_block_2d if n == 2 else _block_3d), _CHUNKS[n]
    # gram (m, k, k) as a view of a (k, k, m) array (what EuclideanComplex stores) costs no copy here
    gt = None if gram is None else np.moveaxis(gram, 0, -1).reshape(k * k, m)
    for s in range(0, m, ch):
        sl = slice(s, s + ch)
        G = None if gt is None else np.ascontiguousarray(gt[:, sl])
        om = np.ascontiguousarray(omega[sl].T)
        if connection is None:                                   # local gauge r_ab = exp(iΩ_0ab)
            ang = np.zeros((ne, om.shape[1]))
            for p, t, sg in gauge:
                ang[p] = sg * om[t]
            rr, ri = np.cos(ang), np.sin(ang)
        else:
            r = connection[sl] if rows is None else connection[rows[sl]]
            rt = np.ascontiguousarray(np.ascontiguousarray(r, dtype=complex).view(float).T)
            rr, ri = rt[0::2], rt[1::2]
        blk = [None if p is None else (p[0][:, sl], p[1][:, sl]) for p in parts]
        step(G, volume[sl], om, rr, ri, [blk[0], None if blk[0] is None else out[1][:, sl],
                                         blk[1], None if blk[1] is None else out[3][:, sl]])
    return tuple(out)


def kernel_2d(gram, volume, omega, connection=None, *, mass=True, dirichlet=True):
    """Closed-form element kernel of triangles; interface of :func:`dhlb.fem.kernels.generic_kernel`.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[[2., -1, -1], [-1, 1, 0], [-1, 0, 1]]])
    >>> Mo, Md, Ao, Ad = kernel_2d(G, np.array([0.5]), np.array([[0.0]]))
    >>> Ao.real.ravel().tolist(), Ad.ravel().tolist()
    ([-0.5, -0.5, 0.0], [1.0, 0.5, 0.5])
    """
    return _closed_kernel(2, gram, volume, omega, connection, mass, dirichlet)


def kernel_3d(gram, volume, omega, connection=None, *, mass=True, dirichlet=True):
    """Closed-form element kernel of tetrahedra; interface of :func:`dhlb.fem.kernels.generic_kernel`.

    Examples
    --------
    >>> import numpy as np
    >>> Mo, Md, Ao, Ad = kernel_3d(None, np.array([6.0]), np.zeros((1, 4)), dirichlet=False)
    >>> Mo.real.ravel().tolist(), Md.ravel().tolist(), Ao is None
    ([0.3, 0.3, 0.3, 0.3, 0.3, 0.3], [0.6, 0.6, 0.6, 0.6], True)
    """
    return _closed_kernel(3, gram, volume, omega, connection, mass, dirichlet)


def split_entries(n, gram, volume, omega, connection=None, *, mass=True, dirichlet=True, rows=None):
    """The closed-form kernel of n-simplices (n = 2, 3) with the off-diagonal entries as real and imaginary parts.

    What the assembly sums (one ``bincount`` per part, no strided copy of a complex array).

    Parameters
    ----------
    n : {2, 3}
        The dimension of the simplices.
    gram, volume, omega, connection, mass, dirichlet :
        As for :func:`kernel_2d` (interface of :func:`dhlb.fem.kernels.generic_kernel`).
    rows : (m, C(n+1, 2)) int array, optional
        With it ``connection`` is one value per edge of the complex and ``connection[rows]`` that of the
        local edges, gathered block by block (no ``(m, C(n+1, 2))`` complex copy).

    Returns
    -------
    mass_off, mass_diag, dirichlet_off, dirichlet_diag : arrays or None
        As :func:`kernel_2d`, but each ``off`` is ``(2, C(n+1, 2), m)`` float: ``off[0] + i off[1]`` is the
        complex entry, to the bit.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[[2., -1, -1], [-1, 1, 0], [-1, 0, 1]]])
    >>> Mo, Md, Ao, Ad = split_entries(2, G, np.array([0.5]), np.array([[0.0]]))
    >>> Ao.shape, Ao[0].ravel().tolist()
    ((2, 3, 1), [-0.5, -0.5, 0.0])
    """
    return _closed_kernel(n, gram, volume, omega, connection, mass, dirichlet, split=True, rows=rows)
