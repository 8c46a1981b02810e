"""Hand-made complexes with known integral homology, shared by the homology and cohomology tests.

``EXPECTED[name] = (simplices, [(rank, torsion) of H_0, H_1, ...])``; ``obj``, ``boundaries`` and
``coboundary`` give exact object-dtype matrices.
"""

import itertools

import numpy as np
import scipy.sparse as sp


def polygon_word(word, n=3):
    """A triangle-free polygon whose sides, read around the boundary, are the letters of ``word``
    (``'a'`` or ``'A'`` = a⁻¹), every side glued to one loop ``a`` cut into ``n`` edges.  The disc is
    an annulus of fresh vertices ``q`` plus a cone from a centre, so the result is simplicial."""
    loop = list(range(n))
    boundary = []
    for letter in word:
        boundary += loop if letter == "a" else [loop[0]] + loop[:0:-1]
    L = len(boundary)
    q = [n + t for t in range(L)]
    centre = n + L
    tris = []
    for t in range(L):
        p0, p1 = boundary[t], boundary[(t + 1) % L]
        tris += [(p0, p1, q[t]), (p1, q[(t + 1) % L], q[t]), (centre, q[t], q[(t + 1) % L])]
    return tris


CIRCLE = [(0, 1), (1, 2), (0, 2)]
SPHERE = [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]
TORUS7 = [(i, (i + 1) % 7, (i + 3) % 7) for i in range(7)] + [(i, (i + 2) % 7, (i + 3) % 7) for i in range(7)]
RP2 = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 1, 5), (1, 2, 4), (2, 3, 5), (1, 3, 4), (1, 3, 5), (2, 4, 5)]
# Klein bottle: 3×3 grid of squares (vertex (i, j) = 3i + j), the j-direction glued with a flip i -> -i
KLEIN = []
for _i in range(3):
    for _j in range(3):
        def _lab(i, j):
            return ((-i if j >= 3 else i) % 3) * 3 + j % 3
        _a, _b, _c, _d = _lab(_i, _j), _lab(_i + 1, _j), _lab(_i + 1, _j + 1), _lab(_i, _j + 1)
        KLEIN += [(_a, _b, _c), (_a, _c, _d)]
DUNCE_HAT = polygon_word("aaA")
PSEUDO_PROJECTIVE_3 = polygon_word("aaa")  # H_1 = Z/3
S3 = [tuple(c) for c in itertools.combinations(range(5), 4)]

EXPECTED = {
    "point": ([(0,)], [(1, ())]),
    "two points": ([(0,), (1,)], [(2, ())]),
    "circle": (CIRCLE, [(1, ()), (1, ())]),
    "S2": (SPHERE, [(1, ()), (0, ()), (1, ())]),
    "torus": (TORUS7, [(1, ()), (2, ()), (1, ())]),
    "RP2": (RP2, [(1, ()), (0, (2,)), (0, ())]),
    "Klein bottle": (KLEIN, [(1, ()), (1, (2,)), (0, ())]),
    "dunce hat": (DUNCE_HAT, [(1, ()), (0, ()), (0, ())]),
    "Z/3 Moore space": (PSEUDO_PROJECTIVE_3, [(1, ()), (0, (3,)), (0, ())]),
    "S3": (S3, [(1, ()), (0, ()), (0, ()), (1, ())]),
    "torus ∨ circle ⊔ point": (TORUS7 + [(0, 7), (7, 8), (0, 8), (9,)], [(2, ()), (3, ()), (1, ())]),
}


def obj(A):
    return np.asarray(A.toarray() if sp.issparse(A) else A, dtype=object)


def boundaries(X):
    return [X.boundary(k) for k in range(X.dim + 1)]


def coboundary(X, k):
    """d_k = ∂_{k+1}ᵀ (zero map above the top dimension)."""
    if k + 1 <= X.dim:
        return obj(X.boundary(k + 1).T)
    return np.zeros((0, X.n_simplices(k)), dtype=object)
