"""Analytic spectra: Landau levels of a uniform magnetic field on flat tori, and their O(h²) convergence.

On the unit flat 2-torus a line bundle of degree d with uniform curvature has the magnetic
Laplacian spectrum B(2k+1), B = 2πd/area, each level of multiplicity d. On the unit 3-torus with
the field B dx∧dy and trivial holonomy around the z-loop the lowest level is B again (k_z = 0) with
multiplicity d; the next one is 3B (when 3B < B + 4π²).
"""

import numpy as np
import pytest

from dhlb.fem import bundle_matrices, smallest_eigenpairs
from dhlb.linalg import SolverOptions
from tests.fem_fixtures import flat_torus_landau


def _levels(n, m, d, k):
    L, geo, B = flat_torus_landau(n, m, d)
    A, M = bundle_matrices(L, geo)
    res = smallest_eigenpairs(A, M, k=k, solver=SolverOptions(tol=1e-10))
    assert res.converged
    return res.eigenvalues / B


@pytest.mark.parametrize("d", [1, 2, 3])
def test_2d_lowest_landau_level_has_multiplicity_d(d):
    ev = _levels(2, 36, d, 2 * d + 1)
    assert np.all(np.abs(ev[:d] - 1) < 0.01)          # lowest level B, d-fold
    assert np.all(np.abs(ev[d:2 * d] - 3) < 0.05)     # next level 3B, d-fold
    assert ev[2 * d] > 4.5                            # then 5B
    assert np.ptp(ev[:d]) < 1e-8                      # degenerate to solver accuracy (magnetic translations)


def _rate(ms, errs):
    return np.polyfit(np.log(1.0 / np.asarray(ms)), np.log(np.asarray(errs)), 1)[0]


def test_2d_convergence_is_second_order():
    ms = [8, 16, 32]
    errs = [abs(_levels(2, m, 2, 1)[0] - 1) for m in ms]
    assert errs[0] > errs[1] > errs[2]
    assert 1.8 < _rate(ms, errs) < 2.3


def test_3d_lowest_level_multiplicity_and_second_order_convergence():
    ms = [8, 12, 16]
    errs = [abs(_levels(3, m, 1, 1)[0] - 1) for m in ms]
    assert errs[0] > errs[1] > errs[2]
    assert 1.8 < _rate(ms, errs) < 2.3
    # degree 2 on the same grid: the lowest level is 2-fold, the next is 3B, and the relative
    # error scales like B·h², i.e. doubles with the degree
    ev = _levels(3, 12, 2, 3)
    assert np.ptp(ev[:2]) < 1e-8
    assert 1.8 < (ev[0] - 1) / errs[1] < 2.2
    assert 2.9 < ev[2] < 3.2
