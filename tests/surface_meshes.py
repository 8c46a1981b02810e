"""Small generated triangle meshes for the surface tests (icosphere, ellipsoid, torus, cylinder, grid)."""

from __future__ import annotations

import numpy as np


def icosphere(level: int = 2, radius: float = 1.0):
    """Loop-subdivided icosahedron projected to the sphere; outward orientation."""
    t = (1 + 5**0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t],
                  [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
                  [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
                  [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    for _ in range(level):
        E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
        keys, inv = np.unique(E[:, 0] * len(V) + E[:, 1], return_inverse=True)   # integer keys: fast at level 8
        mid = (V[keys // len(V)] + V[keys % len(V)]) / 2
        mid /= np.linalg.norm(mid, axis=1, keepdims=True)
        m = len(F)
        a, b, c = (inv.ravel()[k * m:(k + 1) * m] + len(V) for k in range(3))
        V = np.vstack([V, mid])
        F = np.concatenate([np.stack([F[:, 0], a, c], 1), np.stack([a, F[:, 1], b], 1),
                            np.stack([c, b, F[:, 2]], 1), np.stack([a, b, c], 1)])
    return radius * V, F


def ellipsoid(level: int = 4, axes=(3.0, 2.0, 1.0)):
    V, F = icosphere(level)
    return V * np.asarray(axes, float), F


def torus(nu: int = 24, nv: int = 12, R: float = 2.0, r: float = 0.7):
    """Regular torus grid, outward orientation (the generator of dhlb.strategies)."""
    from dhlb.strategies.meshes import _torus

    return _torus(nu, nv, R, r)


def cylinder(nu: int = 32, nz: int = 8, R: float = 1.0, h: float = 2.0):
    """Open cylinder of radius R, outward normals, two boundary circles."""
    i, j = np.meshgrid(np.arange(nu), np.arange(nz + 1), indexing="ij")
    u = 2 * np.pi * i / nu
    V = np.stack([R * np.cos(u), R * np.sin(u), h * j / nz], -1).reshape(-1, 3)
    idx = lambda a, b: (a % nu) * (nz + 1) + b  # noqa: E731
    i, j = i[:, :nz], j[:, :nz]
    a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return V, F


def grid(nx: int = 6, ny: int = 5, z=None):
    """Triangulated rectangle [0, nx] x [0, ny] (counterclockwise), optional height function z(x, y)."""
    x, y = np.meshgrid(np.arange(nx + 1.0), np.arange(ny + 1.0), indexing="ij")
    zz = np.zeros_like(x) if z is None else z(x, y)
    V = np.stack([x, y, zz], -1).reshape(-1, 3)
    idx = lambda a, b: a * (ny + 1) + b  # noqa: E731
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return V, F
