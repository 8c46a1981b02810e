"""Texture coordinates of a stripe pattern (seed part 2, §4.3, App. B, Alg. 10), derived on the double cover.

Given a conjugate-symmetric section ψ (one complex value per vertex; for ``n = 1`` simply a
complex function) and a :class:`~dhlb.stripes.StripeForm`:

* **Spinning form** per canonical edge ``i < j``, on the lift starting at sheet 1 of i:
  ``δ̂_ij = arg(e^{iω̂_ij} ψ_i / ψ̃_j) ∈ [−π, π)`` with ``ψ̃_j = ψ_j`` (s = +1) or ``ψ̄_j`` (s = −1),
  and ``σ̂ = ω̂ − δ̂`` (the seed's §4.3 prints ``σ̂ := ω̂ + δ̂``; its own ``σ̃ := ω̃ − δ`` and Alg. 10
  line 23 have the minus sign). The tie ``δ = π`` is broken as in ``docs/conventions.md``
  (the rotation form ``ξ = −δ`` lies in ``(−π, π]``), once per edge, so both faces of an edge agree.
  ``e^{iσ̃}φ_p = φ_q`` on every lifted edge (``φ = ψ̃/|ψ̃|``): σ follows ω wherever ψ does, however
  large ω is (**frequency adjustment**).
* **Walk** each face ``(i, j, k)`` of ``mesh.faces`` from sheet 1 at its first corner:
  ``α_i = arg ψ_i``, ``α_j = α_i + σ̃_{ij}``, ``α_k = α_j + σ̃_{jk}``, ``α_l = α_k + σ̃_{ki}``.
  On a regular face ``α_l − α_i = 2π n_ijk`` (the **zero index**, in the mesh orientation; for
  ``n = 1`` it is :func:`dhlb.bundles.index_form` of the line bundle ``e^{iω̂}``). On a branch
  face the walk ends on the other sheet, ``α_l ≡ −α_i``.
* **Interpolation** (cones from the barycenter m; corner c spans the cone ``(m, c, c+1)`` where
  ``t_{c+2}`` is the smallest barycentric coordinate). On a regular face
  ``α(t) = Σ_c t_c α'_c + lArg_n(t)`` with ``α' = (α_i, α_j − 2πn/3, α_k − 4πn/3)`` (:attr:`corner_alpha`)
  and lArg of Eq. 4.2, whose corner values are ``0, 2πn/3, 4πn/3``. (Alg. 10 lines 28–29
  subtract ``2πn`` and ``4πn``, which does not match Eq. 4.2's corner values; we subtract lArg
  at the corners as §4.3 says.) On a branch face α is linear on the three cones with corner
  values ``β_m = (α_i + α_l)/2`` (≡ 0 mod π) at m and ``(β_i, β_j)``, ``(β_j, β_k)``, ``(β_k, β_l)``.
* **Continuity** (App. B): ``e^{iα}`` (n = 1), resp. ``cos α`` or any even 2π-periodic function
  of α (n = 2), is continuous on the surface except at the barycenters of zero faces.

Examples
--------
>>> import numpy as np
>>> from dhlb.stripes import larg
>>> (larg(1, [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.5, 0.5, 0]]) / (np.pi / 3)).round(12).tolist()
[0.0, 2.0, 4.0, 1.0]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int
from dhlb.bundles._sections import rotation_angles
from dhlb.errors import InvalidParameterError, NonFiniteError, SectionZeroError, ShapeError

if TYPE_CHECKING:
    from collections.abc import Callable

    from numpy.typing import ArrayLike

    from dhlb.stripes.oneform import StripeForm

__all__ = ["StripeTexture", "Subdivision", "larg", "texture_coordinates"]

TWO_PI = 2.0 * np.pi
_ROWS = np.arange(3)
_PRIORITY = np.array([2, 0, 1])


def _cones(t: np.ndarray):
    """Cone of each barycentric point: ``c`` (cone ``(m, c, c+1)``), t_min, t_c, t_{c+1}, ρ = 1 − 3 t_min."""
    lo = _PRIORITY[np.argmin(t[:, _PRIORITY], axis=1)]  # ties as in Eq. 4.2: t_k, then t_i, then t_j
    c = (lo + 1) % 3
    r = np.arange(len(t))
    tmin = t[r, lo]
    return c, tmin, t[r, c], t[r, (c + 1) % 3], np.clip(1.0 - 3.0 * tmin, 0.0, None)


def larg(n: int | ArrayLike, bary: ArrayLike) -> np.ndarray:
    """The interpolant lArg_n of Eq. 4.2 at barycentric points ``bary`` (k, 3) (n broadcasts).

    In the cone ``(m, c, c+1)`` (``t_{c+2}`` smallest) it equals ``2πn/3 · (c + τ)`` with
    ``τ = (t_{c+1} − t_{c+2}) / (1 − 3 t_{c+2})``: linear along the boundary (0, 2πn/3, 4πn/3 at
    the corners, 2πn back at the first), constant on rays from the barycenter m, and a continuous
    map to the circle away from m. At m it is NaN (0 where n = 0).

    Parameters
    ----------
    n : int or (k,) int array
        The zero index (one for all points, or one per point).
    bary : (k, 3) float array
        Barycentric points (not checked; a single point may be given as 3 numbers).

    Returns
    -------
    (k,) float array
        ``lArg_n`` at each point.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.stripes import larg
    >>> (larg(1, [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.5, 0.5, 0]]) / (np.pi / 3)).round(12).tolist()
    [0.0, 2.0, 4.0, 1.0]
    """
    t = np.asarray(bary, np.float64).reshape(-1, 3)
    n = np.broadcast_to(np.asarray(n, np.float64), (len(t),))
    c, tmin, _, tb, rho = _cones(t)
    ok = rho > 1e-14
    tau = np.clip(np.divide(tb - tmin, rho, out=np.zeros_like(rho), where=ok), 0.0, 1.0)
    val = TWO_PI / 3.0 * n * (c + tau)
    return np.where(ok | (n == 0), val, np.nan)


def _spinning_rotation(omega: np.ndarray, psi_i: np.ndarray, psi_j: np.ndarray) -> np.ndarray:
    """``ξ = −δ̂ = arg(ψ_j / (e^{iω} ψ_i)) ∈ (−π, π]`` per edge: the rotation form, tie rule of the conventions.

    Computed by :func:`dhlb.bundles._sections.rotation_angles` on the conjugate pair, which makes it
    bit-for-bit ``−δ̂`` with ``δ̂ = arg(e^{iω} ψ_i ψ̄_j) ∈ [−π, π)`` (tests/test_stripes_texture.py).

    Examples
    --------
    >>> _spinning_rotation(np.zeros(2), np.array([1, 1]), np.array([1j, -1])).round(6).tolist()
    [1.570796, 3.141593]
    """
    m = len(omega)
    pairs = np.column_stack([np.conj(psi_j), np.conj(np.exp(1j * omega) * psi_i)]).ravel()
    return rotation_angles(np.arange(2 * m).reshape(m, 2), pairs, np.ones(m))


@dataclass(frozen=True)
class Subdivision:
    """Sub-triangles on which α is (approximately) linear: face, barycentric corners, α at the corners.

    Regular faces without zero: the face itself (exact). Branch faces: the three cones (exact).
    Zero faces: each cone on a ``refine × refine`` grid in (distance from m, ray) coordinates, with
    the barycenter blown up (the nodes at m carry the limit values along their rays). Made by
    :meth:`StripeTexture.subdivision`; every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    face : (T,) int array
        The face of ``mesh.faces`` each sub-triangle lies in.
    bary : (T, 3, 3) float array
        Barycentric coordinates of the corners of each sub-triangle in its face.
    alpha : (T, 3) float array
        α at the corners (one continuous branch per sub-triangle).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
    >>> sub = tex.subdivision()        # no zero, no branch face: the two faces themselves
    >>> sub.face.tolist(), sub.bary.shape, sub.alpha.shape
    ([0, 1], (2, 3, 3), (2, 3))
    """

    face: np.ndarray  # (T,) int64
    bary: np.ndarray  # (T, 3, 3) barycentric coordinates of the corners in their face
    alpha: np.ndarray  # (T, 3) α at the corners (one continuous branch per sub-triangle)


class StripeTexture:
    """Per-corner texture coordinates, zero indices and branch data of a section ψ (see the module doc).

    Made by :func:`texture_coordinates`, which checks ψ (the constructor does not).

    Parameters
    ----------
    form : StripeForm
        The stripe form; kept as ``form`` (and ``mesh = form.mesh``).
    psi : (N,) complex array
        The section, finite and nowhere zero, in compact vertex order; kept as ``psi``.

    Attributes
    ----------
    spinning : (n_1,) float array
        σ̂ per canonical edge.
    corner_alpha : (m, 3) float array
        α' per corner of ``mesh.faces`` (the linear part; lArg is added on zero faces).
    zero_index : (m,) int array
        n_ijk (0 on branch faces).
    is_branch : (m,) bool array
        The branch faces of ``form``.
    branch_faces : (b,) int array
        Rows of ``mesh.faces`` of the branch faces.
    branch_alpha : (b, 2) float array
        ``(β_m, β_l)`` of each branch face.
    winding_defect : float
        The largest distance of a regular face's winding ``(α_l − α_i)/2π`` from an integer (rounding).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
    >>> tex.zero_index.tolist(), tex.branch_faces.tolist(), ((tex.corner_alpha / (np.pi / 2)).round(6) + 0.0).tolist()
    ([0, 0], [], [[0.0, 1.0, 0.0], [1.0, 1.0, 0.0]])
    """

    def __init__(self, form: StripeForm, psi: np.ndarray):
        self.form = form
        self.mesh = form.mesh
        self.psi = psi
        E = self.mesh.complex.simplices(1)
        s = form.edge_sign
        pj = np.where(s > 0, psi[E[:, 1]], np.conj(psi[E[:, 1]]))
        self.spinning = form.omega + _spinning_rotation(form.omega, psi[E[:, 0]], pj)
        side = form.lift_halfedges(self.spinning)
        a0 = np.angle(psi[self.mesh.faces[:, 0]])
        walk = np.cumsum(np.column_stack([a0, side]), axis=1)  # α_i, α_j, α_k, α_l
        self.is_branch = form.is_branch
        wind = (walk[:, 3] - walk[:, 0]) / TWO_PI
        self.winding_defect = float(np.max(np.abs(wind - np.round(wind))[~self.is_branch], initial=0.0))
        self.zero_index = np.where(self.is_branch, 0, np.round(wind)).astype(np.int64)
        self.corner_alpha = walk[:, :3] - (TWO_PI / 3.0) * self.zero_index[:, None] * _ROWS[None, :]
        self.branch_faces = np.nonzero(self.is_branch)[0]
        wb = walk[self.branch_faces]
        self.branch_alpha = np.column_stack([0.5 * (wb[:, 0] + wb[:, 3]), wb[:, 3]])
        self._branch_row = np.full(self.mesh.n_faces, -1, np.int64)
        self._branch_row[self.branch_faces] = np.arange(self.branch_faces.size)
        for a in (self.spinning, self.zero_index, self.corner_alpha, self.branch_faces, self.branch_alpha):
            a.setflags(write=False)

    # ------------------------------------------------------------------ singular points
    @property
    def zero_faces(self) -> np.ndarray:
        """Faces with a nonzero index (their zero sits at the barycenter)."""
        return np.nonzero(self.zero_index)[0]

    def _barycenters(self, faces) -> np.ndarray:
        return self.mesh.points[self.mesh.faces[faces]].mean(axis=1)

    @property
    def zero_points(self) -> np.ndarray:
        """Barycenters of the zero faces, shape ``(m, 3)``."""
        return self._barycenters(self.zero_faces)

    @property
    def branch_points(self) -> np.ndarray:
        """Barycenters of the branch faces, shape ``(m, 3)``."""
        return self._barycenters(self.branch_faces)

    # ------------------------------------------------------------------ evaluation
    def _points(self, faces, bary) -> tuple[np.ndarray, np.ndarray]:
        t = np.asarray(bary, dtype=np.float64)
        if t.ndim == 1:
            t = t.reshape(1, -1)
        if t.ndim != 2 or t.shape[1] != 3:
            raise ShapeError(f"barycentric coordinates must have shape (k, 3), got {np.shape(bary)}")
        f = np.asarray(faces)
        if not np.issubdtype(f.dtype, np.integer):
            raise ShapeError(f"faces must be integers (rows of mesh.faces), got dtype {f.dtype}")
        f = f.astype(np.int64).reshape(-1)
        if f.size not in (1, len(t)):
            raise ShapeError(f"faces must be one face or one per point ({len(t)}), got {f.size}")
        f = np.broadcast_to(f, (len(t),))
        bad = (f < 0) | (f >= self.mesh.n_faces)
        if np.any(bad):
            raise InvalidParameterError(f"face {int(f[np.argmax(bad)])} is not a row of mesh.faces "
                                        f"(0 .. {self.mesh.n_faces - 1})")
        bad = ~np.isfinite(t).all(axis=1)
        if np.any(bad):
            raise NonFiniteError(f"barycentric point {int(np.argmax(bad))} is not finite")
        tot = t.sum(axis=1)
        bad = (t.min(axis=1) < -1e-9) | (np.abs(tot - 1.0) > 1e-9)
        if np.any(bad):
            r = int(np.argmax(bad))
            raise InvalidParameterError(f"barycentric point {r} {t[r].tolist()} (face {int(f[r])}) is not in the "
                                        "face: coordinates must be >= 0 and sum to 1")
        return f, np.clip(t, 0.0, None) / tot[:, None]

    def evaluate(self, faces: ArrayLike, bary: ArrayLike) -> np.ndarray:
        """α at barycentric points ``bary`` (k, 3) of ``faces`` (k,) (or one face for all points).

        Barycentric coordinates refer to the corners of ``mesh.faces[f]`` in order. The value is
        meaningful modulo 2π (and, for ``n = 2``, up to sign); NaN exactly at the zero of a zero face.
        """
        f, t = self._points(faces, bary)
        out = np.einsum("kc,kc->k", t, self.corner_alpha[f]) + larg(self.zero_index[f], t)
        br = np.nonzero(self.is_branch[f])[0]
        if br.size:
            c, tmin, ta, tb, _ = _cones(t[br])
            k = self._branch_row[f[br]]
            B = np.column_stack([self.corner_alpha[f[br]], self.branch_alpha[k, 1]])
            r = np.arange(br.size)
            out[br] = 3.0 * tmin * self.branch_alpha[k, 0] + (ta - tmin) * B[r, c] + (tb - tmin) * B[r, c + 1]
        return out

    def pattern(self, faces: ArrayLike, bary: ArrayLike, fn: Callable[[np.ndarray], np.ndarray] = np.cos) -> np.ndarray:
        """``fn(α)`` at barycentric points; use an even 2π-periodic ``fn`` for line fields (n = 2)."""
        return fn(self.evaluate(faces, bary))

    # ------------------------------------------------------------------ subdivision
    def subdivision(self, refine: int = 8) -> Subdivision:
        """Sub-triangles with corner values on which α is linear (exactly, except inside zero faces)."""
        refine = check_int(refine, "refine", 1)
        eye = np.eye(3)
        mid = np.full(3, 1.0 / 3.0)
        parts = []
        plain = np.nonzero(~self.is_branch & (self.zero_index == 0))[0]
        parts.append((plain, np.broadcast_to(eye, (plain.size, 3, 3)), self.corner_alpha[plain]))
        bf = self.branch_faces
        if bf.size:
            B = np.column_stack([self.corner_alpha[bf], self.branch_alpha[:, 1]])
            for c in range(3):
                bary = np.stack([mid, eye[c], eye[(c + 1) % 3]])
                alpha = np.column_stack([self.branch_alpha[:, 0], B[:, c], B[:, c + 1]])
                parts.append((bf, np.broadcast_to(bary, (bf.size, 3, 3)), alpha))
        zf = self.zero_faces
        if zf.size:
            r = int(refine)
            a, b = np.meshgrid(np.arange(r + 1), np.arange(r + 1), indexing="ij")
            rho, tau = ((a / r) ** 2).ravel(), (b / r).ravel()  # radial nodes denser near the zero
            node = lambda x, y: x * (r + 1) + y  # noqa: E731
            ga, gb = np.meshgrid(np.arange(r), np.arange(r), indexing="ij")
            ga, gb = ga.ravel(), gb.ravel()
            tri = np.concatenate([np.stack([node(ga, gb), node(ga + 1, gb), node(ga + 1, gb + 1)], 1),
                                  np.stack([node(ga, gb), node(ga + 1, gb + 1), node(ga, gb + 1)], 1)])
            nz = self.zero_index[zf].astype(np.float64)
            for c in range(3):
                bary = ((1 - rho)[:, None] * mid + rho[:, None] * ((1 - tau)[:, None] * eye[c]
                                                                  + tau[:, None] * eye[(c + 1) % 3]))
                val = self.corner_alpha[zf] @ bary.T + (TWO_PI / 3.0) * nz[:, None] * (c + tau)[None, :]
                parts.append((np.repeat(zf, len(tri)), np.broadcast_to(bary[tri], (zf.size,) + bary[tri].shape)
                              .reshape(-1, 3, 3), val[:, tri].reshape(-1, 3)))
        face = np.concatenate([p[0] for p in parts]).astype(np.int64)
        bary = np.concatenate([np.asarray(p[1]).reshape(-1, 3, 3) for p in parts])
        alpha = np.concatenate([np.asarray(p[2]).reshape(-1, 3) for p in parts])
        return Subdivision(face, bary, alpha)

    def __repr__(self) -> str:
        return (f"StripeTexture(n={self.form.n}, zeros={self.zero_faces.size}, "
                f"branch_faces={self.branch_faces.size}, {self.mesh!r})")


def texture_coordinates(form: StripeForm, psi: ArrayLike) -> StripeTexture:
    """Texture coordinates (§4.3) of a section ψ of the stripe bundle of ``form``.

    Parameters
    ----------
    form : StripeForm
        The stripe form (:func:`~dhlb.stripes.stripe_form`).
    psi : (N,) complex array
        One value per compact vertex (or per row of the input V): for ``n = 2`` the stored value of
        the conjugate-symmetric function (``ψ̃ = ψ`` on the sheet of X_i, ``ψ̄`` on the other);
        e.g. an eigenvector ``x`` of the real 2N×2N problem as ``x[0::2] + 1j * x[1::2]``.

    Returns
    -------
    StripeTexture
        The per-corner texture coordinates, zero indices and branch data; ``evaluate`` gives α anywhere.

    Raises
    ------
    ShapeError, NonFiniteError
        wrong length, NaN or infinity (naming the vertex).
    SectionZeroError
        ψ vanishes at a vertex (its phase is undefined there; naming the vertex).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
    >>> round(float(tex.evaluate(0, [[0.2, 0.5, 0.3]])[0] / (np.pi / 2)), 6)        # α = ν x at x = 0.5
    0.5
    """
    mesh = form.mesh
    arr = np.asarray(psi)
    if arr.ndim != 1:
        raise ShapeError(f"psi must have one complex value per vertex, got shape {arr.shape}")
    z = mesh.per_vertex(arr, "psi").astype(np.complex128)
    bad = ~np.isfinite(z)
    if np.any(bad):
        raise NonFiniteError(f"psi is not finite at vertex {int(mesh.vertex_rows[np.argmax(bad)])}")
    zero = z == 0
    if np.any(zero):
        raise SectionZeroError(f"psi vanishes at vertex {int(mesh.vertex_rows[np.argmax(zero)])} "
                               f"({int(zero.sum())} such vertices): the stripe phase arg ψ is undefined there; "
                               "perturb ψ (an eigenvector generically has no zero at a vertex)")
    z.setflags(write=False)
    return StripeTexture(form, z)
