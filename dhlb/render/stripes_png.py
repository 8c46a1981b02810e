"""PNG pictures of stripe patterns: each face subdivided k × k and coloured by ``cos α``.

Same camera, Lambert shading, back-face culling and painter's algorithm as
:func:`dhlb.render.render_field_png` (whose helpers it reuses). Every face of the mesh is split
into k² sub-triangles on the regular barycentric grid; each sub-triangle is coloured by
``g = (1 + cos α)/2`` at its centroid, α from :meth:`dhlb.stripes.StripeTexture.evaluate`, so the
nonlinear interpolant lArg in zero faces and the cone construction in branch faces are drawn as
they are. The default k resolves about six samples per period on the face with the largest
phase change, within a budget of sub-triangles.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb.errors import InvalidParameterError
from dhlb.render._figure import (
    _CAMERA,
    BRANCH,
    NEGATIVE,
    POSITIVE,
    Camera,
    StripeStyle,
    _matplotlib,
    _unit,
    face_normals,
    finish_figure,
)

if TYPE_CHECKING:
    import os
    from typing import Any

    from dhlb.stripes.texture import StripeTexture

__all__ = ["render_stripes_png", "face_grid"]

_STRIPE_STYLE = ("dark", "light", "fn", "ambient", "max_triangles", "mark_singularities", "background")


def face_grid(k: int) -> tuple[np.ndarray, np.ndarray]:
    """The k × k barycentric grid of a triangle: nodes ``(K, 3)`` and sub-triangles ``(k², 3)`` (node rows).

    Examples
    --------
    >>> nodes, tris = face_grid(2)
    >>> nodes.shape, tris.shape
    ((6, 3), (4, 3))
    """
    a, b = np.meshgrid(np.arange(k + 1), np.arange(k + 1), indexing="ij")
    keep = a + b <= k
    a, b = a[keep], b[keep]
    nodes = np.stack([k - a - b, a, b], axis=1) / k
    lut = -np.ones((k + 2, k + 2), np.int64)
    lut[a, b] = np.arange(a.size)
    up = a + b <= k - 1
    dn = a + b <= k - 2
    tris = np.concatenate([np.stack([lut[a[up], b[up]], lut[a[up] + 1, b[up]], lut[a[up], b[up] + 1]], 1),
                           np.stack([lut[a[dn] + 1, b[dn]], lut[a[dn] + 1, b[dn] + 1], lut[a[dn], b[dn] + 1]], 1)])
    return nodes, tris


def _auto_k(texture, budget: int) -> int:
    A = texture.corner_alpha
    span = np.ptp(A, axis=1) + 2 * np.pi * np.abs(texture.zero_index)
    bf = texture.branch_faces
    span[bf] = np.ptp(np.column_stack([A[bf], texture.branch_alpha]), axis=1)
    k = int(np.clip(np.ceil(6 * np.max(span, initial=0.0) / (2 * np.pi)), 3, 16))
    return max(1, min(k, int(np.sqrt(budget / max(texture.mesh.n_faces, 1)))))


def render_stripes_png(
    path: str | os.PathLike[str],
    texture: StripeTexture,
    *,
    k: int | None = None,
    camera: Camera | None = None,
    style: StripeStyle | None = None,
    title: str | None = None,
    **deprecated: Any,
) -> str:
    r"""Render a :class:`~dhlb.stripes.StripeTexture` to a PNG file.

    Parameters
    ----------
    path : str or path-like
        Output file (PNG).
    texture : StripeTexture
        The texture coordinates of a pattern (``result.texture`` of :func:`dhlb.stripes.stripe_pattern`).
    k : int, optional
        Subdivision of each face (k² sub-triangles); default: about six samples per period, at most
        16 and within ``style.max_triangles`` in total.
    camera : Camera, optional
        View direction, up direction, picture size and dpi (:class:`~dhlb.render.Camera`).
    style : StripeStyle, optional
        Colours, profile, shading and singularity marks (:class:`~dhlb.render.StripeStyle`).
    title : str, optional
        Written in the top left corner.
    **deprecated
        The keywords of dhlb 0.1, with a :class:`DeprecationWarning`: ``view``, ``up``, ``size``, ``dpi``
        (→ ``camera``), ``dark``, ``light``, ``fn``, ``ambient``, ``max_triangles``, ``mark_singularities``,
        ``background`` (→ ``style``).

    Returns
    -------
    str
        The path written.

    Raises
    ------
    InvalidParameterError
        ``k`` is not an integer >= 1.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> from dhlb.render import Camera, StripeStyle, render_stripes_png
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.0]])
    >>> form = stripe_form(validate_surface(V, [[0, 1, 2], [1, 3, 2]]), np.tile([1.0, 0, 0], (4, 1)), frequency=2,
    ...                    warn_aliasing=False)   # period 1/2: stripes narrower than the edges
    >>> tex = texture_coordinates(form, np.exp(4j * np.pi * V[:, 0]))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = render_stripes_png(os.path.join(d, "s.png"), tex, style=StripeStyle(mark_singularities=True),
    ...                            camera=Camera(view=(0, 0, 1), up=(0, 1, 0), size=(64, 64)))
    ...     open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    True
    """
    camera, style = fold_deprecated_kwargs("render_stripes_png", deprecated, ("camera", camera, Camera(), _CAMERA),
                                           ("style", style, StripeStyle(), _STRIPE_STYLE))
    Figure, FigureCanvasAgg, PolyCollection = _matplotlib()
    mesh = texture.mesh
    size, dpi, background, ambient, fn = camera.size, camera.dpi, style.background, style.ambient, style.fn
    dark, light, max_triangles = style.dark, style.light, style.max_triangles
    if k is None:
        k = _auto_k(texture, max_triangles)
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
        raise InvalidParameterError(f"k must be an integer >= 1, got {k!r}")
    k = int(k)
    P, F = mesh.points, mesh.faces
    right, upv, w = camera.fitted(P).frame()
    c = P.mean(axis=0)
    fn_ = _unit(face_normals(P, F))
    facing = fn_ @ w
    light_dir = _unit(w + 0.35 * upv + 0.15 * right)
    shade = fn_ @ light_dir
    closed = mesh.is_closed
    faces = np.nonzero(facing > 0)[0] if closed else np.arange(mesh.n_faces)
    shade = shade if closed else np.where(facing < 0, -shade, shade)
    lam = ambient + (1 - ambient) * np.clip(shade, 0, 1)
    nodes, tris = face_grid(k)
    cen = nodes[tris].mean(axis=1)  # (k², 3) centroids
    nf, nt = faces.size, len(tris)
    ff = np.repeat(faces, nt)
    g = fn(texture.evaluate(ff, np.tile(cen, (nf, 1))))
    g = np.nan_to_num(0.5 * (1 + g), nan=0.5)
    from matplotlib.colors import to_rgb

    c0, c1 = np.asarray(to_rgb(dark)), np.asarray(to_rgb(light))     # any matplotlib colour
    col = c0[None, :] + g[:, None] * (c1 - c0)[None, :]
    col = np.clip(col * lam[ff][:, None], 0, 1)
    X = np.einsum("tc,fcd->ftd", nodes, P[F[faces]] - c)  # (nf, K, 3)
    Y = X[:, tris]  # (nf, nt, 3, 3)
    xy = np.stack([Y @ right, Y @ upv], axis=-1).reshape(-1, 3, 2)
    depth = (Y @ w).mean(axis=2).ravel()
    polys, zs = [xy], [depth]
    rgba = [np.column_stack([col, np.ones(len(col))])]
    if style.mark_singularities:
        E = mesh.complex.simplices(1)
        mean_edge = float(np.mean(np.linalg.norm(P[E[:, 1]] - P[E[:, 0]], axis=1)))
        sf = np.r_[texture.zero_faces, texture.branch_faces]
        kind = np.r_[np.sign(texture.zero_index[texture.zero_faces]), np.zeros(texture.branch_faces.size)]
        seen = facing[sf] > 0 if closed else np.ones(sf.size, bool)
        pts = np.vstack([texture.zero_points, texture.branch_points])[seen] - c
        kind = kind[seen]
        extent = float(np.ptp(np.stack([(P - c) @ right, (P - c) @ upv], axis=1), axis=0).max()) or 1.0
        rad = min(0.3 * mean_edge, 0.012 * extent)
        ang = np.linspace(0, 2 * np.pi, 11)
        ring = rad * np.stack([np.cos(ang), np.sin(ang)], axis=1)
        fan = np.stack([np.zeros((10, 2)), ring[:-1], ring[1:]], axis=1)
        pxy = np.stack([pts @ right, pts @ upv], axis=1)
        polys.append((pxy[:, None, None, :] + fan[None]).reshape(-1, 3, 2))
        zs.append(np.repeat(pts @ w + mean_edge, 10))
        palette = {1.0: (*POSITIVE, 1.0), -1.0: (*NEGATIVE, 1.0), 0.0: (*BRANCH, 1.0)}
        rgba.append(np.repeat(np.array([palette[float(x)] for x in kind]).reshape(-1, 4), 10, axis=0))
    order = np.argsort(np.concatenate(zs), kind="stable")
    polys = np.concatenate(polys)[order]
    rgba = np.concatenate(rgba)[order]
    W, H = size
    fig = Figure(figsize=(W / dpi, H / dpi), dpi=dpi, facecolor=background)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    ax.add_collection(PolyCollection(polys, facecolors=rgba, edgecolors=rgba, linewidths=0.25, closed=True,
                                     antialiaseds=False), autolim=False)
    Q = P - c
    pxy = np.stack([Q @ right, Q @ upv], axis=1)
    return finish_figure(fig, ax, path, pxy, W / H, title, dpi, background)
