"""Interactive 3-D views in a browser and in notebooks, with `plotly <https://plotly.com/python/>`_ (``dhlb[web]``).

The view draws the :class:`~dhlb.render.scene.Scene` of a result (:func:`~dhlb.render.scene.scene_of`,
the scene the polyscope viewer draws) as plotly traces, with the camera, the colours and the glyph
sizes of the PNG pictures:

- surfaces shaded, or coloured by a scalar with a colour bar (the distortion of a conformal map);
- vector quantities as glyphs from each vertex: one quantity (n = 1) as arrows, several (n = 2, 4)
  as crosses (arms of 0.45 mean edge lengths along each direction, as in the PNG pictures), at
  most :data:`MAX_GLYPHS` vertices (evenly spread);
- a stripe texture on an unwelded refined copy of the mesh: each sub-triangle on which α is linear
  (:meth:`~dhlb.stripes.StripeTexture.subdivision`: faces, the cones of branch faces, the grid of zero
  faces) is refined until a period has about six samples, and carries ``cos α`` at its own corners,
  so the branch cuts stay sharp;
- points as markers whose hover text names the face and the index; curves as thick lines.

:func:`figure` gives the plotly figure (to restyle, or to show with plotly's own tools);
:func:`to_html` writes a page that opens offline (plotly's script inline, or one shared copy beside
the page, :func:`write_plotlyjs`); :func:`notebook_view` is what ``result.show(backend="web")``
displays in Jupyter (:class:`dhlb.render.registry.WebView`). Meshes above :data:`MAX_FACES` faces
are decimated for the view only (vertex clustering; a stripe texture is then drawn per vertex, its
branch cuts blurred at the scale of the clusters), and the view says so in its title.

Examples
--------
>>> from dhlb.io import example_path, read_surface
>>> from dhlb.fields import direction_field
>>> spec = figure_spec(direction_field(*read_surface(example_path("torus.obj")), n=4))
>>> [t["name"] for t in spec["data"]]
['mesh', 'mesh: glyphs', 'singularities']
>>> spec["data"][2]["hovertext"][0]
'face 60, index -1/4'
"""

from __future__ import annotations

import base64
import html
import json
import os
import uuid
from typing import TYPE_CHECKING, Any

import numpy as np

from dhlb._install import install_hint
from dhlb.errors import InvalidParameterError, OutputError
from dhlb.render._figure import (
    GLYPH_COLOR,
    STRIPE_DARK,
    STRIPE_LIGHT,
    Camera,
    _unit,
    face_normals,
    mean_edge_length,
    thin_out,
    up_vector,
)
from dhlb.render.scene import Scene, scene_of

if TYPE_CHECKING:
    from dhlb.render.scene import SceneCurves, SceneMesh, ScenePoints

__all__ = ["MAX_FACES", "MAX_GLYPHS", "WEB_EXTRA", "decimate", "figure", "figure_spec", "notebook_view",
           "plotlyjs_path", "smooth_stripe_surface", "stripe_surface", "to_html", "write_plotlyjs"]

WEB_EXTRA = f"plotly is not installed: {install_hint('plotly', 'web')}"
"""The message of the ``ImportError`` raised when plotly is missing."""
MAX_FACES = 200_000
"""Meshes with more faces are decimated for the web view (the page stays light)."""
MAX_GLYPHS = 3000
"""At most this many vertices carry direction glyphs (an evenly spread subset of a finer mesh, glyphs as far apart)."""
STRIPE_TRIANGLES = 60_000
"""Budget of sub-triangles of the refined copy that carries a stripe texture."""
PLOTLYJS = "plotly.min.js"
"""The file name of the shared copy of plotly's script (:func:`write_plotlyjs`)."""
_DEFAULT_CAMERA = Camera()
ZOOM = 1.8
"""plotly's orthographic zoom (the aspect ratio of a cube around the scene's bounding sphere) that frames it."""
FILL = 0.8
"""The share of the picture's height that the first view fills (the rest: margin, title)."""
SMALL_VIEW = 480
"""Pixels: the height of the view the markers are lifted for (a card of the demo page is about 470 high)."""
MARKER_LIFT = 0.6
"""Markers on a surface are lifted off it by this many marker radii (in a view :data:`SMALL_VIEW` high)."""


