"""Seed part 2, Fig. 3: on a surface of revolution whose radius steps between levels, a stripe pattern
along the parallels must change its number of stripes, and does so by edge dislocations (zeros of ψ).

The mesh is an irregular (random Delaunay) triangulation: on an exactly rotation-symmetric mesh the
eigenvector is a single Fourier mode and the symmetry, not the geometry, decides the pattern.

What holds (and is asserted): the net index of the dislocations is the change in the number of
stripes between the bottom and the top level, they have one sign (up to one extra ± pair), and there
are none on the top level. What does not hold exactly: the smallest eigenvector *localizes* on the level
where the frequency fits best (here the top one: |ψ| there is ~50× larger than on the middle level),
so the dislocations may sit anywhere on the low-amplitude lower levels rather than in the steps
themselves (``docs/stripes.md``). This is the relaxed ``section="eigenvector"``; the default
``section="unit"`` keeps every level's count (``tests/test_stripes_section.py``).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.spatial

from dhlb.stripes import SectionOptions, StripeOptions, stripe_pattern

LEVELS = (1.0, 2.0, 3.0)          # radii of the three levels: h ∈ [0, 1), [1, 2), [2, 3]


def _radius(h):
    return 1.0 + 0.5 * np.tanh((h - 1) * 8) + 0.5 * np.tanh((h - 2) * 8) + 1.0


def _stepped_surface(n_points=4000, seed=1):
    rng = np.random.default_rng(seed)
    th, h = rng.uniform(0, 2 * np.pi, n_points), rng.uniform(0, 3, n_points)
    ring = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    P = np.r_[np.c_[th, h], np.c_[ring, np.zeros(60)], np.c_[ring, np.full(60, 3.0)]]
    n = len(P)
    ext = np.r_[P, P + [2 * np.pi, 0], P - [2 * np.pi, 0]]     # periodic in θ
    tri = scipy.spatial.Delaunay(ext).simplices
    c = ext[tri].mean(axis=1)
    tri = tri[(c[:, 0] >= 0) & (c[:, 0] < 2 * np.pi)]
    a = ext[tri]
    det = (a[:, 1, 0] - a[:, 0, 0]) * (a[:, 2, 1] - a[:, 0, 1]) - (a[:, 1, 1] - a[:, 0, 1]) * (a[:, 2, 0] - a[:, 0, 0])
    F = np.where((det < 0)[:, None], tri[:, [0, 2, 1]], tri) % n
    R = _radius(P[:, 1])
    V = np.c_[R * np.cos(P[:, 0]), R * np.sin(P[:, 0]), P[:, 1]]
    X = np.c_[-np.sin(P[:, 0]), np.cos(P[:, 0]), np.zeros(n)]      # along the parallels
    return V, F, X


@pytest.mark.parametrize("spacing", [0.5, 0.7])
def test_dislocations_sit_where_the_number_of_stripes_changes(spacing):
    V, F, X = _stepped_surface()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = stripe_pattern(V, F, X, frequency=1.0 / spacing,
                             options=StripeOptions(section=SectionOptions(kind="eigenvector")))
    zeros = res.to_json()["zero_faces"]
    h = np.array([V[F[z["face"]], 2].mean() for z in zeros])
    index = np.array([z["index"] for z in zeros])
    stripes = [2 * np.pi * r / spacing for r in LEVELS]               # stripes that fit around each level
    # net index: the number of stripes grows by about Δ from the bottom to the top level (the winding
    # numbers on the two boundary circles are the nearest integers), all with the same sign up to
    # at most one extra ± pair
    delta = stripes[-1] - stripes[0]
    assert abs(abs(int(index.sum())) - delta) <= 1.5, (int(index.sum()), delta)
    assert np.sum(index == np.sign(index.sum())) >= len(index) - 2
    assert np.all(h < 2.3), h                                         # none on the top level, where ψ lives
    top = V[:, 2] > 2.3
    mid = np.abs(V[:, 2] - 1.5) < 0.3
    assert np.abs(res.psi[top]).mean() > 10 * np.abs(res.psi[mid]).mean()   # the localization described above
