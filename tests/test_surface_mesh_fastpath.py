"""The fast validation path of validate_surface agrees with the general checks on random (bad) meshes.

Valid meshes skip the general manifold and orientation checks (distinct directed half-edges
imply an edge-manifold, consistently oriented surface; the vertex fans check the vertices). This
property test builds meshes with random defects — flipped faces, a third face on an edge, two
surfaces pinched at a vertex, holes, extra components, unused vertices — and checks that the
result (or the exception type and message) is the same with the fast path switched off.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import dhlb.mesh.surface as _surface
from dhlb.mesh import validate_surface
from tests.surface_meshes import grid, icosphere, torus

DEFECTS = ["none", "flip", "third-face", "pinch", "hole", "component", "unused", "flip-all-of-one"]


def _mesh(kind, defect, seed):
    rng = np.random.default_rng(seed)
    V, F = {"sphere": lambda: icosphere(1), "torus": lambda: torus(10, 6), "grid": lambda: grid(5, 4)}[kind]()
    V, F = np.array(V, float), np.array(F)
    if defect == "flip":
        k = rng.integers(1, 4)
        rows = rng.choice(len(F), k, replace=False)
        F[rows] = F[rows, ::-1]
    elif defect == "third-face":
        f = F[rng.integers(len(F))]
        V = np.vstack([V, V[f].mean(axis=0) + 0.3])
        F = np.vstack([F, [f[0], f[1], len(V) - 1]])
    elif defect == "pinch":  # a second copy sharing one vertex
        v = int(F[0, 0])
        F2 = np.where(F == v, v, F + len(V))
        V = np.vstack([V, V + [5.0, 0.0, 0.0]])
        F = np.vstack([F, F2])
    elif defect == "hole":
        F = np.delete(F, rng.choice(len(F), 2, replace=False), axis=0)
    elif defect == "component":
        V2, F2 = grid(3, 3)
        F = np.vstack([F, np.asarray(F2) + len(V)])
        V = np.vstack([V, np.asarray(V2, float) + [10.0, 0.0, 0.0]])
    elif defect == "unused":
        V = np.vstack([V, [[9.0, 9.0, 9.0]]])
    elif defect == "flip-all-of-one":
        F = F[:, ::-1].copy()
    perm = rng.permutation(len(F))  # any face order
    return V, F[perm]


def _outcome(V, F, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            m = validate_surface(V, F, **kw)
        except Exception as err:  # the type and message are what is compared
            return type(err).__name__, str(err)
    return "ok", (m.faces.tolist(), m.flipped.tolist(), m.vertex_labels.tolist(), m.triangle_of_face.tolist(),
                  m.boundary_halfedges.tolist(), m.euler_characteristic,
                  [m.complex.simplices(k).tolist() for k in range(3)], [m.complex.faces(k).tolist() for k in (1, 2)])


@settings(max_examples=60, deadline=None)
@given(kind=st.sampled_from(["sphere", "torus", "grid"]), defect=st.sampled_from(DEFECTS),
       seed=st.integers(0, 2**31), reorient=st.booleans())
def test_fast_path_agrees_with_the_general_checks(kind, defect, seed, reorient):
    V, F = _mesh(kind, defect, seed)
    fast = _outcome(V, F, reorient=reorient)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_surface, "_distinct_halfedges", lambda F, n: None)
        slow = _outcome(V, F, reorient=reorient)
    assert fast == slow


@pytest.mark.parametrize("defect", ["third-face", "pinch", "flip"])
def test_each_defect_is_refused_with_its_error(defect):
    V, F = _mesh("sphere", defect, 3)
    expected = {"third-face": "NonManifoldError", "pinch": "NonManifoldError",
                "flip": "InconsistentOrientationError"}[defect]
    assert _outcome(V, F)[0] == expected
