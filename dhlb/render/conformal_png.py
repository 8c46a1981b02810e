"""The picture of a close-to-conformal deformation: the boundary before and after, coloured by distortion.

Examples
--------
>>> from dhlb.conformal import conformal_deformation, point_charge_factor
>>> from dhlb.mesh import ball_tet_mesh
>>> from dhlb.render.conformal_png import boundary_distortion
>>> m = ball_tet_mesh(2)
>>> F, d = boundary_distortion(conformal_deformation(m.points, m.tets, point_charge_factor([(3, 0, 0, 0.5)])))
>>> F.shape[0] == d.shape[0] and bool((d >= 1).all())
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb.render._figure import _CAMERA, Camera, ConformalStyle, _matplotlib, _title_band, face_normals, write_png

if TYPE_CHECKING:
    import os
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["CONFORMAL_CAMERA", "boundary_distortion", "distortion_range", "render_conformal_png", "rigid_fit"]

CONFORMAL_CAMERA = Camera(size=(1200, 600))
"""The default camera of :func:`render_conformal_png` (two panels side by side)."""


def render_conformal_png(path: str | os.PathLike[str], before: ArrayLike, after: ArrayLike, faces: ArrayLike,
                         distortion_faces: ArrayLike, *, camera: Camera | None = None,
                         style: ConformalStyle | None = None, title: str | None = None, **deprecated: Any) -> str:
    r"""Two panels, the boundary surface before and after, each triangle coloured by the distortion of its tet.

    The colour bar runs from 1 (conformal) to the 98th percentile of the distortion; the few
    triangles above it have the top colour (the bar's arrow says so).

    The deformed mesh is shown after the rigid motion that best aligns it with the input (the map is
    defined up to one); each panel is scaled to fit its mesh.

    Parameters
    ----------
    path : str or path-like
        Output file (PNG).
    before, after : (N, 3) float array
        Vertex positions of the mesh and of its deformation.
    faces : (b, 3) int array
        Boundary triangles (outward), rows of ``before``.
    distortion_faces : (b,) float array
        The distortion of the tet of each boundary triangle (1 = conformal; :func:`boundary_distortion`).
    camera : Camera, optional
        View direction, up direction, picture size and dpi (:class:`~dhlb.render.Camera`; default
        :data:`CONFORMAL_CAMERA`, 1200 × 600).
    style : ConformalStyle, optional
        Colormap and background (:class:`~dhlb.render.ConformalStyle`).
    title : str, optional
        Written above the panels (wrapped to the picture's width).
    **deprecated
        The keywords ``view``, ``up``, ``size``, ``dpi`` (→ ``camera``) of dhlb 0.1, with a
        :class:`DeprecationWarning`.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    InvalidParameterError
        An old keyword together with ``camera``.
    TypeError
        An unknown keyword argument.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.render import CONFORMAL_CAMERA, ConformalStyle, render_conformal_png
    >>> m = box_tet_mesh(2)
    >>> F = m.boundary_faces
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = render_conformal_png(os.path.join(d, "c.png"), m.points, 2 * m.points, F, np.ones(len(F)),
    ...                              camera=CONFORMAL_CAMERA.replace(size=(300, 150)),
    ...                              style=ConformalStyle(colormap="magma"))
    ...     open(p, "rb").read(4) == b"\x89PNG"
    True
    """
    (camera,) = fold_deprecated_kwargs("render_conformal_png", deprecated,
                                       ("camera", camera, CONFORMAL_CAMERA, _CAMERA))
    if style is not None:
        from dhlb._deprecation import check_option_group

        check_option_group("render_conformal_png", "style", style, ConformalStyle())
    style = ConformalStyle() if style is None else style
    Figure, FigureCanvasAgg, PolyCollection = _matplotlib()
    from matplotlib import colormaps
    from matplotlib.colors import Normalize

    size, dpi = camera.size, camera.dpi
    F = np.asarray(faces, dtype=np.int64)
    B, A = np.asarray(before, float), np.asarray(after, float)
    right, upv, w = camera.fitted(B).frame()
    after = rigid_fit(A, B)   # f is defined up to a rigid motion: show it best aligned with the input
    d = np.asarray(distortion_faces, dtype=float)
    norm = Normalize(*distortion_range(d))
    hi = norm.vmax
    cmap = colormaps[style.colormap]
    fig = Figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi, facecolor=style.background)
    FigureCanvasAgg(fig)
    band = _title_band(fig, title, dpi)                  # the title above the panels, never over them
    top = max(1 - band - 1.6 * 10 * dpi / 72 / size[1], 0.3)   # room for the panels' own titles
    aspect = 0.5 * size[0] / ((top - 0.17) * size[1])    # of one panel
    for k, (V, name) in enumerate(((B, "before"), (np.asarray(after, float), "after"))):
        ax = fig.add_axes([k / 2, 0.17, 0.5, top - 0.17])
        ax.set_axis_off()
        xy = np.c_[V @ right, V @ upv]
        depth = V[F].mean(axis=1) @ w
        n = face_normals(V, F)
        front = n @ w > 0
        order = np.argsort(depth)
        order = order[front[order]]
        shade = 0.55 + 0.45 * np.abs(n[order] @ w) / np.maximum(np.linalg.norm(n[order], axis=1), 1e-300)
        colors = cmap(norm(d[order]))
        colors[:, :3] *= shade[:, None]
        ax.add_collection(PolyCollection(xy[F[order]], facecolors=colors, edgecolors="none"))
        drawn = xy[np.unique(F)] if F.size else xy
        lo, hi_ = drawn.min(0), drawn.max(0)
        mid = (lo + hi_) / 2
        hy = 0.55 * max((hi_[0] - lo[0]) / aspect, hi_[1] - lo[1], 1e-12)   # the mesh fills its panel
        ax.set_xlim(mid[0] - hy * aspect, mid[0] + hy * aspect)
        ax.set_ylim(mid[1] - hy, mid[1] + hy)
        ax.set_title(name, fontsize=10)
    from matplotlib.cm import ScalarMappable

    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), cax=fig.add_axes([0.3, 0.12, 0.4, 0.025]),
                       orientation="horizontal", extend="max" if d.size and float(np.nanmax(d)) > hi else "neither")
    bar.set_label("distortion of the tet (1 = conformal)", fontsize=9)   # bar and label above the bottom edge
    bar.ax.tick_params(labelsize=8)
    return write_png(fig, path, dpi, style.background)


def rigid_fit(points: ArrayLike, target: ArrayLike) -> np.ndarray:
    """``points`` moved by the rotation and translation that bring them closest to ``target`` (least squares).

    A close-to-conformal deformation is defined up to a rigid motion; its pictures show it aligned
    with the input (the orthogonal Procrustes problem, solved by an SVD, without reflection).

    Parameters
    ----------
    points, target : (N, 3) float arrays
        Corresponding points.

    Returns
    -------
    (N, 3) float array

    Examples
    --------
    >>> import numpy as np
    >>> X = np.random.default_rng(0).normal(size=(5, 3))
    >>> R = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    >>> bool(np.allclose(rigid_fit(X @ R.T + 2.0, X), X))
    True
    """
    A, B = np.asarray(points, dtype=np.float64), np.asarray(target, dtype=np.float64)
    U, _, Vt = np.linalg.svd((A - A.mean(0)).T @ (B - B.mean(0)))
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    return (A - A.mean(0)) @ U @ D @ Vt + B.mean(0)


def distortion_range(distortion: ArrayLike) -> tuple[float, float]:
    """The colour range of a distortion picture: 1 (conformal) to the 98th percentile.

    One bad tet must not make the rest one colour: the top 2 % saturate instead.

    Parameters
    ----------
    distortion : (m,) float array

    Returns
    -------
    low, high : float
        ``1.0`` and the 98th percentile (at least ``1 + 1e-6``).

    Examples
    --------
    >>> import numpy as np
    >>> d = np.r_[np.linspace(1.0, 1.1, 99), 2.9]       # one outlier
    >>> round(distortion_range(d)[1], 3)
    1.098
    """
    d = np.asarray(distortion, dtype=float).reshape(-1)
    d = d[np.isfinite(d)]
    return 1.0, max(float(np.percentile(d, 98)) if d.size else 1.0, 1.0 + 1e-6)


def boundary_distortion(result) -> tuple[np.ndarray, np.ndarray]:
    """The boundary triangles of a :class:`~dhlb.conformal.ConformalResult` and the distortion of their tets.

    Parameters
    ----------
    result : ConformalResult
        A result of :func:`dhlb.conformal.conformal_deformation`.

    Returns
    -------
    faces : (b, 3) int array
        ``result.mesh.boundary_faces``.
    distortion : (b,) float array
        The distortion of the tet of each of them.

    Examples
    --------
    >>> from dhlb.conformal import conformal_deformation, point_charge_factor
    >>> from dhlb.mesh import ball_tet_mesh
    >>> m = ball_tet_mesh(2)
    >>> F, d = boundary_distortion(conformal_deformation(m.points, m.tets, point_charge_factor([(3, 0, 0, 0.5)])))
    >>> F.shape[0] == d.shape[0] and bool((d >= 1).all())
    True
    """
    mesh = result.mesh
    F = mesh.boundary_faces
    local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])  # the tet of each boundary triangle
    allf = np.sort(mesh.tets[:, local].reshape(-1, 3), axis=1)
    tet_of = np.repeat(np.arange(mesh.tets.shape[0]), 4)
    keys = {tuple(f): t for f, t in zip(allf.tolist(), tet_of.tolist())}
    return F, np.array([result.distortion[keys[tuple(sorted(f))]] for f in F.tolist()])
