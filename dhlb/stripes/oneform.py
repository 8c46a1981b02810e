"""The stripe 1-form, the relative orientation of line-field representatives and the double cover.

Seed part 2, §3.1–§3.4, Alg. 6.

Input: a validated mesh, one direction per vertex (a 3D vector, made tangent and unit) and a
frequency per vertex. With ``n = 1`` the directions are oriented (a vector field); with ``n = 2``
they represent lines (a line field: ``X_i`` and ``−X_i`` mean the same).

**Frequency.** ``frequency`` f is measured in *stripes per unit length*: along X the pattern
``cos α`` repeats every ``1/f`` length units, so α grows at the angular rate ``ν = 2π f``
(radians per unit length; the seed's ν). ``spacing`` s is the period measured in mean edge
lengths: ``f = 1 / (s · mean edge length)``.

**Relative orientation** (§3.3). With φ_i the rescaled angle of X_i (frames of
:class:`~dhlb.mesh.TangentBundle`) and ρ_ij its Levi-Civita transport (``n = 1``),
``s_ij = +1`` iff ``φ_j − φ_i − ρ_ij ∈ [−π/2, π/2)`` mod 2π, else −1; for ``n = 1`` all
``s_ij = +1``. A face is a **branch triangle** iff ``s_ij s_jk s_ki = −1``.

**The 1-form** ω̂ (Eq. 3.2 derived; one real per canonical edge ``i < j``): the integral of
``⟨νX, ·⟩`` along the edge with X_j replaced by its representative ``s_ij X_j`` that matches X_i,

* ``method="intrinsic"`` (default): ``ω̂_ij = ½ ℓ_ij (ν_i cos(φ_i − θ_i(e_ij)) − s_ij ν_j cos(φ_j − θ_j(e_ji)))``;
* ``method="extrinsic"``: ``ω̂_ij = ½ (ν_i ⟨e_ij, X_i⟩ + s_ij ν_j ⟨e_ij, X_j⟩)`` (3D vectors).

(Eq. 3.3 and Alg. 6 of the seed print ``+ ν_j cos(φ_j − θ_ji)``: θ_ji is the direction of the
edge *from j to i*, so the edge direction at j is ``θ_ji + π`` and the sign flips. On a flat mesh
both methods agree exactly.)

**The double cover as a real rank-2 bundle** (§3.3–§3.4, §4.1). A conjugate-symmetric function
on the double cover is one ψ_i ∈ C ≅ R² per vertex; the energy term of edge ij is
``|ψ_j − e^{iω̂}ψ_i|²`` (s = +1) or ``|ψ̄_j − e^{iω̂}ψ_i|²`` (s = −1). Both are
``|v_j − η_ij v_i|²`` for the orthogonal transport ``η_ij = R(ω̂_ij)`` (rotation) or
``η_ij = C R(ω̂_ij)`` (reflection, ``C = diag(1, −1)`` the conjugation) on ``v = (Re ψ, Im ψ)``:
:attr:`StripeForm.bundle` is this :class:`~dhlb.bundles.VectorBundle` over ``"R"``. The
holonomy of a face has determinant ``s_ij s_jk s_ki``: branch triangles are exactly the faces
whose holonomy is a reflection. :attr:`StripeForm.double_cover` is the equivalent complex data
(:class:`DoubleCover`): K̃ with the line bundle ``e^{iω̃}``, ``Ω = dω̃``, where ``ψ̃ = (ψ, ψ̄)``
has twice the energy of ψ in the real bundle.

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import validate_surface
>>> from dhlb.stripes import stripe_form
>>> mesh = validate_surface([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]])
>>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)   # period 4
>>> (form.omega / np.pi).round(12).tolist()     # ν Δx = (π/2) Δx on edges (0,1) (0,2) (1,2) (1,3) (2,3)
[0.5, 0.0, -0.5, 0.0, 0.5]
>>> bool(form.is_branch.any()), form.bundle.rank
(False, 2)
"""

from __future__ import annotations

import warnings
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int
from dhlb.bundles.hermitian import HermitianLineBundle
from dhlb.bundles.vector_bundle import VectorBundle
from dhlb.errors import DhlbWarning, InvalidConnectionError, InvalidParameterError
from dhlb.mesh.coerce import as_tangent_bundle
from dhlb.mesh.surface import SurfaceMesh
from dhlb.mesh.tangent import TangentBundle
from dhlb.stripes._double_cover import DoubleCover
from dhlb.stripes._oneform_input import checked_directions, edge_name, per_vertex_positive
from dhlb.topology.complex import SimplicialComplex

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["StripeForm", "DoubleCover", "stripe_form"]

