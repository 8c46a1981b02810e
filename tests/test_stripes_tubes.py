"""The seed's Fig. 3 as a property (issue 28): on *random* stepped tubes every level keeps its own
stripe count, joined by exactly |ΔN| dislocations in each transition — n = 1 and the n = 2 double cover.

The tubes are drawn where the claim is the unit energy's minimum, not an accident of the start:

* every level wants a different integer count ``N_k = 2π r_k f`` (the frequency f is drawn with the
  first level's radius; the other radii follow from their counts);
* levels at least three times as long as their largest radius. A level of the wrong count pays
  ``(ΔN / r)²`` per unit area over its whole length, a dislocation a fixed core energy; on levels
  as long as their radius the wrong count can be cheaper (measured: radii 1 / 1.75 / 1.5 with
  2.5-long levels keep 12 stripes on the middle level at a lower unit energy than the 14 that fit);
* at least six vertices per stripe around the widest level (fewer alias: 24 stripes on 64 vertices
  came out as 19 or 20).
"""

from __future__ import annotations

import warnings

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dhlb.stripes import stripe_pattern
from dhlb.stripes.revolution import stepped_tube


@st.composite
def tubes(draw):
    """A stepped tube with a different integer stripe count on each of its 2–4 levels."""
    counts = draw(st.lists(st.integers(5, 10), min_size=2, max_size=4, unique=True))
    r0 = draw(st.floats(0.8, 1.25))
    radii = np.array(counts) * r0 / counts[0]
    spacing = 2 * np.pi * r0 / counts[0]                            # 1 / f
    around = max(48, 6 * max(counts))
    level, transition = draw(st.floats(8.0, 9.0)) * radii.max(), draw(st.floats(0.5, 1.0)) * spacing
    length = len(counts) * level + (len(counts) - 1) * transition
    return stepped_tube(
        tuple(radii),
        stripes=counts[0],
        around=around,
        level_length=level,
        transition_length=transition,
        rows=round(length / (4 * np.pi * radii.mean() / around)),   # cells twice as long as wide
        jitter=draw(st.sampled_from([0.0, 0.25])),
        seed=draw(st.integers(0, 2**16)),
    )


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(tube=tubes(), n=st.sampled_from([1, 2]))
def test_every_level_keeps_its_count_and_each_transition_gets_delta_n_dislocations(tube, n):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = stripe_pattern(tube.points, tube.faces, tube.directions, frequency=tube.frequency, n=n)
    want = tube.stripes_per_level
    assert np.allclose(want, np.round(want), atol=1e-9)             # each level fits an integer count
    w = tube.winding(res.psi, res.mesh.vertex_labels)
    assert np.allclose(w[tube.middle_rings()], want, atol=1e-9), (w[tube.middle_rings()], want)
    rows = res.mesh.face_rows[res.zero_faces]
    z = tube.points[tube.faces[rows], 2]                            # heights of the zero faces' corners
    low, high = z.min(axis=1), z.max(axis=1)
    index = res.zero_index[res.zero_faces]
    dN = np.round(np.diff(want)).astype(int)
    # a dislocation is located to its core, about one stripe spacing 1/f: measured, the zeros sit at the
    # narrow end of a transition, in 1 of ~600 random tubes more than half a spacing before it
    slack = 1.0 / tube.frequency
    band = tube.transitions + [-slack, slack]
    meets = (high[:, None] >= band[:, 0]) & (low[:, None] <= band[:, 1])
    assert np.all(meets.sum(axis=1) == 1), (low, high, band)         # no zero inside a level
    assert np.array_equal(meets.sum(axis=0), np.abs(dN)), (meets.sum(axis=0), dN)
    for k in range(dN.size):                                         # Stokes on the band: index −sign(ΔN)
        assert np.all(index[meets[:, k]] == -np.sign(dN[k])), (k, index[meets[:, k]])
    it = res.iteration
    assert it.converged and it.iterations < 100                      # stopped because the iterate stopped moving
    assert res.eigenvalue <= res.unit_energy <= it.start_energy