# ---------------------------------------------------------------------------- pieces of geometry
def decimate(V, F, max_faces: int = MAX_FACES) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A coarser copy of the triangle mesh (V, F) with at most ``max_faces`` faces (vertex clustering).

    Vertices are merged per cell of a uniform grid (the cell grows until few enough faces remain)
    at the mean of their positions; faces that collapse are dropped, duplicates kept once. For
    drawing only: the topology may change at the scale of a cell.

    Parameters
    ----------
    V : (N, 3) float array
    F : (m, 3) int array
    max_faces : int

    Returns
    -------
    points : (N', 3) float array
    faces : (m', 3) int array
        ``m' <= max_faces``.
    kept : (m',) int array
        The row of F each face comes from (to carry face quantities over).

    Examples
    --------
    >>> from dhlb.io import example_path, read_surface
    >>> V, F = read_surface(example_path("spot.obj"))
    >>> P, T, kept = decimate(V, F, 1000)
    >>> len(T) <= 1000 < len(F), bool(np.array_equal(T.max() + 1, len(P)) or T.max() < len(P))
    (True, True)
    """
    P, T = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    if len(T) <= max_faces:
        return P, T, np.arange(len(T))
    lo, span = P.min(axis=0), max(float(np.ptp(P, axis=0).max()), 1e-300)
    cells = max(2, int(np.sqrt(max_faces / 2.0)))                  # about 2 cells² faces on a surface
    while True:
        key = np.floor((P - lo) / span * cells).astype(np.int64)
        _, cluster = np.unique(key[:, 0] * (cells + 1) ** 2 + key[:, 1] * (cells + 1) + key[:, 2],
                               return_inverse=True)
        C = cluster.reshape(-1)[T]
        alive = (C[:, 0] != C[:, 1]) & (C[:, 1] != C[:, 2]) & (C[:, 2] != C[:, 0])
        _, first = np.unique(np.sort(C[alive], axis=1), axis=0, return_index=True)
        kept = np.nonzero(alive)[0][np.sort(first)]
        if len(kept) <= max_faces or cells <= 2:
            break
        cells = int(cells * 0.85)
    cluster = cluster.reshape(-1)
    counts = np.bincount(cluster)
    Q = np.stack([np.bincount(cluster, P[:, d]) for d in range(3)], axis=1) / counts[:, None]
    return Q, cluster[T[kept]], kept


def stripe_surface(texture, max_triangles: int = STRIPE_TRIANGLES, samples: float = 6.0):
    """The unwelded refined copy of a stripe texture's mesh that the web view colours by ``cos α``.

    Every sub-triangle of :meth:`~dhlb.stripes.StripeTexture.subdivision` (on which α is linear) is
    split k × k, k chosen per sub-triangle for about ``samples`` nodes per period of α (fewer when
    the total would exceed ``max_triangles``); α at the nodes interpolates the sub-triangle's own
    corner values, so no value is shared across a face, a cone or a branch cut.

    Parameters
    ----------
    texture : StripeTexture
    max_triangles : int
        Budget of triangles (the copy has at least one per sub-triangle).
    samples : float
        Nodes per period of α along the steepest direction.

    Returns
    -------
    points : (K, 3) float array
    faces : (T, 3) int array
    alpha : (K,) float array
        α at the nodes.
    face : (K,) int array
        The face of ``texture.mesh.faces`` each node lies in.
    bary : (K, 3) float array
        Its barycentric coordinates in that face.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.0]])
    >>> form = stripe_form(validate_surface(V, [[0, 1, 2], [1, 3, 2]]), np.tile([1.0, 0, 0], (4, 1)),
    ...                    frequency=2, warn_aliasing=False)
    >>> tex = texture_coordinates(form, np.exp(4j * np.pi * V[:, 0]))
    >>> P, T, alpha, face, bary = stripe_surface(tex)
    >>> corner = np.isclose(bary, 1).any(axis=1)                      # nodes at a corner of their face
    >>> c = np.argmax(bary[corner], axis=1)
    >>> bool(np.allclose(alpha[corner], tex.corner_alpha[face[corner], c]))
    True
    >>> len(stripe_surface(tex)[1]), len(stripe_surface(tex, max_triangles=20)[1])   # within a budget
    (288, 18)
    """
    from dhlb.render.stripes_png import face_grid

    sub = texture.subdivision()
    span = np.ptp(sub.alpha, axis=1)
    k = np.clip(np.ceil(samples * span / (2 * np.pi)), 1, 16).astype(np.int64)
    while int(np.sum(k * k)) > max_triangles and k.max() > 1:   # shrink strictly until within budget or k = 1
        k = np.maximum(1, np.minimum(k - 1, np.ceil(0.8 * k))).astype(np.int64)
    mesh = texture.mesh
    X = mesh.points[mesh.faces[sub.face]]                          # (t, 3, 3) corners of each face
    parts, base = [], 0
    for kk in np.unique(k):
        rows = np.nonzero(k == kk)[0]
        nodes, tris = face_grid(int(kk))                          # (G, 3) weights of the sub-triangle's corners
        b = np.einsum("gc,tcd->tgd", nodes, sub.bary[rows])       # barycentric in the face, (r, G, 3)
        a = np.einsum("gc,tc->tg", nodes, sub.alpha[rows])        # α: linear on the sub-triangle
        p = np.einsum("tgc,tcd->tgd", b, X[rows])
        G = len(nodes)
        f = (base + G * np.arange(len(rows)))[:, None, None] + tris[None]
        parts.append((p.reshape(-1, 3), f.reshape(-1, 3), a.reshape(-1), np.repeat(sub.face[rows], G),
                      b.reshape(-1, 3)))
        base += G * len(rows)
    return tuple(np.concatenate([q[i] for q in parts]) for i in range(5))


PHONG = 0.75
"""The shape factor of the Phong tessellation that curves the refined copy of a stripe texture's mesh."""


