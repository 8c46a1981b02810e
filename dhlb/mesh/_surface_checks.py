"""The checks behind :func:`dhlb.mesh.validate_surface`, each raising a typed error that names the culprit.

Valid meshes take a fast path: duplicate faces are found by one sort of integer face keys, and a
mesh whose directed half-edges are all distinct has at most two faces per edge, consistently
oriented, so only the vertex fans remain to be checked (:func:`dhlb.mesh.halfedge.halfedge_pairs`
finds that with the sort that pairs the half-edges). Only when a fast check finds a problem do the
general checks of :mod:`dhlb.topology.manifold` run, to say exactly what is wrong and where.
"""

from __future__ import annotations

import numpy as np

from dhlb.errors import (
    DegenerateSimplexError,
    EmptyComplexError,
    InconsistentOrientationError,
    InvalidSimplexError,
    InvalidTypeError,
    NonFiniteError,
    NonManifoldError,
    NonOrientableError,
    RaggedInputError,
    ShapeError,
)
from dhlb.geometry.simplex import SimplexStack
from dhlb.mesh.arrays import check_cells, check_row_lengths
from dhlb.topology.complex import SimplicialComplex
from dhlb.topology.manifold import interior_pairs, is_consistently_oriented, manifold_report

__all__ = ["check_faces", "check_geometry", "check_manifold", "length_scale", "orient", "parse"]


def _face(F, r) -> str:
    return f"face {int(r)} (vertices {', '.join(str(int(v)) for v in F[r])})"


def _array(values, name: str) -> np.ndarray:
    """``np.asarray(values)`` with ragged rows and non-numeric entries as typed errors."""
    if name == "F":
        check_row_lengths(values, 3, "face", name="F")
    try:
        arr = np.asarray(values)
    except (ValueError, TypeError):  # numpy >= 1.24: ragged nested sequences (of V; or deeper in F)
        raise RaggedInputError(f"{name} has rows of different lengths; every row of {name} needs "
                               f"{3 if name == 'F' else '2 or 3'} entries") from None
    if arr.dtype == object:
        lengths = {len(r) if hasattr(r, "__len__") else -1 for r in values} if arr.ndim == 1 else set()
        if len(lengths) > 1:
            raise RaggedInputError(f"{name} has rows of different lengths {sorted(lengths)}; every row needs "
                                   f"{3 if name == 'F' else '2 or 3'} entries")
    if np.iscomplexobj(arr):
        raise InvalidTypeError(f"{name} is complex (dtype {arr.dtype}); give real "
                               f"{'indices' if name == 'F' else 'coordinates'} (e.g. {name}.real)")
    if arr.dtype.kind in "USV" and arr.ndim == 2:
        raise InvalidTypeError(f"{name} holds {arr.dtype} values, not numbers; convert it with np.asarray(..., "
                               f"dtype={'int' if name == 'F' else 'float'}) first")
    return arr


