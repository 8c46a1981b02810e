"""Stepped tubes: the surface of revolution of the seed's part 2, Fig. 3, as a test and demo mesh.

A tube around the z axis made of *levels* of constant radius joined by C² transitions
(``r`` follows ``10t³ − 15t⁴ + 6t⁵`` over each transition). The mesh is a grid of rings (every
other ring turned by half a step), optionally with random jitter of the angles; the directions run
along the parallels, so stripes run along the meridians and a level of radius r carries
``2π r f`` stripes at frequency f. With ``f = N/(2π r₀)`` and radii proportional to the wanted
counts (e.g. 1, 1.5, 2 for 8, 12, 16 stripes) every level fits an integer number of stripes, and
between two levels ``|ΔN|`` dislocations are needed (seed: "judiciously placed branch points").

Examples
--------
>>> import numpy as np
>>> from dhlb.stripes.revolution import stepped_tube
>>> tube = stepped_tube((1.0, 1.5, 2.0), stripes=8, around=64)
>>> tube.points.shape[1], tube.levels.round(2).tolist(), tube.transitions.round(2).tolist()
(3, [[0.0, 2.5], [3.1, 5.6], [6.2, 8.7]], [[2.5, 3.1], [5.6, 6.2]])
>>> tube.stripes_per_level.tolist()                      # 2π r f with f = 8 / (2π · 1)
[8.0, 12.0, 16.0]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError

__all__ = ["SteppedTube", "stepped_tube"]


@dataclass(frozen=True)
class SteppedTube:
    """A stepped tube mesh with its directions and the data to check a stripe pattern on it.

    Made by :func:`stepped_tube`; every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    points : (k, 3) float array
        Vertex positions.
    faces : (m, 3) int array
        Triangles, outward oriented.
    directions : (k, 3) float array
        Unit vectors along the parallels (increasing angle θ).
    frequency : float
        Stripes per unit length.
    radii : (L,) float array
        Radius of each level, bottom to top.
    levels : (L, 2) float array
        The z-intervals of constant radius.
    transitions : (L−1, 2) float array
        The z-intervals of the transitions between levels.
    rings : (R, a) int array
        The vertex rows of every ring (bottom to top), in increasing θ.
    ring_heights : (R,) float array
        The height z of every ring.
    stripes_per_level : (L,) float array
        ``2π r f``, the number of stripes around each level.

    Examples
    --------
    >>> from dhlb.stripes.revolution import stepped_tube
    >>> t = stepped_tube((1.0, 2.0), stripes=4, around=32, level_length=1.0, transition_length=0.5)
    >>> t.rings.shape[1], t.middle_rings().tolist() == [int(abs(t.ring_heights - 0.5).argmin()),
    ...                                                 int(abs(t.ring_heights - 2.0).argmin())]
    (32, True)
    """

    points: np.ndarray
    faces: np.ndarray
    directions: np.ndarray
    frequency: float
    radii: np.ndarray
    levels: np.ndarray
    transitions: np.ndarray
    rings: np.ndarray
    ring_heights: np.ndarray
    stripes_per_level: np.ndarray

    def middle_rings(self) -> np.ndarray:
        """Row (into :attr:`rings`) of the ring nearest the middle of each level.

        Examples
        --------
        >>> from dhlb.stripes.revolution import stepped_tube
        >>> stepped_tube((1.0, 1.5), stripes=8, around=48).middle_rings().size
        2
        """
        mid = self.levels.mean(axis=1)
        return np.abs(self.ring_heights[None, :] - mid[:, None]).argmin(axis=1)

    def winding(self, psi, vertex_labels=None) -> np.ndarray:
        """Winding number of ψ around every ring (in increasing θ): the number of stripes there.

        ``psi`` holds one value per row of :attr:`points`, or per compact vertex with
        ``vertex_labels`` (``result.mesh.vertex_labels``) giving their rows.

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb.stripes.revolution import stepped_tube
        >>> t = stepped_tube((1.0,), stripes=5, around=40)
        >>> theta = np.arctan2(t.points[:, 1], t.points[:, 0])
        >>> np.round(t.winding(np.exp(5j * theta)), 9)[:3].tolist()
        [5.0, 5.0, 5.0]
        """
        z = np.asarray(psi, np.complex128)
        if vertex_labels is not None:
            full = np.full(len(self.points), np.nan + 0j)
            full[np.asarray(vertex_labels)] = z
            z = full
        if z.shape != (len(self.points),):
            raise InvalidParameterError(f"psi needs one value per tube vertex ({len(self.points)}), got {z.shape}")
        R = z[self.rings]
        return np.angle(np.roll(R, -1, axis=1) / R).sum(axis=1) / (2 * np.pi)


def _smootherstep(t):
    t = np.clip(t, 0.0, 1.0)
    return t ** 3 * (10.0 - 15.0 * t + 6.0 * t * t)


def stepped_tube(
    radii=(1.0, 1.5, 2.0),
    *,
    stripes: int = 8,
    around: int = 96,
    level_length: float = 2.5,
    transition_length: float = 0.6,
    rows: int | None = None,
    jitter: float = 0.0,
    seed: int = 0,
) -> SteppedTube:
    """A tube of levels with the given radii, joined by C² transitions (seed part 2, Fig. 3).

    Parameters
    ----------
    radii : sequence of float > 0
        Radius of each level, bottom to top.
    stripes : int >= 1
        Stripes around the first level; the frequency is ``stripes / (2π radii[0])``.
    around : int >= 8
        Vertices per ring.
    level_length : float > 0
        Length along z of each level.
    transition_length : float > 0
        Length along z of each transition.
    rows : int, optional
        Number of ring intervals along z, 2 .. 100000 (default: square-ish cells at the mean radius).
    jitter : float in [0, 0.45]
        Random angular displacement of every vertex, as a fraction of the angular step.
    seed : int
        Seed of the random generator of the jitter.

    Returns
    -------
    SteppedTube
        The mesh, its directions and the data to check a stripe pattern on it.

    Raises
    ------
    InvalidParameterError
        A parameter outside the ranges above (also ``stripes`` above 10000, ``around`` above
        100000), or more than 2e7 vertices.

    Examples
    --------
    >>> from dhlb.stripes.revolution import stepped_tube
    >>> t = stepped_tube((1.0, 2.0, 1.5), stripes=8, around=64, jitter=0.2, seed=1)
    >>> t.stripes_per_level.tolist(), len(t.faces) == 2 * 64 * (len(t.rings) - 1)
    ([8.0, 16.0, 12.0], True)
    """
    r = np.asarray(radii, dtype=float).reshape(-1)
    if r.size == 0 or not np.all(np.isfinite(r) & (r > 0)):
        raise InvalidParameterError(f"radii must be positive numbers, got {radii!r}")
    stripes, around = check_int(stripes, "stripes", 1, 10_000), check_int(around, "around", 8, 100_000)
    for name, v in (("level_length", level_length), ("transition_length", transition_length)):
        if not (np.isfinite(v) and v > 0):
            raise InvalidParameterError(f"{name} must be a positive number, got {v!r}")
    if not (np.isfinite(jitter) and 0 <= jitter <= 0.45):
        raise InvalidParameterError(f"jitter must be between 0 and 0.45, got {jitter!r}")
    L = r.size * level_length + (r.size - 1) * transition_length
    if rows is None:
        rows = max(2, round(L / (2 * np.pi * float(r.mean()) / around)))
    rows = check_int(rows, "rows", 2, 100_000)
    if (rows + 1) * around > 20_000_000:
        raise InvalidParameterError(f"rows × around = {(rows + 1) * around} vertices is too many (at most 2e7)")
    starts = np.arange(r.size) * (level_length + transition_length)
    levels = np.stack([starts, starts + level_length], axis=1)
    transitions = np.stack([levels[:-1, 1], levels[1:, 0]], axis=1)
    z = np.linspace(0.0, L, rows + 1)
    radius = np.full_like(z, r[0])
    for k in range(1, r.size):
        radius = radius + (r[k] - r[k - 1]) * _smootherstep((z - transitions[k - 1, 0]) / transition_length)
    step = 2 * np.pi / around
    theta = step * np.arange(around)[None, :] + 0.5 * step * (np.arange(rows + 1) % 2)[:, None]
    if jitter:
        theta = theta + jitter * step * np.random.default_rng(seed).uniform(-1, 1, theta.shape)
    R = np.broadcast_to(radius[:, None], theta.shape)
    Z = np.broadcast_to(z[:, None], theta.shape)
    points = np.stack([R * np.cos(theta), R * np.sin(theta), Z], axis=-1).reshape(-1, 3)
    directions = np.stack([-np.sin(theta), np.cos(theta), np.zeros_like(theta)], axis=-1).reshape(-1, 3)
    i = np.arange(rows)[:, None]
    j = np.arange(around)[None, :]
    a, b = i * around + j, i * around + (j + 1) % around
    c, d = (i + 1) * around + (j + 1) % around, (i + 1) * around + j
    even = (i % 2 == 0) & np.ones_like(j, bool)
    t1 = np.where(even[..., None], np.stack([a, b, d], -1), np.stack([a, b, c], -1))
    t2 = np.where(even[..., None], np.stack([b, c, d], -1), np.stack([a, c, d], -1))
    faces = np.concatenate([t1.reshape(-1, 3), t2.reshape(-1, 3)]).astype(np.int64)
    f = stripes / (2 * np.pi * r[0])
    return SteppedTube(points, faces, directions, float(f), r, levels, transitions,
                       np.arange((rows + 1) * around).reshape(rows + 1, around), z, 2 * np.pi * r * f)
