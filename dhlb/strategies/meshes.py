"""A hypothesis strategy for embedded, consistently oriented closed triangle meshes of known genus.

Three families, all with outward orientation and without degenerate triangles:

* genus 0: UV spheres (``nu`` longitudes, ``nv`` latitude bands) with radially perturbed
  vertices. Radial scaling by positive factors keeps ``det(v_0, v_1, v_2) > 0`` for every triangle,
  so the perturbed mesh is still a radial graph over the sphere, hence embedded.
* genus 1: tori of revolution (an ``nu × nv`` grid) with the tube radius perturbed by at most 20 %.
* any genus g: the boundary of a board of ``(2g+1) × 3 × 1`` voxels with ``g`` square holes
  (each voxel cut into ``sx × sy × sz`` cells), quads split along a random diagonal, vertices
  moved by at most 5 % of a cell. No two filled cells touch along an edge or vertex only, so the
  boundary is a closed surface; its Euler characteristic is ``2 − 2g`` (counted in
  ``tests/test_strategies_proofs.py``).
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError

__all__ = ["surface_meshes"]

_MAX_OPTIONS = 4000


# ---------------------------------------------------------------------------- face counts
def _board_squares(g: int, sx: int, sy: int, sz: int) -> int:
    """Unit squares on the boundary of the (2g+1) × 3 × 1 board with g holes, cells sx × sy × sz."""
    return 2 * (5 * g + 3) * sx * sy + (6 + 2 * g) * sy * sz + (6 * g + 2) * sx * sz


def _options(genus: int, lo: int, hi: int) -> list:
    """All constructions of the given genus with lo <= faces <= hi, sorted by face count."""
    out = []
    if genus == 0:
        for nu in range(3, hi // 2 + 1):
            for nv in range(2, hi // (2 * nu) + 2):
                f = 2 * nu * (nv - 1)
                if lo <= f <= hi and nu <= 4 * nv + 4 and nv <= 4 * nu:
                    out.append((f, "sphere", (nu, nv)))
    if genus == 1:
        for nu in range(3, hi // 6 + 1):
            for nv in range(3, hi // (2 * nu) + 1):
                f = 2 * nu * nv
                if lo <= f <= hi and nv <= nu <= 4 * nv:
                    out.append((f, "torus", (nu, nv)))
    for sx in range(1, 9):
        for sy in range(1, 9):
            for sz in range(1, 9):
                f = 2 * _board_squares(genus, sx, sy, sz)
                if lo <= f <= hi:
                    out.append((f, "board", (sx, sy, sz)))
    out.sort(key=lambda o: (o[0], o[1], o[2]))
    if len(out) > _MAX_OPTIONS:  # keep an even spread over the face counts
        out = [out[i] for i in np.linspace(0, len(out) - 1, _MAX_OPTIONS).astype(int)]
    return out


# ---------------------------------------------------------------------------- constructions
def _uv_sphere(nu: int, nv: int):
    th = np.pi * np.arange(1, nv) / nv
    ph = 2 * np.pi * np.arange(nu) / nu
    ring = np.stack([np.sin(th)[:, None] * np.cos(ph), np.sin(th)[:, None] * np.sin(ph),
                     np.cos(th)[:, None] * np.ones(nu)], -1).reshape(-1, 3)
    V = np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]])
    idx = lambda a, b: 1 + a * nu + b % nu  # noqa: E731  (ring a = 0 .. nv-2)
    F = []
    for b in range(nu):
        F.append((0, idx(0, b), idx(0, b + 1)))
        F.append((len(V) - 1, idx(nv - 2, b + 1), idx(nv - 2, b)))
        for a in range(nv - 2):
            F.append((idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)))
            F.append((idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)))
    return V, np.asarray(F, dtype=np.int64)


def _torus(nu: int, nv: int, R: float = 1.0, r: float = 0.4):
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    u, v = 2 * np.pi * i / nu, 2 * np.pi * j / nv
    V = np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], -1).reshape(-1, 3)
    idx = lambda a, b: (a % nu) * nv + (b % nv)  # noqa: E731
    a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return V, F.astype(np.int64)


def _board(g: int, sx: int, sy: int, sz: int, diagonals: np.ndarray | None):
    """Boundary quads of the voxel board, split into triangles; outward orientation."""
    occ = np.ones((2 * g + 1, 3, 1), dtype=bool)
    occ[2 * np.arange(g) + 1, 1, 0] = False
    occ = np.kron(occ, np.ones((sx, sy, sz), dtype=bool))
    occ = np.pad(occ, 1)
    shape = np.array(occ.shape) + 1  # grid points
    quads = []
    for a in range(3):
        b, c = (a + 1) % 3, (a + 2) % 3
        lo = [slice(None)] * 3
        hi = [slice(None)] * 3
        lo[a], hi[a] = slice(0, -1), slice(1, None)
        plus = occ[tuple(lo)] & ~occ[tuple(hi)]  # filled below, empty above: normal +a
        minus = ~occ[tuple(lo)] & occ[tuple(hi)]
        for mask, sign in ((plus, 1), (minus, -1)):
            cells = np.argwhere(mask)
            p = cells.copy()
            p[:, a] += 1  # the face lies on the plane x_a = i + 1
            corners = []
            for db, dc in ((0, 0), (1, 0), (1, 1), (0, 1)):  # counterclockwise about +a (b × c = a)
                q = p.copy()
                q[:, b] += db
                q[:, c] += dc
                corners.append(np.ravel_multi_index(q.T, shape))
            Q = np.stack(corners, 1)
            quads.append(Q if sign > 0 else Q[:, ::-1])
    Q = np.concatenate(quads)
    used, Q = np.unique(Q, return_inverse=True)
    Q = Q.reshape(-1, 4)
    V = np.stack(np.unravel_index(used, shape), 1).astype(np.float64)
    flip = np.zeros(len(Q), bool) if diagonals is None else diagonals[: len(Q)]
    T1 = np.where(flip[:, None], Q[:, [0, 1, 3]], Q[:, [0, 1, 2]])
    T2 = np.where(flip[:, None], Q[:, [1, 2, 3]], Q[:, [0, 2, 3]])
    F = np.concatenate([T1, T2]).astype(np.int64)
    scale = np.array([sx, sy, sz], dtype=np.float64)
    return V, F, scale


@st.composite
def _mesh(draw, genus: int, lo: int, hi: int):
    options = _options(genus, lo, hi)
    _, family, par = draw(st.sampled_from(options))
    noise = draw(st.sampled_from([0.0, 0.5, 1.0]))
    shuffle = draw(st.booleans())
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if family == "sphere":
        V, F = _uv_sphere(*par)
        V = V * (1 + 0.3 * noise * rng.uniform(-1, 1, size=(len(V), 1)))
    elif family == "torus":
        V, F = _torus(*par)
        nu, nv = par
        u = np.repeat(2 * np.pi * np.arange(nu) / nu, nv)  # vertex i * nv + j lies on meridian i
        core = np.stack([np.cos(u), np.sin(u), np.zeros_like(u)], 1)
        V = core + (V - core) * (1 + 0.2 * noise * rng.uniform(-1, 1, size=(len(V), 1)))
    else:
        diag = rng.random(4 * _board_squares(genus, *par)) < 0.5 if draw(st.booleans()) else None
        V, F, scale = _board(genus, *par, diag)
        V = V + 0.05 * noise * rng.uniform(-1, 1, size=V.shape)
        V = (V - V.mean(0)) / scale  # one voxel per unit
    if shuffle:
        perm = rng.permutation(len(V))
        inv = np.empty_like(perm)
        inv[perm] = np.arange(len(V))
        V, F = V[perm], inv[F]
        F = F[rng.permutation(len(F))]
        roll = rng.integers(0, 3, size=len(F))  # cyclic rotations keep the orientation
        F = np.stack([F[np.arange(len(F)), (roll + s) % 3] for s in range(3)], 1)
    return np.ascontiguousarray(V, dtype=np.float64), np.ascontiguousarray(F, dtype=np.int64), genus


def surface_meshes(genus: int | None = None, min_faces: int = 1, max_faces: int = 400) -> st.SearchStrategy:
    """Embedded, consistently (outward) oriented closed triangle meshes ``(V, F, genus)``.

    Parameters
    ----------
    genus : int, optional
        The genus; default: 0, 1 or 2 (those that fit the face bounds).
    min_faces, max_faces : int
        Bounds on the number of triangles. The smallest meshes have 6 (genus 0), 18 (genus 1)
        and ``36 g + 28`` triangles (genus g >= 2).

    Returns
    -------
    SearchStrategy of (ndarray, ndarray, int)
        ``V`` (n, 3) float64, ``F`` (m, 3) int64 rows of V, outward orientation, every vertex
        used, no degenerate triangle; perturbed UV spheres, perturbed tori of revolution and
        voxel boards with ``genus`` holes; vertices and faces optionally shuffled. Shrinks
        towards the smallest unperturbed mesh.

    Raises
    ------
    InvalidParameterError
        a negative genus, bad bounds, or no mesh of that genus within the bounds.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> from dhlb.mesh import validate_surface
    >>> @settings(max_examples=20)
    ... @given(surface_meshes(max_faces=200))
    ... def genus_from_euler(mesh):
    ...     V, F, g = mesh
    ...     assert validate_surface(V, F).euler_characteristic == 2 - 2 * g
    >>> genus_from_euler()
    """
    min_faces, max_faces = check_int(min_faces, "min_faces", 0), check_int(max_faces, "max_faces", 0)
    if max_faces < min_faces:
        raise InvalidParameterError(f"max_faces ({max_faces}) < min_faces ({min_faces})")
    if genus is not None:
        genus = check_int(genus, "genus", 0)
    genera = [int(genus)] if genus is not None else [0, 1, 2]
    genera = [g for g in genera if _options(g, int(min_faces), int(max_faces))]
    if not genera:
        raise InvalidParameterError(
            f"no mesh of genus {genus if genus is not None else '0, 1 or 2'} has between {min_faces} and "
            f"{max_faces} triangles (genus g >= 2 needs at least 36 g + 28); raise max_faces"
        )
    return st.sampled_from(genera).flatmap(lambda g: _mesh(g, int(min_faces), int(max_faces)))