TWO_PI = 2.0 * np.pi


class StripeForm:
    """Directions, frequencies, the 1-form ω̂, the signs s and the double cover of a stripe problem.

    Build it with :func:`stripe_form`. Per canonical edge of ``mesh.complex.simplices(1)``:
    :attr:`omega`, :attr:`edge_sign`; per face of ``mesh.faces`` (mesh orientation):
    :attr:`is_branch`, :attr:`corner_sheet`, :meth:`lift_halfedges`.

    The constructor checks nothing (:func:`stripe_form` does) and makes the arrays read-only; every
    parameter is kept as the attribute of the same name, and ``mesh`` is ``tangent.mesh``.

    Parameters
    ----------
    tangent : TangentBundle
        The tangent bundle of the mesh with power 1 (its frames and transport angles are used).
    directions : (N, 3) float array
        The unit tangent direction ``X_i`` at each compact vertex.
    angles : (N,) float array
        The rescaled angle ``φ_i`` of ``X_i`` in the frames of ``tangent``.
    frequency : (N,) float array
        Stripes per unit length at each vertex (``ν = 2π · frequency``).
    n : {1, 2}
        1: oriented directions (vector field); 2: lines.
    method : {"intrinsic", "extrinsic"}
        How :attr:`omega` is computed (see the module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> form.n, form.edge_sign.tolist(), form.is_branch.tolist(), round(float(form.omega[0] / np.pi), 6)
    (1, [1, 1, 1, 1, 1], [False, False], 0.5)
    """

    def __init__(self, tangent: TangentBundle, directions: np.ndarray, angles: np.ndarray, frequency: np.ndarray,
                 n: int, method: str):
        self.tangent = tangent
        self.mesh = tangent.mesh
        self.n = int(n)
        self.method = method
        self.directions = directions
        self.angles = angles
        self.frequency = frequency
        for a in (directions, angles, frequency):
            a.setflags(write=False)

    @property
    def nu(self) -> np.ndarray:
        """``(N,)`` angular frequency ν = 2π f (radians of α per unit length)."""
        return TWO_PI * self.frequency

    @cached_property
    def edge_lengths(self) -> np.ndarray:
        """Length of every edge (rows of ``mesh.complex.simplices(1)``): the intrinsic one of a mollified mesh."""
        if self.mesh.edge_lengths is not None:
            return self.mesh.edge_lengths
        E = self.mesh.complex.simplices(1)
        return np.linalg.norm(self.mesh.points[E[:, 1]] - self.mesh.points[E[:, 0]], axis=1)

    @cached_property
    def edge_sign(self) -> np.ndarray:
        """``(n_1,)`` int64 s_ij ∈ {+1, −1}: does ``X_j`` match the transport of ``X_i`` (+1) or ``−X_i``."""
        E = self.mesh.complex.simplices(1)
        if self.n == 1:
            return np.ones(E.shape[0], np.int64)
        phi = self.angles
        rho = self.tangent.transport_angles
        d = np.mod(phi[E[:, 1]] - phi[E[:, 0]] - rho + np.pi, TWO_PI) - np.pi
        return np.where((d >= -np.pi / 2) & (d < np.pi / 2), 1, -1).astype(np.int64)

    @cached_property
    def omega(self) -> np.ndarray:
        """``(n_1,)`` ω̂_ij per canonical edge ``i < j`` (from the sheet of X_i to the matching sheet of j)."""
        E = self.mesh.complex.simplices(1)
        i, j = E[:, 0], E[:, 1]
        nu, s = self.nu, self.edge_sign
        if self.method == "extrinsic":
            e = self.mesh.points[j] - self.mesh.points[i]
            X = self.directions
            return 0.5 * (nu[i] * np.sum(e * X[i], 1) + s * nu[j] * np.sum(e * X[j], 1))
        th = self.tangent.edge_angles
        phi = self.angles
        return 0.5 * self.edge_lengths * (nu[i] * np.cos(phi[i] - th[:, 0]) - s * nu[j] * np.cos(phi[j] - th[:, 1]))

    # ------------------------------------------------------------------ per face
    @cached_property
    def face_edges(self) -> np.ndarray:
        """``(m, 3)`` canonical edge of the side ``c → c+1`` of each face (corners in mesh order)."""
        return self.mesh.halfedge_edge.reshape(-1, 3)

    @cached_property
    def face_forward(self) -> np.ndarray:
        """``(m, 3)`` bool: the side ``c → c+1`` runs along the canonical orientation of its edge."""
        F = self.mesh.faces
        return F < np.roll(F, -1, axis=1)

    @cached_property
    def corner_sheet(self) -> np.ndarray:
        """``(m, 3)`` ±1: the sheet of each corner when the face is lifted from sheet 1 at its first corner."""
        s = self.edge_sign[self.face_edges]
        return np.stack([np.ones(len(s), np.int64), s[:, 0], s[:, 0] * s[:, 1]], axis=1)

    @cached_property
    def is_branch(self) -> np.ndarray:
        """``(m,)`` bool: ``s_ij s_jk s_ki = −1`` (the lifted boundary of the face is a hexagon)."""
        return np.prod(self.edge_sign[self.face_edges], axis=1) < 0

    def lift_halfedges(self, values: ArrayLike) -> np.ndarray:
        """Lift a 1-form on the double cover given by its canonical values (like ω̂) to the face sides.

        ``values[e]`` is the value on the lift of edge ``i < j`` starting at sheet 1 of ``i``; it is
        antisymmetric under sheet interchange. Returns ``(m, 3)``: the value along the side
        ``c → c+1`` of each face lifted from sheet 1 at its first corner.
        """
        v = np.asarray(values, np.float64)[self.face_edges]
        s = self.edge_sign[self.face_edges]
        return self.corner_sheet * np.where(self.face_forward, v, -s * v)

    # ------------------------------------------------------------------ bundles
    @cached_property
    def transports(self) -> np.ndarray:
        """``(n_1, 2, 2)`` read-only: the transports ``R(ω̂)`` (s = +1) or ``C R(ω̂)`` (s = −1) of :attr:`bundle`."""
        c, sn = np.cos(self.omega), np.sin(self.omega)
        s = self.edge_sign.astype(np.float64)
        eta = np.stack([np.stack([c, -sn], -1), np.stack([s * sn, s * c], -1)], axis=1)
        eta.setflags(write=False)
        return eta

    @cached_property
    def bundle(self) -> VectorBundle:
        """The real rank-2 Euclidean bundle of conjugate-symmetric functions: ``R(ω̂)`` or ``C R(ω̂)``."""
        return VectorBundle(self.mesh.complex, self.transports, "R", metric=True)

    @cached_property
    def line_bundle(self) -> HermitianLineBundle:
        """The hermitian line bundle ``e^{iω̂}``, ``Ω = dω̂`` on the base (only if every ``s_ij = +1``).

        Raises
        ------
        InvalidConnectionError
            if some edge has ``s_ij = −1`` (use :attr:`bundle` or :attr:`double_cover`).
        """
        bad = self.edge_sign < 0
        if np.any(bad):
            raise InvalidConnectionError(
                f"the line field is not consistently oriented along {edge_name(self.mesh, int(np.argmax(bad)))} "
                f"({int(bad.sum())} such edges): there is no complex line bundle on the base; use the real rank-2 "
                "bundle form.bundle or the double cover form.double_cover")
        X = self.mesh.complex
        return HermitianLineBundle(X, np.exp(1j * self.omega), X.coboundary(1) @ self.omega)

    @cached_property
    def double_cover(self) -> DoubleCover:
        """The double cover of the non-branch part with the line bundle ``e^{iω̃}`` (see :class:`DoubleCover`)."""
        N = self.mesh.n_vertices
        E = self.mesh.complex.simplices(1)
        i, j = E[:, 0], E[:, 1]
        jj = np.where(self.edge_sign > 0, j, j + N)
        jt = np.where(self.edge_sign > 0, j + N, j)
        a = np.concatenate([i, i + N])
        b = np.concatenate([jj, jt])
        val = np.concatenate([self.omega, -self.omega])
        lifts = self.mesh.faces + N * (self.corner_sheet < 0)
        reg = ~self.is_branch
        tris = np.concatenate([lifts[reg], np.where(lifts[reg] >= N, lifts[reg] - N, lifts[reg] + N)])
        blocks = [np.sort(np.stack([a, b], 1), axis=1)]
        if tris.size:
            blocks.insert(0, np.sort(tris, axis=1))
        Xt = SimplicialComplex(blocks)
        om = np.zeros(Xt.n_simplices(1))
        om[Xt.index(1, np.stack([a, b], 1))] = np.where(a < b, val, -val)
        L = HermitianLineBundle(Xt, np.exp(1j * om), Xt.coboundary(1) @ om if Xt.dim >= 2 else np.zeros(0))
        lifts.setflags(write=False)
        pts = np.concatenate([self.mesh.points, self.mesh.points])
        pts.setflags(write=False)
        return DoubleCover(Xt, L, N, lifts, pts)

    def __repr__(self) -> str:
        nb = int(self.is_branch.sum())
        return f"StripeForm(n={self.n}, method={self.method!r}, branch_faces={nb}, {self.mesh!r})"