def _phong(X, N, b):
    """Phong tessellation (Boubekeur & Alexa 2008): the point of barycentric ``b`` on the curved triangle X, N.

    ``X``, ``N``: (k, 3, 3) corners and their unit vertex normals; ``b``: (k, 3). The flat point is
    pulled toward its projections on the three corners' tangent planes (weights ``b``, factor :data:`PHONG`).
    """
    q = np.einsum("kc,kcd->kd", b, X)
    off = np.einsum("kcd,kcd->kc", q[:, None, :] - X, N)
    return q - PHONG * np.einsum("kc,kc,kcd->kd", b, off, N)


def smooth_stripe_surface(mesh, faces, alpha, face, bary) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions and welded triangles for the refined copy of :func:`stripe_surface`, so that it shades smoothly.

    The copy is refined on flat faces and not welded, so a browser computing vertex normals from its
    triangles would shade each face of the mesh flat: every face of the input shows. Here each node
    is moved onto the Phong tessellation of the mesh (:func:`_phong`, with the mesh's vertex normals;
    a node on an edge of the mesh onto the polyline of the coarser of the edge's two faces, so that
    neither side opens a crack), and the triangles are re-pointed at one node per position and
    value of ``cos α`` (nodes across a branch cut stay apart). The arrays of nodes keep their length
    and order (``alpha`` still applies to them).

    Parameters
    ----------
    mesh : SurfaceMesh
        ``texture.mesh``.
    faces : (T, 3) int array
        The triangles of :func:`stripe_surface`.
    alpha, face, bary : (K,), (K,), (K, 3) arrays
        α, the face and the barycentric coordinates of each node (:func:`stripe_surface`).

    Returns
    -------
    points : (K, 3) float array
    faces : (T, 3) int array
        Rows of ``points``: nodes at the same place with the same ``cos α`` are one.
    rise : (K,) float array
        How far each node stands above its flat face (along the face's normal; negative: below).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.0]])
    >>> form = stripe_form(validate_surface(V, [[0, 1, 2], [1, 3, 2]]), np.tile([1.0, 0, 0], (4, 1)),
    ...                    frequency=2, warn_aliasing=False)
    >>> tex = texture_coordinates(form, np.exp(4j * np.pi * V[:, 0]))
    >>> X, T, alpha, face, bary = stripe_surface(tex)
    >>> Y, W, rise = smooth_stripe_surface(tex.mesh, T, alpha, face, bary)
    >>> len(np.unique(W)) < len(np.unique(T)), float(np.abs(rise).max())   # welded; a flat mesh stays flat
    (True, 0.0)
    """
    P, F = np.asarray(mesh.points, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)
    N = _vertex_normals(P, F)
    corners = F[face]
    b = np.asarray(bary, dtype=np.float64)
    X = _phong(P[corners], N[corners], b)
    zero = b <= 1e-12
    nz = zero.sum(axis=1)
    at = np.nonzero(nz == 2)[0]                                     # corners of the mesh: its vertices
    X[at] = P[corners[at, np.argmax(b[at], axis=1)]]
    on = np.nonzero(nz == 1)[0]                                     # on an edge of the mesh
    if on.size:
        z = np.argmax(zero[on], axis=1)
        i, j = (z + 1) % 3, (z + 2) % 3
        va, vb = corners[on, i], corners[on, j]
        ta = b[on, j] / (b[on, i] + b[on, j])                        # from va toward vb
        swap = va > vb
        lo, hi = np.where(swap, vb, va), np.where(swap, va, vb)
        one = np.int64(1) << 30
        tq = np.rint(np.where(swap, 1 - ta, ta) * one).astype(np.int64)   # from lo toward hi
        edges, eid = np.unique(np.stack([lo, hi], axis=1), axis=0, return_inverse=True)
        eid = eid.reshape(-1)
        # each edge's coarser side: of the faces at it, the one with the fewest nodes inside it (perhaps none);
        # its nodes and both ends are the polyline both sides follow
        rows = np.unique(np.stack([eid, face[on], tq], axis=1), axis=0)
        pair, count = np.unique(rows[:, :2], axis=0, return_counts=True)
        nv, nf = len(P), len(F)
        side = np.sort(F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)          # every face's edges
        side_key, side_face = side[:, 0] * nv + side[:, 1], np.repeat(np.arange(nf), 3)
        near = np.isin(side_key, edges[:, 0] * nv + edges[:, 1])
        adj = np.stack([np.searchsorted(edges[:, 0] * nv + edges[:, 1], side_key[near]), side_face[near]], 1)
        found = np.searchsorted(pair[:, 0] * nf + pair[:, 1], adj[:, 0] * nf + adj[:, 1])
        found = np.minimum(found, len(pair) - 1)
        hit = pair[found, 0] * nf + pair[found, 1] == adj[:, 0] * nf + adj[:, 1]
        n_inside = np.where(hit, count[found], 0)
        best = np.lexsort((n_inside, adj[:, 0]))
        first = best[np.r_[True, adj[best][1:, 0] != adj[best][:-1, 0]]]
        chosen = adj[first]                                         # (edge, face) of the coarser side
        keep = np.isin(rows[:, 0] * nf + rows[:, 1], chosen[:, 0] * nf + chosen[:, 1])
        ids = np.arange(len(edges))
        cnode = np.concatenate([rows[keep][:, [0, 2]], np.stack([ids, np.zeros_like(ids)], 1),
                                np.stack([ids, np.full_like(ids, one)], 1)])
        cnode = np.unique(cnode, axis=0)                            # sorted by edge, then t
        t = cnode[:, 1] / one
        e = edges[cnode[:, 0]]
        w = np.stack([1 - t, t], axis=1)
        at_nodes = _phong(P[e][:, [0, 1, 1]], N[e][:, [0, 1, 1]], np.c_[w, np.zeros(len(t))])
        ckey = cnode[:, 0] * (one + 1) + cnode[:, 1]
        key = eid * (one + 1) + tq
        left = np.searchsorted(ckey, key, side="right") - 1
        right = np.minimum(left + 1, len(ckey) - 1)
        span = np.maximum(cnode[right, 1] - cnode[left, 1], 1)
        u = ((tq - cnode[left, 1]) / span)[:, None]
        X[on] = (1 - u) * at_nodes[left] + u * at_nodes[right]
    flat = np.einsum("kc,kcd->kd", b, P[corners])
    fn = _unit(face_normals(P, F))
    rise = np.einsum("kd,kd->k", X - flat, fn[face])
    scale = max(float(np.ptp(P, axis=0).max()), 1e-300) / 2.0 ** 30
    key = np.column_stack([np.rint(X / scale), np.rint(np.cos(alpha) * 2.0 ** 20)]).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return X, first[inverse.reshape(-1)][np.asarray(faces, dtype=np.int64)], rise


class _Rise:
    """How far the drawn surfaces stand above the mesh near given points (0 where a mesh is drawn flat)."""

    def __init__(self):
        self.nodes, self.rise = [], []

    def add(self, flat, rise) -> None:
        self.nodes.append(np.asarray(flat, dtype=np.float64))
        self.rise.append(np.asarray(rise, dtype=np.float64))

    def at(self, X) -> np.ndarray:
        """The largest rise of the 8 nearest nodes of a curved copy (0 if none rises), per row of X."""
        X = np.asarray(X, dtype=np.float64).reshape(-1, 3)
        if not self.nodes or not len(X):
            return np.zeros(len(X))
        from scipy.spatial import cKDTree

        nodes, rise = np.concatenate(self.nodes), np.concatenate(self.rise)
        _, near = cKDTree(nodes).query(X, k=min(8, len(nodes)))
        return np.maximum(rise[np.asarray(near).reshape(len(X), -1)].max(axis=1), 0.0)


def _vertex_normals(P, T):
    n = face_normals(P, T)
    vn = np.zeros_like(P)
    for c in range(3):
        np.add.at(vn, T[:, c], n)
    return vn / np.maximum(np.linalg.norm(vn, axis=1, keepdims=True), 1e-300)


def _gaps(pieces) -> np.ndarray:
    """Polylines ``[(k_i, 3), ...]`` as one array with a NaN row after each (a line trace's gaps)."""
    if not pieces:
        return np.zeros((0, 3))
    gap = np.full((1, 3), np.nan)
    return np.concatenate([x for p in pieces for x in (p, gap)])


# ---------------------------------------------------------------------------- traces
def _rgb(c) -> str:
    r, g, b = (round(255 * float(x)) for x in c[:3])
    return f"rgb({r},{g},{b})"


def _colorscale(name: str, samples: int = 11) -> list:
    from matplotlib import colormaps

    cmap = colormaps[name]
    return [[t, _rgb(cmap(t))] for t in np.linspace(0.0, 1.0, samples).tolist()]


def _xyz(X) -> dict:
    X = np.asarray(X, dtype=np.float32)
    return {"x": X[:, 0], "y": X[:, 1], "z": X[:, 2]}


_LIGHTING = {"ambient": 0.45, "diffuse": 0.7, "specular": 0.05, "roughness": 0.9, "fresnel": 0.05}
_UNLIT = {"ambient": 0.8, "diffuse": 0.0, "specular": 0.0, "roughness": 1.0, "fresnel": 0.0}
_STRIPES = {"cmin": -1.0, "cmax": 1.0, "colorscale": [[0.0, _rgb(STRIPE_DARK)], [1.0, _rgb(STRIPE_LIGHT)]],
            "showscale": False}


def _mesh3d(name: str, X, S, **style) -> dict:
    return {"type": "mesh3d", "name": name, **_xyz(X), "i": S[:, 0].astype(np.int32), "j": S[:, 1].astype(np.int32),
            "k": S[:, 2].astype(np.int32), "lighting": _LIGHTING, "hoverinfo": "skip", **style}


def _mesh_traces(m: SceneMesh, max_faces: int, max_glyphs: int, colorbar: bool, notes: list,
                 rises: _Rise | None = None) -> list:
    P, T = m.points, m.faces
    if m.texture is not None and len(T) <= max_faces:
        flat, S, alpha, face, bary = stripe_surface(m.texture)
        X, S, rise = smooth_stripe_surface(m.texture.mesh, S, alpha, face, bary)
        if rises is not None:
            rises.add(flat, rise)
        return [_mesh3d(m.name, X, S, intensity=np.nan_to_num(np.cos(alpha)).astype(np.float32), **_STRIPES)]
    Q, F, kept = decimate(P, T, max_faces)
    if len(F) < len(T):
        notes.append(f"{m.name}: {len(T):,} faces, decimated to {len(F):,} for this view")

    def at_kept_vertices(values):  # per-vertex values on the decimated mesh: those of a vertex of each cluster
        out = np.zeros(len(Q))
        out[F.reshape(-1)] = np.asarray(values)[T[kept].reshape(-1)]
        return out

    if m.texture is not None:   # too many faces to refine: cos α per corner, averaged at the vertices
        corners = T.reshape(-1)
        mean = (np.bincount(corners, np.cos(m.texture.corner_alpha).reshape(-1), len(P))
                / np.maximum(np.bincount(corners, None, len(P)), 1))
        notes.append("stripes drawn per vertex (branch cuts blurred)")
        return [_mesh3d(m.name, Q, F, intensity=np.nan_to_num(at_kept_vertices(mean)).astype(np.float32),
                        **_STRIPES)]
    # a translucent domain is unlit, one colour on every face: the browser blends overlapping translucent
    # triangles in the order of their rows, and blending two differently lit faces gives another colour in
    # each order, so a box showed saw-teeth along its edges where its top is seen over its back
    trace = _mesh3d(m.name, Q, F, opacity=float(m.transparency), flatshading=m.transparency < 1.0)
    if m.transparency < 1.0:
        trace["lighting"] = _UNLIT
    if m.shown_scalar is None:
        trace["color"] = _rgb(m.color)
    else:
        v = np.asarray(m.scalars[m.shown_scalar])
        per_face = len(v) == len(T) and len(v) != len(P)
        v = v[kept] if per_face else at_kept_vertices(v) if len(F) < len(T) else v
        lo, hi = m.scalar_range if m.scalar_range is not None else (float(np.nanmin(v)), float(np.nanmax(v)))
        trace.update(intensity=v.astype(np.float32), intensitymode="cell" if per_face else "vertex",
                     colorscale=_colorscale(m.colormap), cmin=lo, cmax=hi, showscale=colorbar,
                     colorbar={"title": {"text": m.scalar_label or m.shown_scalar, "side": "top"},
                               "orientation": "h", "len": 0.5, "thickness": 12, "y": 0.02, "yanchor": "bottom"})
    return [trace, _glyphs(m, max_glyphs)] if m.vectors else [trace]


def _glyphs(m: SceneMesh, max_glyphs: int) -> dict:
    """Glyphs of the vector quantities of ``m``: arrows for one quantity, crosses (or stars) for several."""
    P, T = m.points, m.faces
    D = np.stack(list(m.vectors.values()), axis=1)                # (N, n, 3)
    n = D.shape[1]
    verts = np.nonzero(np.any(D != 0, axis=(1, 2)))[0]
    spacing = mean_edge_length(P, T)
    if verts.size > max_glyphs:                                   # an evenly spread subset, glyphs as far apart
        verts, spacing = thin_out(P, verts, 0.5 * spacing, max_glyphs)
    ell = 0.45 * spacing
    normal = _vertex_normals(P, T)[verts]
    base = P[verts] + 0.08 * ell * normal                         # just above the surface
    gap = np.full((len(verts), 1, 3), np.nan)
    if n == 1:                                                    # an arrow: shaft, then a head at the tip
        d = D[verts, 0]
        tip = base + ell * d
        side = np.cross(normal, d)
        h = 0.35 * ell
        parts = [base, tip, gap[:, 0], tip - h * d + 0.45 * h * side, tip, tip - h * d - 0.45 * h * side]
        X = np.concatenate([np.stack(parts, axis=1), gap], axis=1)
    elif n % 2 == 0:                                              # crosses: arms k and k + n/2 through the vertex
        segs = []
        for k in range(n // 2):
            segs += [base + ell * D[verts, k + n // 2], base, base + ell * D[verts, k], gap[:, 0]]
        X = np.stack(segs, axis=1)
    else:                                                         # an odd star: an arm per direction
        X = np.stack([x for k in range(n) for x in (base, base + ell * D[verts, k], gap[:, 0])], axis=1)
    return {"type": "scatter3d", "mode": "lines", "name": f"{m.name}: glyphs", **_xyz(X.reshape(-1, 3)),
            "line": {"color": _rgb(GLYPH_COLOR), "width": 1}, "hoverinfo": "skip"}


def _marker_size(p: ScenePoints) -> float:
    """The diameter of the markers of ``p`` in pixels."""
    return float(np.clip(p.radius * 700, 4, 12))


def _points_trace(p: ScenePoints, pixel: float = 0.0, rises: _Rise | None = None) -> dict:
    """The markers of ``p``; points on a surface (``p.normals``) are lifted off it.

    The lift is how far the drawn surface stands above the mesh there (``rises``) plus
    :data:`MARKER_LIFT` marker radii (``pixel``: world units per pixel in the first view
    :data:`SMALL_VIEW` pixels high), so that no marker is half buried in the surface; on both sides
    of a surface with boundary.
    """
    X, colors, labels = p.points, [_rgb(c) for c in p.colors], p.labels
    if p.normals is not None:
        h = (0.0 if rises is None else rises.at(X)) + MARKER_LIFT * 0.5 * _marker_size(p) * pixel
        X = X + h[:, None] * p.normals
        if p.two_sided:
            X = np.vstack([X, p.points - h[:, None] * p.normals])
            colors = colors + colors
            labels = None if labels is None else list(labels) + list(labels)
    t = {"type": "scatter3d", "mode": "markers", "name": p.name, **_xyz(X),
         "marker": {"size": _marker_size(p), "color": colors, "line": {"width": 0}}}
    if labels is not None:
        t.update(hovertext=list(labels), hoverinfo="text")
    else:
        t["hoverinfo"] = "skip"
    return t


def _curves_trace(c: SceneCurves, pixel: float = 0.0, rises: _Rise | None = None) -> dict:
    """The lines of ``c``; curves on a surface (``c.normals``) are lifted off it: the surface's rise and a pixel."""
    E = c.edges
    nodes = c.nodes
    if c.normals is not None:
        nodes = nodes + ((0.0 if rises is None else rises.at(nodes)) + pixel)[:, None] * c.normals
    if len(E):   # chain consecutive edges (a, b), (b, c), ... into polylines
        breaks = np.nonzero(E[1:, 0] != E[:-1, 1])[0] + 1
        starts, ends = np.r_[0, breaks], np.r_[breaks, len(E)]
        pieces = [nodes[np.r_[E[s:e, 0], E[e - 1, 1]]] for s, e in zip(starts.tolist(), ends.tolist())]
    else:
        pieces = []
    t = {"type": "scatter3d", "mode": "lines", "name": c.name, **_xyz(_gaps(pieces)),
         "line": {"color": _rgb(c.color), "width": float(np.clip(c.radius * 1000, 2, 8))}, "hoverinfo": "skip"}
    if c.label:
        t.update(hovertext=c.label, hoverinfo="text")
    return t


# ---------------------------------------------------------------------------- the figure
def _camera(scene: Scene, camera: Camera | None) -> tuple[dict, dict, float, float]:
    """The plotly scene camera, axis ranges, zoom and pixel size for ``camera`` (fitted as in the PNG pictures).

    The axes span the bounding sphere (radius ``r``) whatever the turn; the zoom frames what the
    first view shows, as the PNG does: :data:`ZOOM` (the sphere) times ``r`` over the larger
    half-extent of the drawn points on the screen (at most 1.6 times closer), times :data:`FILL`.
    The pixel size is the world length of a pixel in the first view :data:`SMALL_VIEW` pixels high.
    """
    X = scene.drawn_points()
    lo, hi = X.min(axis=0), X.max(axis=0)
    c, r = 0.5 * (lo + hi), max(0.5 * float(np.linalg.norm(hi - lo)), 1e-12)
    cam = camera or _DEFAULT_CAMERA
    if cam.view is None and scene.view is not None:        # the direction the scene is arranged for
        cam = cam.replace(view=scene.view)
    cam = cam.fitted(np.vstack([lo, hi]))
    w = np.asarray(cam.view, dtype=np.float64)
    eye = 2.0 * w / np.linalg.norm(w)
    axes = {a: {"range": [float(c[i] - r), float(c[i] + r)], "visible": False} for i, a in enumerate("xyz")}
    up = up_vector(cam.up)
    right, screen_up, _ = cam.frame()
    half = max(float(np.abs((X - c) @ right).max()), float(np.abs((X - c) @ screen_up).max()), 1e-12)
    zoom = ZOOM * min(r / half, 1.6) * FILL
    pixel = max(half, r / 1.6) / (FILL * SMALL_VIEW / 2)
    return ({"eye": dict(zip("xyz", eye.tolist())), "up": dict(zip("xyz", up.tolist())),
             "center": {"x": 0.0, "y": 0.0, "z": 0.0}, "projection": {"type": "orthographic"}}, axes, zoom, pixel)


def figure_spec(result: Any, *, camera: Camera | None = None, isolines: bool = True, title: str | None = None,
                max_faces: int = MAX_FACES, max_glyphs: int = MAX_GLYPHS) -> dict:
    """The plotly figure of a result as a plain dict (``data``, ``layout``) with numpy arrays.

    Parameters
    ----------
    result : a result of the applications, of :func:`dhlb.io.read_result`, or a Scene
        See :func:`~dhlb.render.scene.scene_of`.
    camera : Camera, optional
        Its ``view`` and ``up`` (default: fitted as in the PNG pictures).
    isolines : bool
        Stripe patterns: draw the isolines.
    title : str, optional
        Default: the scene's title (with a note when a mesh was decimated).
    max_faces, max_glyphs : int
        Decimate meshes above ``max_faces`` faces; glyphs on at most ``max_glyphs`` vertices.

    Returns
    -------
    dict
        ``{"data": [...], "layout": {...}}``, as ``plotly.graph_objects.Figure`` takes it.
    """
    for name, v in (("max_faces", max_faces), ("max_glyphs", max_glyphs)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise InvalidParameterError(f"{name} must be a positive integer, got {v!r}")
    scene = scene_of(result, isolines=isolines)
    notes: list[str] = []
    data = []
    rises = _Rise()
    bars = [i for i, m in enumerate(scene.meshes) if m.shown_scalar is not None]
    for i, m in enumerate(scene.meshes):
        data += _mesh_traces(m, int(max_faces), int(max_glyphs), bool(bars) and i == bars[-1], notes, rises)
    cam, axes, zoom, pixel = _camera(scene, camera)
    data += [_curves_trace(c, pixel, rises) for c in scene.curves if len(c.edges)]
    data += [_points_trace(p, pixel, rises) for p in scene.points if len(p.points)]
    plain = scene.title if title is None else title
    text = html.escape(plain) + (f"<br><sub>{html.escape('; '.join(notes))}</sub>" if notes else "")
    layout = {"title": {"text": text, "x": 0.02, "y": 0.98, "font": {"size": 14}},
              "showlegend": False, "paper_bgcolor": "white", "margin": {"l": 0, "r": 0, "t": 36, "b": 0},
              "modebar": {"orientation": "v"},
              "scene": {"camera": cam, "aspectmode": "manual", "aspectratio": dict.fromkeys("xyz", zoom),
                        **{f"{a}axis": v for a, v in axes.items()}, "bgcolor": "white"},
              "hovermode": "closest", "meta": {"dhlb": {"title": plain, "notes": notes}}}
    return {"data": data, "layout": layout}


def _plotly():
    try:
        import plotly
    except ImportError:
        raise ImportError(WEB_EXTRA) from None
    return plotly


def figure(result: Any, **kwargs: Any):
    """The plotly figure of a result (``plotly.graph_objects.Figure``): :func:`figure_spec`, validated by plotly.

    Parameters
    ----------
    result : a result, a result read back, or a Scene
    **kwargs
        Of :func:`figure_spec`.

    Returns
    -------
    plotly.graph_objects.Figure

    Raises
    ------
    ImportError
        plotly is not installed (names the extra ``dhlb[web]``).
    """
    _plotly()
    import plotly.graph_objects as go

    return go.Figure(figure_spec(result, **kwargs))


# ---------------------------------------------------------------------------- HTML
_DTYPES = {np.dtype(np.float32): "f4", np.dtype(np.float64): "f8", np.dtype(np.int32): "i4",
           np.dtype(np.uint8): "u1", np.dtype(np.int16): "i2", np.dtype(np.uint32): "u4"}


def _encode(obj):
    """JSON of numpy arrays: plotly.js's typed-array form ``{"dtype", "bdata"}`` (base64), compact and exact."""
    if isinstance(obj, np.ndarray):
        a = obj.astype(np.int32) if obj.dtype == np.int64 else obj
        if a.dtype not in _DTYPES:
            return a.tolist()
        return {"dtype": _DTYPES[a.dtype], "bdata": base64.b64encode(np.ascontiguousarray(a).tobytes()).decode()}
    if isinstance(obj, np.generic):
        return obj.item()
    raise TypeError(f"cannot write a {type(obj).__name__} into a web view")


def figure_json(spec: dict) -> str:
    """The JSON of :func:`figure_spec` (arrays as base64 typed arrays), safe to put inside a ``<script>``."""
    text = json.dumps(spec, default=_encode, separators=(",", ":"), allow_nan=False)
    return text.replace("</", "<\\/")


def plotlyjs_path() -> str:
    """The file of plotly's minified script inside the installed plotly package (no network needed).

    Raises
    ------
    ImportError
        plotly is not installed (names the extra ``dhlb[web]``).
    """
    plotly = _plotly()
    path = os.path.join(os.path.dirname(plotly.__file__), "package_data", PLOTLYJS)
    if not os.path.isfile(path):  # pragma: no cover - a broken plotly installation
        raise ImportError(f"plotly is installed but its script {path} is missing; reinstall plotly")
    return path


def write_plotlyjs(folder: str | os.PathLike[str]) -> str:
    """Copy plotly's script into ``folder`` (once: an existing copy of the same size is kept); return its path.

    Parameters
    ----------
    folder : str or path-like
        Where the pages that share the script live.

    Returns
    -------
    str
        ``folder/plotly.min.js``.
    """
    from dhlb._files import atomic_write

    src, dst = plotlyjs_path(), os.path.join(os.fspath(folder), PLOTLYJS)
    if not (os.path.isfile(dst) and os.path.getsize(dst) == os.path.getsize(src)):
        with open(src, "rb") as fh, atomic_write(dst, "wb") as out:
            out.write(fh.read())
    return dst


_GUARD = ("<script>window.PlotlyConfig = {MathJaxConfig: 'local'}; window.__dhlbDefine = window.define; "
          "window.define = undefined;</script>\n{script}\n<script>window.define = window.__dhlbDefine;</script>")


def _script_tag(plotlyjs: str) -> str:
    """``<script>`` loading plotly: inline, or from a file; hidden from require.js (an AMD loader would swallow it)."""
    if plotlyjs == "inline":
        with open(plotlyjs_path(), encoding="utf-8") as fh:
            tag = f"<script>{fh.read()}</script>"
    else:
        tag = f'<script src="{html.escape(plotlyjs)}"></script>'
    return _GUARD.replace("{script}", tag)


def _plot_call(div: str, spec: dict, config: dict) -> str:
    return (f"<script>(function () {{ var fig = {figure_json(spec)}; var gd = document.getElementById('{div}');"
            f" Plotly.newPlot(gd, fig.data, fig.layout, {json.dumps(config)}).then(function () {{"
            " gd.setAttribute('data-ready', '1'); }); })();</script>")


_CONFIG = {"displaylogo": False, "responsive": True, "scrollZoom": True}


def to_html(result: Any, path: str | os.PathLike[str], *, plotlyjs: str = "inline", title: str | None = None,
            **kwargs: Any) -> str:
    """Write an HTML page with the interactive 3-D view of ``result``; it opens from the file system, offline.

    Parameters
    ----------
    result : a result, a result read back, or a Scene
    path : str or path-like
        The page (written atomically).
    plotlyjs : {"inline", "directory"} or str
        ``"inline"``: plotly's script inside the page (self-contained, about 5 MB); ``"directory"``:
        one shared copy ``plotly.min.js`` beside the page (written if missing, :func:`write_plotlyjs`);
        any other string: the URL or relative path of plotly's script, used as given.
    title : str, optional
        The page's title (default: the scene's).
    **kwargs
        Of :func:`figure_spec` (``camera``, ``isolines``, ``max_faces``, ``max_glyphs``).

    Returns
    -------
    str
        The path written.

    Raises
    ------
    ImportError
        plotly is not installed (names the extra ``dhlb[web]``).
    OutputError
        The folder does not exist.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import uniform_flow, vortex_filaments
    >>> res = vortex_filaments(box_tet_mesh(2), None, uniform_flow([0.1, 0, 0]), hbar=1.0)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     page = to_html(res, os.path.join(d, "v.html"), plotlyjs="directory")
    ...     sorted(os.listdir(d)), "http" in open(page).read()
    (['plotly.min.js', 'v.html'], False)
    """
    from dhlb._files import atomic_write

    _plotly()                                               # before any work: the page needs plotly's script
    out = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(folder):
        raise OutputError(out, "the folder does not exist")
    spec = figure_spec(result, title=title, **kwargs)
    if plotlyjs == "directory":
        write_plotlyjs(folder)
        plotlyjs = PLOTLYJS
    script = _script_tag(plotlyjs)
    name = html.escape(spec["layout"]["meta"]["dhlb"]["title"])
    page = (f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n<title>{name}</title>\n'
            "<style>html, body { height: 100%; margin: 0; } #dhlb-view { width: 100%; height: 100%; }</style>\n"
            f"{script}\n</head>\n<body>\n<div id=\"dhlb-view\" class=\"dhlb-web-view\"></div>\n"
            f"{_plot_call('dhlb-view', spec, _CONFIG)}\n</body>\n</html>\n")
    with atomic_write(out) as fh:
        fh.write(page)
    return out


# ---------------------------------------------------------------------------- notebooks
_SENT: dict = {}


def notebook_view(result: Any, *, height: int = 480, **kwargs: Any) -> str:
    """The HTML of an inline interactive view (a div and a script) for a notebook cell.

    plotly's script is included with the first view of the process (a kernel: once per notebook) and
    reused by the next ones. With the environment variable ``DHLB_WEB_SCRIPT=page`` it is never
    included (the page provides it, as the documentation does).

    Parameters
    ----------
    result : a result, a result read back, or a Scene
    height : int
        Pixels.
    **kwargs
        Of :func:`figure_spec`.

    Returns
    -------
    str
        HTML.

    Raises
    ------
    ImportError
        plotly is not installed (names the extra ``dhlb[web]``).
    """
    spec = figure_spec(result, **kwargs)
    script = ""
    if os.environ.get("DHLB_WEB_SCRIPT") != "page" and not _SENT.get("plotlyjs"):
        script = _script_tag("inline")
        _SENT["plotlyjs"] = True
    else:
        _plotly()
    div = f"dhlb-view-{uuid.uuid4().hex[:12]}"
    return (f'{script}<div id="{div}" class="dhlb-web-view" style="width:100%;height:{int(height)}px"></div>'
            f"{_plot_call(div, spec, _CONFIG)}")
