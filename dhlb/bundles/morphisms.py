"""Morphisms of discrete vector bundles: gauge, direct sum, tensor, dual, Hom, isomorphism search.

Proposition 2 of the seed: ``f: E → F`` is a morphism iff ``f_j η_ij = θ_ij f_i`` on every
edge, i.e. iff ``f`` is a parallel section of ``Hom(E, F) = F ⊗ E*``.  Theorem 2: E ≅ F iff
their monodromy representations at a base vertex are conjugate; :func:`find_isomorphism`
solves the linear intertwining equations ``M^F_g f = f M^E_g`` for ``f`` at the root of each
component, picks an invertible solution and propagates it along the spanning tree.

Matrices of ``Hom(E, F)`` are flattened row-major (``vec(f)[a K_E + b] = f[a, b]``); then
``vec(θ f η⁻¹) = (θ ⊗ η⁻ᵀ) vec(f)``, which is the transport of ``F ⊗ E*``.

Examples
--------
>>> import numpy as np
>>> from dhlb import SimplicialComplex
>>> from dhlb.bundles import VectorBundle, find_isomorphism
>>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
>>> E = VectorBundle(X, [[[2.0]], [[1.0]], [[1.0]]])
>>> F = E.gauge(np.array([1.0, 3.0, -1.0]))
>>> f = find_isomorphism(E, F)
>>> is_morphism(E, F, f), find_isomorphism(E, VectorBundle.trivial(X, 1)) is None
(True, True)
>>> E.tensor(E.dual()).is_trivial()
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.bundles.vector_bundle import VectorBundle, _check_pair, _kron
from dhlb.errors import ConvergenceError, InvalidConnectionError

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = [
    "gauge",
    "direct_sum",
    "tensor",
    "dual",
    "hom",
    "is_morphism",
    "find_isomorphism",
    "is_isomorphic",
]



def gauge(E: VectorBundle, g: ArrayLike) -> VectorBundle:
    """The gauge-transformed bundle ``η'_ij = g_j η_ij g_i⁻¹``; ``g`` is an isomorphism E → E'.

    ``g`` has shape (n_0, K, K) (or (n_0,) for rank 1).  The result keeps ``metric=True``
    only if every ``g_i`` is orthogonal / unitary.

    Parameters
    ----------
    E : VectorBundle
        A bundle of rank K over ``X``.
    g : (n_0, K, K) array_like, or (n_0,) for K = 1
        One invertible matrix per vertex, in the field of ``E``.

    Returns
    -------
    VectorBundle
        The bundle E' over the same complex and field, transports ``g_j η_ij g_i⁻¹``.

    Raises
    ------
    InvalidConnectionError
        if some ``g_i`` is singular (names the vertex), or ``g`` has the wrong shape or
        non-numeric (or, for a real bundle, complex) entries.
    NonFiniteError
        ``g`` contains NaN or infinity.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])             # edges (0,1), (0,2), (1,2)
    >>> gauge(VectorBundle.trivial(X, 1), np.array([1.0, 2.0, 4.0])).transports.ravel().tolist()
    [2.0, 4.0, 2.0]
    """
    return E.gauge(g)


def direct_sum(E: VectorBundle, F: VectorBundle) -> VectorBundle:
    """``E ⊕ F`` with the block-diagonal connection ``η ⊕ θ``.

    Parameters
    ----------
    E : VectorBundle
        A bundle of rank ``K_E`` over ``X``.
    F : VectorBundle
        A bundle of rank ``K_F`` over the same complex and field.

    Returns
    -------
    VectorBundle
        The bundle of rank ``K_E + K_F``; ``metric`` when both are metric.

    Raises
    ------
    InvalidConnectionError
        ``E`` and ``F`` are not both :class:`VectorBundle` objects, or live over different
        complexes or fields.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> S = direct_sum(VectorBundle(X, [2.0, 1.0, 1.0]), VectorBundle.trivial(X, 2))
    >>> S.rank, S.monodromy([0, 1, 2, 0]).diagonal().tolist()
    (3, [2.0, 1.0, 1.0])
    """
    return E.direct_sum(F)


def tensor(E: VectorBundle, F: VectorBundle) -> VectorBundle:
    """``E ⊗ F`` with ``(η ⊗ θ)_ij = η_ij ⊗ θ_ij`` (Kronecker product, row-major).

    Parameters
    ----------
    E : VectorBundle
        A bundle of rank ``K_E`` over ``X``.
    F : VectorBundle
        A bundle of rank ``K_F`` over the same complex and field.

    Returns
    -------
    VectorBundle
        The bundle of rank ``K_E K_F``; ``metric`` when both are metric.

    Raises
    ------
    InvalidConnectionError
        ``E`` and ``F`` are not both :class:`VectorBundle` objects, or live over different
        complexes or fields.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> E = VectorBundle(X, [2.0, 1.0, 1.0])
    >>> tensor(E, E).transports.ravel().tolist(), tensor(E, VectorBundle.trivial(X, 3)).rank
    ([4.0, 1.0, 1.0], 3)
    """
    return E.tensor(F)


def dual(E: VectorBundle) -> VectorBundle:
    """``E*`` with the contragredient connection ``(η_ij⁻¹)ᵀ`` (complex-linear dual).

    Parameters
    ----------
    E : VectorBundle
        A bundle of rank K.

    Returns
    -------
    VectorBundle
        The dual bundle, of rank K over the same complex and field.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> dual(VectorBundle(X, [2.0, 1.0, 1.0])).transports.ravel().tolist()
    [0.5, 1.0, 1.0]
    """
    return E.dual()


def hom(E: VectorBundle, F: VectorBundle) -> VectorBundle:
    """``Hom(E, F) = F ⊗ E*``; its parallel sections, reshaped to (K_F, K_E), are the morphisms.

    Parameters
    ----------
    E : VectorBundle
        The source, of rank ``K_E``.
    F : VectorBundle
        The target, of rank ``K_F``, over the same complex and field.

    Returns
    -------
    VectorBundle
        The bundle of rank ``K_F K_E``; fibres are the (K_F, K_E) matrices flattened row-major.

    Raises
    ------
    InvalidConnectionError
        ``E`` and ``F`` are not both :class:`VectorBundle` objects, or live over different
        complexes or fields.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> E = VectorBundle(X, [2.0, 1.0, 1.0])
    >>> hom(E, E).is_trivial(), hom(E, VectorBundle.trivial(X, 1)).is_trivial()
    (True, False)
    """
    return tensor(F, dual(E))


def is_morphism(E: VectorBundle, F: VectorBundle, f: ArrayLike) -> bool:
    """True if ``f`` (shape (n_0, K_F, K_E)) makes every edge diagram commute: ``f_j η_ij = θ_ij f_i``.

    Parameters
    ----------
    E : VectorBundle
        The source, transports ``η``, rank ``K_E``.
    F : VectorBundle
        The target, transports ``θ``, rank ``K_F``, over the same complex and field.
    f : (n_0, K_F, K_E) array_like
        One linear map per vertex.

    Returns
    -------
    bool
        Whether ``f_j η_ij = θ_ij f_i`` on every edge (within the tolerance of the field; exactly
        over GF(p)). ``f`` need not be invertible.

    Raises
    ------
    InvalidConnectionError
        The bundles are not both :class:`VectorBundle` objects or differ in complex or field;
        ``f`` has the wrong shape or non-numeric entries.
    NonFiniteError
        ``f`` contains NaN or infinity.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> E, I = VectorBundle(X, [2.0, 1.0, 1.0]), VectorBundle.trivial(X, 1)
    >>> is_morphism(E, E, np.full((3, 1, 1), 5.0)), is_morphism(E, I, np.ones((3, 1, 1)))
    (True, False)
    """
    _check_pair(E, F)
    ops = E.ops
    f = ops.asarray(np.asarray(f), "the morphism")
    if f.shape != (E.X.n_vertices, F.rank, E.rank):
        raise InvalidConnectionError(
            f"a morphism has shape (n_0, K_F, K_E) = {(E.X.n_vertices, F.rank, E.rank)}, got {f.shape}"
        )
    Ed = E.X.simplices(1)
    lhs = ops.matmul(f[Ed[:, 1]], E.transports)
    rhs = ops.matmul(F.transports, f[Ed[:, 0]])
    return bool(np.all(ops.close(lhs, rhs)))


def _invertible_in_span(ops, N: np.ndarray, K: int, rng, max_enumeration: int):
    """An invertible K×K matrix in the column span of N (columns = vec(f)), or None."""
    d = N.shape[1]
    if not ops.exact:
        for _ in range(12):
            f = (N @ ops.random(d, rng)).reshape(K, K)
            if ops.is_invertible(f):
                return f
        return None
    p = ops.p
    if p**d <= max_enumeration:
        coeffs = np.indices((p,) * d).reshape(d, -1).T.astype(np.int64)
        cand = (coeffs @ N.T % p).reshape(-1, K, K)
        _, singular = ops.inv(cand)
        ok = np.nonzero(~singular)[0]
        return cand[ok[0]] if ok.size else None
    for _ in range(200):
        f = (N @ ops.random(d, rng) % p).reshape(K, K)
        if ops.is_invertible(f):
            return f
    if p > K:
        # Schwartz–Zippel: if an invertible solution exists, each trial fails with
        # probability <= K/p, so 200 failures happen with probability <= (K/p)^200.
        return None
    raise ConvergenceError(
        f"could not decide isomorphism over GF({p}): the intertwiner space has dimension {d} "
        f"(p^d > {max_enumeration} is too large to enumerate) and p <= rank; raise max_enumeration"
    )


def find_isomorphism(
    E: VectorBundle, F: VectorBundle, *, rng: np.random.Generator | int | None = None, max_enumeration: int = 2**16
) -> np.ndarray | None:
    """An isomorphism ``f: E → F`` (array (n_0, K, K), ``f_j η_ij = θ_ij f_i``) or ``None``.

    Per component: solve ``M^F_g f = f M^E_g`` for all loop generators g (a linear system in
    ``vec f``), take an invertible element of the solution space (random combination over R/C;
    exhaustive enumeration over GF(p) when ``p^dim <= max_enumeration``, random search with
    a Schwartz–Zippel bound otherwise) and propagate along the spanning tree
    (``f_v = T^F_v f T^E_v⁻¹``).  The result is verified on every edge.

    Parameters
    ----------
    E : VectorBundle
        The source, rank K.
    F : VectorBundle
        The target, rank K, over the same complex and field.
    rng : numpy.random.Generator or int, optional
        Randomness of the search for an invertible intertwiner (default: a generator seeded 0,
        so the result is reproducible).
    max_enumeration : int, default 2**16
        Over GF(p): enumerate the intertwiner space when it has at most this many elements.

    Returns
    -------
    (n_0, K, K) array or None
        An isomorphism ``f`` in the field's dtype, or ``None`` when E and F are not isomorphic.

    Raises
    ------
    InvalidConnectionError
        if the bundles have different complexes, fields or ranks.
    ConvergenceError
        Floating point: the monodromy or tree transport matrices are too ill-conditioned
        (condition number > 1e8) to trust a negative answer. GF(p) with ``p <= K``: the random
        search failed and the intertwiner space is too large to enumerate.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> E = VectorBundle(X, [2.0, 1.0, 1.0])                        # monodromy 2 around the circle
    >>> F = E.gauge(np.array([1.0, 3.0, -1.0]))
    >>> f = find_isomorphism(E, F)
    >>> f.shape, is_morphism(E, F, f), find_isomorphism(E, E.dual()) is None
    ((3, 1, 1), True, True)
    """
    _check_pair(E, F, same_rank=True)
    ops = E.ops
    K = E.rank
    rng = np.random.default_rng(0) if rng is None else rng
    T = E.forest
    ME, MF = E.monodromy_representation(), F.monodromy_representation()
    comp_g = E._component_generators()
    I = ops.eye(K)
    roots = []
    for c in range(T.n_components):
        sel = comp_g == c
        if not np.any(sel):
            roots.append(I)
            continue
        A = (
            _kron(MF[sel], np.broadcast_to(I, MF[sel].shape))
            - _kron(np.broadcast_to(I, ME[sel].shape), np.swapaxes(ME[sel], 1, 2))
        ).reshape(-1, K * K)
        if ops.exact:
            A = A % ops.p
        N = ops.nullspace(A)
        if N.shape[1] == 0:
            return _no_isomorphism(ops, ME, MF, E, F)
        f = _invertible_in_span(ops, N, K, rng, max_enumeration)
        if f is None:
            return _no_isomorphism(ops, ME, MF, E, F)
        roots.append(f)
    roots = np.stack(roots).astype(ops.dtype)
    TEinv, _ = ops.inv(E.tree_transports)
    f = ops.matmul(F.tree_transports, ops.matmul(roots[T.component], TEinv))
    return f if is_morphism(E, F, f) else _no_isomorphism(ops, ME, MF, E, F)


_MAX_CONDITION = 1e8  # beyond this, floating-point monodromies cannot decide conjugacy


def _no_isomorphism(ops, ME, MF, E: VectorBundle, F: VectorBundle):
    """``None``, unless floating-point conditioning makes that answer untrustworthy (then raise)."""
    if ops.exact:
        return None
    mats = [m for m in (ME, MF, E.tree_transports, F.tree_transports) if m.size]
    cond = max((float(np.max(np.linalg.cond(m))) for m in mats), default=1.0)
    if not np.isfinite(cond) or cond > _MAX_CONDITION:
        raise ConvergenceError(
            f"cannot decide isomorphism in floating point: monodromy/transport matrices have condition "
            f"number {cond:.3g} > {_MAX_CONDITION:.0e}; use unitary/orthogonal transports (metric=True), "
            f"exact arithmetic over GF(p), or a smaller complex"
        )
    return None


def is_isomorphic(E: VectorBundle, F: VectorBundle, **kwargs: Any) -> bool:
    """True if :func:`find_isomorphism` finds an isomorphism.

    Parameters
    ----------
    E : VectorBundle
        The source, rank K.
    F : VectorBundle
        The target, over the same complex and field.
    **kwargs
        ``rng``, ``max_enumeration`` of :func:`find_isomorphism`.

    Returns
    -------
    bool
        Whether E ≅ F.

    Raises
    ------
    InvalidConnectionError
        The bundles differ in complex, field or rank.
    ConvergenceError
        As in :func:`find_isomorphism`: the answer cannot be decided reliably.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> E = VectorBundle(X, [-1.0, 1.0, 1.0])                       # monodromy -1: a Möbius band
    >>> is_isomorphic(E, E.gauge(np.array([1.0, 3.0, -1.0]))), is_isomorphic(E, VectorBundle.trivial(X, 1))
    (True, False)
    """
    return find_isomorphism(E, F, **kwargs) is not None