def stripe_form(
    surface: SurfaceMesh | TangentBundle,
    directions: ArrayLike,
    n: int = 1,
    *,
    frequency: ArrayLike | None = None,
    spacing: ArrayLike | None = None,
    method: str = "intrinsic",
    warn_aliasing: bool = True,
) -> StripeForm:
    """The stripe 1-form ω̂, the signs s and the bundles of a stripe-pattern problem.

    Parameters
    ----------
    surface : SurfaceMesh or TangentBundle
        The validated mesh (:func:`dhlb.mesh.validate_surface`); a TangentBundle of any power
        is used for its mesh (the stripe form uses the power-1 frames).
    directions : (N, 3) float (or (N, k, 3): the first direction is used), or a direction-field result
        One tangent direction per compact vertex or per row of the input V; its tangential part
        is used and normalized. Of a direction field (:func:`dhlb.fields.direction_field`) the first
        direction is used; on this very mesh its rescaled angle is ``arg u / n`` of the field's section.
    n : {1, 2}
        1: oriented directions (vector field); 2: lines (``X`` and ``−X`` are the same).
    frequency : float or (N,) float, > 0
        Stripes per unit length (period ``1/frequency``); ``ν = 2π · frequency``.
    spacing : float or (N,) float, > 0
        Alternatively: the period in units of the mean edge length.
    method : {"intrinsic", "extrinsic"}
        ω̂ from rescaled angles (Eq. 3.3, corrected) or from 3D vectors (Eq. 3.2).
    warn_aliasing : bool
        Warn if ``|ω̂| > π`` on some edge (stripes narrower than two edges).

    Returns
    -------
    StripeForm
        The directions, frequencies, 1-form, signs and bundles, on the power-1 tangent bundle of the mesh.

    Raises
    ------
    ShapeError, NonFiniteError
        Wrong shapes; NaN/inf directions or frequencies (naming the vertex).
    SectionZeroError
        A zero direction, or one normal to the surface (naming the vertex).
    InvalidParameterError
        ``surface`` is neither a :class:`~dhlb.mesh.SurfaceMesh` nor a :class:`~dhlb.mesh.TangentBundle`;
        n not in {1, 2}; a non-positive frequency or spacing (naming the vertex); both or neither of
        ``frequency`` / ``spacing``; an unknown method.

    Warns
    -----
    DhlbWarning
        On edges with ``|ω̂| > π`` the per-vertex values ``arg ψ`` alias; the texture coordinates
        (:func:`dhlb.stripes.texture_coordinates`, frequency adjustment of §4.3) stay correct.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> ((form.omega / np.pi).round(6) + 0.0).tolist()    # ν ⟨e, X⟩ on the edges 01 02 12 13 23, ν = 2π/4
    [0.5, 0.0, -0.5, 0.0, 0.5]
    """
    tb = as_tangent_bundle(surface, None, 1, caller="stripe_form")
    n = check_int(n, "n", 1, 2, why="1 is a vector field, 2 a line field")
    if method not in ("intrinsic", "extrinsic"):
        raise InvalidParameterError(f"method must be 'intrinsic' or 'extrinsic', got {method!r}")
    if (frequency is None) == (spacing is None):
        raise InvalidParameterError("give exactly one of frequency= (stripes per unit length) and spacing= "
                                    "(the period in mean edge lengths)")
    mesh = tb.mesh
    X, theta = checked_directions(tb, directions, method)
    if spacing is None:
        f = per_vertex_positive(mesh, frequency, "frequency")
    else:
        E = mesh.complex.simplices(1)
        mean_edge = float(np.mean(np.linalg.norm(mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1)))
        f = 1.0 / (per_vertex_positive(mesh, spacing, "spacing") * mean_edge)
    form = StripeForm(tb, X, theta, f, int(n), method)
    if warn_aliasing:
        big = np.abs(form.omega) > np.pi
        if np.any(big):
            e = int(np.argmax(np.abs(form.omega)))
            warnings.warn(
                f"the stripes are narrower than the mesh resolves on {int(big.sum())} edge(s): the largest phase "
                f"change is {abs(form.omega[e]):.3g} rad > π on {edge_name(mesh, e)} (a period of "
                f"{TWO_PI / abs(form.omega[e]):.3g} edge lengths). Per-vertex values alias there; the texture "
                "coordinates use the frequency adjustment of §4.3 and stay correct. Refine the mesh or lower the "
                "frequency if unwanted zeros appear", DhlbWarning, stacklevel=2)
    return form