def parse(V, F) -> tuple[np.ndarray, np.ndarray]:
    V = _array(V, "V")
    try:
        P = np.asarray(V, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ShapeError("V must be a numeric array of shape (n, 3) (or (n, 2) for a planar mesh)") from None
    if P.ndim != 2 or P.shape[1] not in (2, 3):
        raise ShapeError(f"V must have shape (n, 3) (or (n, 2) for a planar mesh), got {P.shape}")
    if P.shape[1] == 2:
        P = np.column_stack([P, np.zeros(len(P))])
    T = _array(F, "F")
    if T.dtype == object and T.ndim == 2 and all(isinstance(v, (int, np.integer)) for v in T.ravel()):
        big = [int(v) for v in T.ravel() if not -(2**62) < int(v) < 2**62]
        if big:
            raise InvalidSimplexError(f"F refers to vertex {big[0]}, outside V (rows 0 .. {len(P) - 1})")
        T = T.astype(np.int64)
    if T.dtype == object or not (np.issubdtype(T.dtype, np.integer) or np.issubdtype(T.dtype, np.floating)):
        raise InvalidSimplexError(f"F must be an integer array of shape (m, 3), got dtype {T.dtype}")
    if T.ndim != 2 or T.shape[1] != 3:
        raise InvalidSimplexError(f"F must have shape (m, 3) (one triangle per row), got {T.shape}")
    if T.shape[0] == 0:
        raise EmptyComplexError("F has no faces; a surface mesh needs at least one triangle")
    if np.issubdtype(T.dtype, np.floating):
        bad = ~np.isfinite(T).all(axis=1) | np.any(T != np.round(T), axis=1)
        if np.any(bad):
            r = int(np.argmax(bad))
            raise InvalidSimplexError(f"face {r} has non-integer vertex indices {T[r].tolist()}")
        huge = np.any(np.abs(T) >= 2.0**62, axis=1)  # would wrap around in int64
        if np.any(huge):
            r = int(np.argmax(huge))
            raise InvalidSimplexError(f"face {r} (vertices {T[r].tolist()}) refers to a vertex outside V "
                                      f"(rows 0 .. {len(P) - 1})")
    return P, check_cells(T.astype(np.int64), len(P), 3, "face")


def check_faces(P, T) -> None:
    """Refuse faces that repeat a vertex and duplicate faces (in either orientation)."""
    srt = np.sort(T, axis=1)
    rep = np.any(srt[:, 1:] == srt[:, :-1], axis=1)
    if np.any(rep):
        r = int(np.argmax(rep))
        raise DegenerateSimplexError(f"{_face(T, r)} repeats a vertex; remove it (it has zero area)")
    n = max(len(P), 1)
    if n < 2_000_000:  # n³ fits into int64: one sort of integer keys finds duplicates
        key = (srt[:, 0] * n + srt[:, 1]) * n + srt[:, 2]
        sk = np.sort(key)
        if not np.any(sk[1:] == sk[:-1]):
            return
        _, first, inv = np.unique(key, return_index=True, return_inverse=True)
    else:
        _, first, inv = np.unique(srt, axis=0, return_index=True, return_inverse=True)
    dup = np.nonzero(first[inv.ravel()] != np.arange(len(T)))[0]
    if dup.size:
        r2 = int(dup[0])
        r1 = int(first[inv.ravel()[r2]])
        same = SimplicialComplex.orientation_of(T[[r1, r2]])
        how = "with the same orientation" if same[0] == same[1] else "with opposite orientations (a doubled sheet)"
        raise InvalidSimplexError(f"faces {r1} and {r2} are the same triangle {tuple(int(v) for v in srt[r2])} "
                                  f"{how}; remove one of them")


def length_scale(points) -> float:
    """A power of two in ``(h, 2h]``, ``h`` the largest half-extent of the bounding box of ``points`` (1 if flat/empty).

    Dividing coordinates by it is exact (only the exponent changes), so results computed in
    these units convert back without rounding.

    Examples
    --------
    >>> s = length_scale(np.array([[0.0, 0, 0], [3e-150, 0, 0]]))   # half extent 1.5e-150
    >>> bool(1 < s / 1.5e-150 <= 2), float(np.log2(s)).is_integer()
    (True, True)
    >>> length_scale(np.array([[0.0, 0, 0], [1.0, 2, 0]]))
    2.0
    """
    P = np.asarray(points, dtype=np.float64)
    if P.size == 0 or not np.all(np.isfinite(P)):
        return 1.0
    lo, hi = P.min(axis=0), P.max(axis=0)
    half = np.max(hi / 2 - lo / 2)  # no overflow near the largest floats
    if not half > 0 or not np.isfinite(half):
        return 1.0
    _, e = np.frexp(half)
    return float(np.ldexp(1.0, int(e)))


def check_geometry(P, T, rows) -> None:
    used = np.nonzero(np.bincount(T.ravel(), minlength=len(P)))[0]
    bad = ~np.isfinite(P[used]).all(axis=1)
    if np.any(bad):
        v = int(used[np.argmax(bad)])
        raise NonFiniteError(f"vertex {v} has a NaN or infinite coordinate {P[v].tolist()} "
                             f"({int(bad.sum())} used vertices affected); give finite coordinates")
    # the degeneracy test is scale free: work in units of a power of two near the mesh size
    # (exact), so that a mesh in 1e-150 or 1e+150 units does not underflow / overflow
    scale = length_scale(P[used])
    st = SimplexStack.from_points(P[T] / scale)
    deg = np.nonzero(~st.positive_definite)[0]
    if deg.size:
        r = int(deg[0])
        raise DegenerateSimplexError(
            f"{deg.size} face(s) have zero area, first face {int(rows[r])} (vertices "
            f"{', '.join(str(int(v)) for v in T[r])}) with area {st.volumes[r] * scale * scale:.3g}; "
            "remove or repair them (collinear vertices)")


def check_manifold(X, T, rows) -> None:
    _, _, _, counts = interior_pairs(X)
    if np.any(counts > 2):
        e = int(np.argmax(counts > 2))
        a, b = (int(v) for v in X.vertex_labels[X.simplices(1)[e]])
        at = rows[np.isin(T, [a]).any(axis=1) & np.isin(T, [b]).any(axis=1)]
        raise NonManifoldError(f"non-manifold edge ({a}, {b}): it lies in {int(counts[e])} faces "
                               f"(rows {', '.join(str(int(r)) for r in at[:6])}); a surface allows at most 2. "
                               "Split or remove faces there")
    rep = manifold_report(X, limit=1)
    if not rep.is_manifold:
        o = rep.first()
        if o.k == 0:
            v = o.simplex[0]
            raise NonManifoldError(f"non-manifold vertex {v}: its faces form more than one fan (e.g. two "
                                   "surfaces touching at a point); split the vertex")
        raise NonManifoldError(f"not a surface: {o}")


def orient(X, T, rows, reorient: bool) -> np.ndarray:
    """Flip mask making the faces consistently oriented (all False if they already are)."""
    ok, edge = is_consistently_oriented(X, T)
    if ok:
        return np.zeros(len(T), bool)
    try:
        o = X.orientation()
    except NonOrientableError as err:
        at = getattr(err, "simplex", edge)
        raise NonOrientableError(
            f"the surface is not orientable: it contains a Möbius band (carrying an orientation of the faces "
            f"around it comes back reversed, e.g. at edge {at}). Direction fields are sections of the tangent "
            "bundle of an oriented surface; n-direction fields on non-orientable surfaces (a twisted bundle) "
            "are future work") from None
    if not reorient:
        a, b = edge
        at = rows[np.isin(T, [a]).any(axis=1) & np.isin(T, [b]).any(axis=1)]
        raise InconsistentOrientationError(
            f"faces {int(at[0])} and {int(at[1])} traverse their common edge {edge} in the same direction: "
            "the faces are not consistently oriented. Pass reorient=True to flip faces into a consistent "
            "orientation (the majority orientation of each component is kept)")
    tri = X.index(2, T)
    want = o[tri] * SimplicialComplex.orientation_of(T)  # +1 where the face agrees with o
    _, comp = X.connected_components()
    c = comp[np.searchsorted(X.vertex_labels, T[:, 0])]
    votes = np.bincount(c, weights=want, minlength=int(c.max()) + 1)
    sign = np.where(votes >= 0, 1, -1)
    return want * sign[c] < 0
