"""Isolines ``α ≡ c (mod 2π)`` of a stripe pattern as polylines, by marching triangles.

The pattern is cut into sub-triangles on which α is linear (:meth:`StripeTexture.subdivision`):
plain faces as they are and the three cones of each branch triangle (both exact), and a fine
grid in the cones of each zero face (the barycenter blown up, so isolines run into the zero).
In each sub-triangle the level sets of the linear α at ``c + 2πk`` (every k in its range) are
segments; for line fields (``n = 2``) α is defined up to sign and the levels are ``±c + 2πk``
(the level set of ``cos α = cos c``). Crossing points of neighbouring sub-triangles are merged
(within ``tol``) and the segments are chained into polylines without a loop over segments:
every undirected segment gives two half-edges, the successor of ``u → v`` is the other
half-edge leaving v, and chains are ranked by pointer jumping. Polylines end at the zeros
(where ``|n|`` isolines of each level end, ``2|n|`` for line fields) and at the boundary; points
where more than two segments meet split into separate ends. On a closed surface every open
polyline ends at zeros; branch points are passed (the isolines turn around them).

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import validate_surface
>>> from dhlb.stripes import stripe_form, texture_coordinates, isolines
>>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
>>> form = stripe_form(validate_surface(V, [[0, 1, 2], [1, 3, 2]]), np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
>>> iso = isolines(texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0])), level=np.pi / 4)
>>> len(iso.polylines), iso.points[iso.polylines[0]][:, 0].round(12).tolist()   # the line x = 1/2
(1, [0.5, 0.5, 0.5])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from dhlb._coerce import check_int, check_real
from dhlb.errors import InvalidParameterError, NonFiniteError, ResourceLimitError, format_bytes

if TYPE_CHECKING:
    from dhlb.stripes.texture import StripeTexture

__all__ = ["MAX_BYTES", "Isolines", "isoline_cost", "isolines"]

MAX_BYTES = 1_000_000_000
"""Default memory budget of :func:`isolines` (bytes); larger work is refused before it starts."""
BYTES_PER_SUBTRIANGLE = 320
"""Measured peak bytes per sub-triangle of the subdivision (bary, α, corners, marching temporaries)."""
BYTES_PER_SEGMENT = 480
"""Measured peak bytes per isoline segment (two crossing points, merging, chaining)."""

TWO_PI = 2.0 * np.pi
_SIDES = np.array([[0, 1], [1, 2], [2, 0]])


@dataclass(frozen=True)
class Isolines:
    """Polylines of ``α ≡ level`` (``≡ ±level`` for n = 2).

    Made by :func:`isolines`; every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    level : float
        The level ``c`` actually used, reduced to ``[−π, π)``; for n = 2 its absolute value in
        ``[0, π]`` (snapped to 0 or π when within 1e-6 of them).
    points : (P, 3) float array
        Positions of the isoline points.
    faces : (P,) int array
        A face of ``mesh.faces`` containing each point.
    bary : (P, 3) float array
        The barycentric coordinates of each point in that face.
    segments : (S, 2) int array
        Segments as rows of ``points``.
    polylines : tuple of int arrays
        Rows of ``points``, in order; a closed one repeats its first point.
    closed : (L,) bool array
        Which polylines are closed.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
    >>> from dhlb.stripes import isolines
    >>> iso = isolines(tex, level=np.pi / 4)              # α = ν x = π/4: the segment x = 1/2
    >>> iso.points.shape, iso.segments.tolist(), iso.closed.tolist()
    ((3, 3), [[0, 2], [1, 2]], [False])
    """

    level: float
    points: np.ndarray
    faces: np.ndarray
    bary: np.ndarray
    segments: np.ndarray
    polylines: tuple
    closed: np.ndarray


def _levels(texture, level):
    c = float(level)
    if not np.isfinite(c):
        raise NonFiniteError(f"level must be finite, got {level!r}")
    if not -np.pi <= c < np.pi:
        c = float(np.mod(c + np.pi, TWO_PI) - np.pi)
    if texture.form.n == 2 and abs(np.sin(c)) < 1e-6:  # ±c would be two nearly coincident curves: snap
        c = 0.0 if abs(c) < 1.0 else -np.pi
    return c, [c] if texture.form.n == 1 or c in (0.0, -np.pi) else [c, -c]


def _n_subtriangles(texture, refine: int) -> int:
    z, b = texture.zero_faces.size, texture.branch_faces.size
    return int(texture.mesh.n_faces - z - b + 3 * b + 6 * refine * refine * z)


def _n_crossings(sub, levels) -> int:
    vmin, vmax = sub.alpha.min(axis=1), sub.alpha.max(axis=1)
    total = 0
    for L0 in levels:
        k_lo = np.floor((vmin - L0) / TWO_PI) + 1
        total += int(np.maximum(np.floor((vmax - L0) / TWO_PI) - k_lo + 1, 0).sum())
    return total


def _refuse(what, texture, estimate, max_bytes, scale, fixed=0.0):
    f = float(np.max(texture.form.frequency))
    if scale != "frequency":
        advice = "allowed: a smaller refine (the zero faces' grid has 6·refine² sub-triangles each) or max_bytes="
    else:
        fits = f * max(max_bytes - fixed, 0.0) / max(estimate - fixed, 1.0)   # the crossings grow linearly with f
        widest = float(np.max(np.abs(texture.form.omega), initial=0.0))      # phase change per edge, ∝ f
        resolved = f * np.pi / widest if widest > np.pi else np.inf            # where it is π on every edge
        if np.isfinite(resolved):   # shown rounded down: following the advice must not alias
            step = 10.0 ** (np.floor(np.log10(resolved)) - 2)
            resolved = float(np.floor(resolved / step) * step)
        if resolved < fits:   # the budget would allow stripes the mesh cannot show: advise what it can
            advice = (f"this mesh resolves stripes up to frequency {resolved:.3g} (the largest phase change per "
                      f"edge is now {widest:.3g} rad; at most π keeps every stripe wider than an edge): ask for at "
                      "most that, or give a spacing (the period in mean edge lengths) of 2 or more")
        else:
            advice = (f"allowed: frequency <= {fits:.3g} stripes per unit length on this mesh (about: the "
                      "crossings grow linearly with it), a coarser pattern (larger spacing), or isolines(..., "
                      "max_bytes=) for a larger budget")
    return ResourceLimitError(what, f"{f:.6g}" if scale == "frequency" else scale, estimate, max_bytes,
                              f"the isolines of this pattern need {format_bytes(estimate)}; {advice}")


def isoline_cost(texture: StripeTexture, level: float = 0.0, *, refine: int = 8) -> dict:
    """Size of the work of :func:`isolines` before doing it: sub-triangles, level crossings, bytes.

    The count of crossings is exact (the number of level values ``c + 2πk`` inside the α range of
    every sub-triangle); the bytes are the measured peak per sub-triangle and per crossing
    (``BYTES_PER_SUBTRIANGLE``, ``BYTES_PER_SEGMENT``). It grows linearly with the stripe frequency.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> from dhlb.stripes.isolines import isoline_cost
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> form = stripe_form(validate_surface(V, [[0, 1, 2], [1, 3, 2]]), np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))
    >>> c = isoline_cost(tex, np.pi / 8)           # α = π x / 2 = π/8: the line x = 1/4 crosses both faces
    >>> c["subtriangles"], c["crossings"]
    (2, 2)
    """
    refine = _check_refine(refine)
    _, levels = _levels(texture, level)
    sub = texture.subdivision(refine)
    T, S = len(sub.face), _n_crossings(sub, levels)
    return {"subtriangles": T, "crossings": S, "bytes": T * BYTES_PER_SUBTRIANGLE + S * BYTES_PER_SEGMENT}


def _check_refine(refine):
    return check_int(refine, "refine", 1, 64)


def _march(sub, levels, corners):
    """Crossing points (face, bary) of each level segment: arrays for the first and the second end.

    ``corners`` (T, 3, 3) are the positions of the sub-triangle corners; each crossed side is
    interpolated from its lexicographically smaller end, so that both faces of a mesh edge
    compute the same point up to the rounding of the values.
    """
    ends = [[], []]
    for L0 in levels:
        vmin, vmax = sub.alpha.min(axis=1), sub.alpha.max(axis=1)
        k_lo = np.floor((vmin - L0) / TWO_PI).astype(np.int64) + 1
        cnt = np.maximum(np.floor((vmax - L0) / TWO_PI).astype(np.int64) - k_lo + 1, 0)
        tri = np.repeat(np.arange(len(cnt)), cnt)
        k = k_lo[tri] + np.arange(tri.size) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        L = L0 + TWO_PI * k
        v = sub.alpha[tri]
        above = v >= L[:, None]
        cross = above[:, _SIDES[:, 0]] != above[:, _SIDES[:, 1]]
        ok = cross.sum(axis=1) == 2
        tri, L, v, cross = tri[ok], L[ok], v[ok], cross[ok]
        which = np.argsort(~cross, axis=1, kind="stable")[:, :2]
        r = np.arange(tri.size)[:, None]
        a, b = _SIDES[which, 0], _SIDES[which, 1]
        C = corners[tri]
        d = C[r, b] - C[r, a]
        nz = d != 0
        first = np.take_along_axis(d, np.argmax(nz, axis=2)[..., None], axis=2)[..., 0]
        swap = first < 0
        a, b = np.where(swap, b, a), np.where(swap, a, b)
        va, vb = v[r, a], v[r, b]
        t = (L[:, None] - va) / (vb - va)
        B = sub.bary[tri]
        pts = B[r, a] + t[..., None] * (B[r, b] - B[r, a])
        for e in range(2):
            ends[e].append((sub.face[tri], pts[:, e]))
    return [(np.concatenate([x[0] for x in ends[e]]), np.concatenate([x[1] for x in ends[e]])) for e in range(2)]


def _chain(seg: np.ndarray, n_nodes: int, split=None) -> tuple[list, np.ndarray]:
    """Order segments (S, 2) over nodes 0..n_nodes-1 into polylines (node arrays) and closed flags.

    Polylines end at nodes of degree 1, at junctions (degree > 2) and at the nodes marked in ``split``.
    """
    seg = seg[seg[:, 0] != seg[:, 1]]
    seg = np.unique(np.sort(seg, axis=1), axis=0)
    if seg.size == 0:
        return [], np.zeros(0, bool)
    deg = np.bincount(seg.ravel(), minlength=n_nodes)
    orig = np.arange(n_nodes)
    high = deg[seg] > 2  # split junctions: every segment end gets its own node there
    if split is not None:
        high |= np.asarray(split, bool)[seg] & (deg[seg] > 1)
    if np.any(high):
        new = n_nodes + np.arange(int(high.sum()))
        orig = np.concatenate([orig, seg[high]])
        seg = seg.copy()
        seg[high] = new
        n_nodes = orig.size
        deg = np.bincount(seg.ravel(), minlength=n_nodes)
    S = len(seg)
    tail = seg.ravel()  # half-edge 2s: seg[s,0] -> seg[s,1]; 2s+1: reverse
    head = seg[:, ::-1].ravel()
    H = 2 * S
    order = np.argsort(tail, kind="stable")
    start = np.searchsorted(tail[order], np.arange(n_nodes))
    o1 = order[start[head]]
    o2 = order[np.minimum(start[head] + 1, H - 1)]
    rev = np.arange(H) ^ 1
    nxt = np.where(o1 != rev, o1, np.where(deg[head] == 2, o2, -1))
    nxt = np.where(deg[head] == 1, -1, nxt)
    ncomp, comp = connected_components(sp.coo_matrix((np.ones(S), (seg[:, 0], seg[:, 1])), shape=(n_nodes,) * 2),
                                       directed=False)
    used = np.zeros(n_nodes, bool)
    used[seg.ravel()] = True
    open_comp = np.zeros(ncomp, bool)
    open_comp[comp[(deg == 1) & used]] = True
    hcomp = comp[tail]
    cyc_root = np.zeros(H, bool)
    first = np.full(ncomp, H, np.int64)
    np.minimum.at(first, hcomp, np.arange(H))
    c_ids = np.nonzero(~open_comp & (first < H))[0]
    h0 = first[c_ids]  # even: the forward half-edge of the first segment of the cycle
    cyc_root[h0] = True
    prev = np.full(H, -1, np.int64)
    has = nxt >= 0
    prev[nxt[has]] = np.nonzero(has)[0]
    cut = np.concatenate([prev[h0], prev[h0 ^ 1]])
    nxt[cut[cut >= 0]] = -1
    prev = np.full(H, -1, np.int64)
    has = nxt >= 0
    prev[nxt[has]] = np.nonzero(has)[0]
    par = np.where(prev >= 0, prev, np.arange(H))
    dist = (prev >= 0).astype(np.int64)
    while np.any(par[par] != par):  # pointer jumping: root and distance from it
        dist = dist + dist[par]
        par = par[par]
    srt = np.lexsort((dist, par))
    bounds = np.nonzero(np.r_[True, par[srt][1:] != par[srt][:-1]])[0]
    roots = par[srt][bounds]
    lasts = srt[np.r_[bounds[1:], H] - 1]
    keep = cyc_root[roots] | (open_comp[hcomp[roots]] & (tail[roots] < head[lasts]))
    chains = np.split(srt, bounds[1:])
    polylines = [orig[np.r_[tail[ch], head[ch[-1]]]] for ch, k in zip(chains, keep) if k]
    return polylines, cyc_root[roots][keep]


def isolines(texture: StripeTexture, level: float = 0.0, *, refine: int = 8, tol: float | None = None,
             max_bytes: float | None = None) -> Isolines:
    """The isolines ``α ≡ level (mod 2π)`` of a :class:`~dhlb.stripes.StripeTexture` as polylines.

    Parameters
    ----------
    texture : StripeTexture
        The texture coordinates (:func:`~dhlb.stripes.texture_coordinates`).
    level : float, optional
        The value c; for line fields (n = 2) the curves ``α ≡ ±c`` (where ``cos α = cos c``); there a
        level within 1e-6 of 0 or π is snapped to it (``±c`` would be two curves closer than ``tol``).
    refine : int, optional
        Grid size in each cone of a zero face (other faces are exact), between 1 and 64.
    tol : float, optional
        Distance below which crossing points are merged (default ``1e-10 ×`` mean edge length). Isolines
        closer than this (e.g. the two sides of a hairpin at a level within ~tol of a fold) are merged.
    max_bytes : float, optional
        Memory budget (default :data:`MAX_BYTES`, 1 GB). The work (:func:`isoline_cost`) is counted
        before anything large is allocated; above the budget a
        :class:`~dhlb.errors.ResourceLimitError` names the frequency (or ``refine``), the estimate and
        the allowed range.

    Returns
    -------
    Isolines
        The points, segments and polylines of the level set.

    Raises
    ------
    ResourceLimitError
        The stripes are so dense (or ``refine`` so large) that the isolines would exceed ``max_bytes``.
    InvalidParameterError, NonFiniteError
        Bad ``refine``, ``tol``, ``max_bytes`` or ``level``.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
    >>> from dhlb.stripes import isolines
    >>> iso = isolines(tex, level=np.pi / 4)
    >>> len(iso.polylines), iso.points[iso.polylines[0]][:, 0].round(12).tolist()   # the line x = 1/2
    (1, [0.5, 0.5, 0.5])
    """
    refine = _check_refine(refine)
    if tol is not None:
        tol = check_real(tol, "tol", low=0.0)            # before the work, not after it
    c, levels = _levels(texture, level)
    budget = float(MAX_BYTES if max_bytes is None else max_bytes)
    if not budget > 0:
        raise InvalidParameterError(f"max_bytes must be a positive number, got {max_bytes!r}")
    mesh = texture.mesh
    est = _n_subtriangles(texture, refine) * BYTES_PER_SUBTRIANGLE
    if est > budget:
        raise _refuse("refine", texture, est, budget, str(refine))
    sub = texture.subdivision(refine)
    fixed = len(sub.face) * BYTES_PER_SUBTRIANGLE
    est = fixed + _n_crossings(sub, levels) * BYTES_PER_SEGMENT
    if est > budget:
        raise _refuse("frequency", texture, est, budget, "frequency", fixed)
    corners = np.einsum("tcj,tjd->tcd", sub.bary, mesh.points[mesh.faces[sub.face]])
    (f0, b0), (f1, b1) = _march(sub, levels, corners)
    faces = np.concatenate([f0, f1])
    bary = np.concatenate([b0, b1])
    P = np.einsum("pc,pcd->pd", bary, mesh.points[mesh.faces[faces]])
    E = mesh.complex.simplices(1)
    mean_edge = float(np.mean(np.linalg.norm(mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1)))
    tol = 1e-10 * mean_edge if tol is None else tol
    n = len(P)
    if n:
        pairs = cKDTree(P).query_pairs(tol, output_type="ndarray")
        g = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        _, lab = connected_components(g, directed=False)
    else:
        lab = np.zeros(0, np.int64)
    rep, node = np.unique(lab, return_index=True)[1], np.unique(lab, return_inverse=True)[1].ravel()
    S = len(f0)
    seg = np.stack([node[:S], node[S:]], axis=1)
    at_zero = (texture.zero_index[faces[rep]] != 0) & (np.abs(bary[rep] - 1.0 / 3.0).max(axis=1) < 1e-12)
    polylines, closed = _chain(seg, rep.size, split=at_zero)
    seg = np.unique(np.sort(seg[seg[:, 0] != seg[:, 1]], axis=1), axis=0)
    return Isolines(c if texture.form.n == 1 else abs(c), P[rep], faces[rep], bary[rep], seg.astype(np.int64),
                    tuple(np.asarray(p, np.int64) for p in polylines), np.asarray(closed, bool))
