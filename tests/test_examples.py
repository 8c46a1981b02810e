"""dhlb.examples: named complexes against textbook homology, manifold checks, lens spaces and Künneth.

The combinatorics and geometry of the builders (f-vectors, grids, points, product numbering, mesh
wrappers, bad parameters) are tested in ``test_examples_builders.py``.
"""

from collections import Counter
from itertools import combinations
from itertools import product as iproduct
from math import comb, gcd

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb import examples as E
from dhlb.examples.quotients import _lens_cover
from dhlb.examples.surfaces import _DUNCE
from dhlb.topology.homology import homology


def H(X):
    """Homology as a list of (rank, torsion tuple)."""
    return [(h.rank, tuple(h.torsion)) for h in homology(X)]


Z, T2 = (1, ()), (0, (2,))
ZERO = (0, ())


def sphere_homology(n):
    return [(2, ())] if n == 0 else [Z] + [ZERO] * (n - 1) + [Z]


def rp_homology(n):
    out = [Z]
    for k in range(1, n + 1):
        if k == n:
            out.append(Z if n % 2 else ZERO)
        else:
            out.append(T2 if k % 2 else ZERO)
    return out


CASES = {
    "S0": (lambda: E.sphere(0), sphere_homology(0)),
    "S1": (lambda: E.sphere(1), sphere_homology(1)),
    "S2": (lambda: E.sphere(2), sphere_homology(2)),
    "S4": (lambda: E.sphere(4), sphere_homology(4)),
    "ball3": (lambda: E.ball(3), [Z, ZERO, ZERO, ZERO]),
    "torus": (E.torus, [Z, (2, ()), Z]),
    "klein": (E.klein_bottle, [Z, (1, (2,)), ZERO]),
    "RP2": (E.projective_plane, [Z, T2, ZERO]),
    "moebius": (E.moebius_strip, [Z, Z, ZERO]),
    "dunce": (E.dunce_hat, [Z, ZERO, ZERO]),
    "RP1": (lambda: E.projective_space(1), rp_homology(1)),
    "RP2_sd": (lambda: E.projective_space(2), rp_homology(2)),
    "RP3": (lambda: E.projective_space(3), rp_homology(3)),
    "RP4": (lambda: E.projective_space(4), rp_homology(4)),
    "L(1,0)=S3": (lambda: E.lens_space(1, 0), sphere_homology(3)),
    "L(2,1)=RP3": (lambda: E.lens_space(2, 1), [Z, T2, ZERO, Z]),
    "L(5,2)": (lambda: E.lens_space(5, 2), [Z, (0, (5,)), ZERO, Z]),
    "L(7,-3)": (lambda: E.lens_space(7, -3), [Z, (0, (7,)), ZERO, Z]),
    "L(12,5)": (lambda: E.lens_space(12, 5), [Z, (0, (12,)), ZERO, Z]),
    "cube_nd(3,3)": (lambda: E.cube_nd(3, 3), [Z, ZERO, ZERO, ZERO]),
    "S1xS1": (lambda: E.product(E.sphere(1), E.sphere(1)), [Z, (2, ()), Z]),
    "RP2xS1": (lambda: E.product(E.projective_plane(), E.sphere(1)), [Z, (1, (2,)), T2, ZERO]),
    "RP2xRP2": (lambda: E.product(E.projective_plane(), E.projective_plane()), [Z, (0, (2, 2)), T2, T2, ZERO]),
    "suspension(RP2)": (lambda: E.suspension(E.projective_plane()), [Z, ZERO, T2, ZERO]),
    "cone(klein)": (lambda: E.cone(E.klein_bottle()), [Z, ZERO, ZERO, ZERO]),
    "S1*S1=S3": (lambda: E.join(E.sphere(1), E.sphere(1)), sphere_homology(3)),
}


@pytest.mark.parametrize("name", list(CASES))
def test_textbook_homology(name):
    build, expected = CASES[name]
    assert H(build()) == expected


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_torus_nd_betti_numbers_are_binomial(n):
    assert H(E.torus_nd(n, 3)) == [(comb(n, k), ()) for k in range(n + 1)]


# ------------------------------------------------------------------ manifold / orientability
@pytest.mark.parametrize(
    "build, manifold, orientable, closed",
    [
        (lambda: E.sphere(3), True, True, True),
        (lambda: E.ball(3), True, True, False),
        (E.torus, True, True, True),
        (E.klein_bottle, True, False, True),
        (E.projective_plane, True, False, True),
        (E.moebius_strip, True, False, False),
        (E.dunce_hat, False, False, True),
        (lambda: E.projective_space(3), True, True, True),
        (lambda: E.projective_space(4), True, False, True),
        (lambda: E.lens_space(5, 2), True, True, True),
        (lambda: E.torus_nd(3, 3), True, True, True),
        (lambda: E.cube_nd(3, 2), True, True, False),
        (lambda: E.product(E.projective_plane(), E.sphere(1)), True, False, True),
        (lambda: E.product(E.moebius_strip(), E.sphere(1)), True, False, False),
    ],
)
def test_manifold_and_orientability(build, manifold, orientable, closed):
    X = build()
    assert X.is_manifold() is manifold
    assert X.is_orientable() is orientable
    if manifold:
        assert (X.boundary_complex() is None) is closed


def test_klein_bottle_by_classification():
    # a closed connected non-orientable surface with χ = 0 is the Klein bottle
    K = E.klein_bottle()
    assert K.is_manifold() and not K.is_orientable() and K.boundary_complex() is None
    assert K.connected_components()[0] == 1 and K.euler_characteristic == 0
    assert K.counts == (8, 24, 16)


def test_moebius_strip_has_one_boundary_circle_and_is_rp2_minus_a_disk():
    M = E.moebius_strip()
    B = M.boundary_complex()
    assert B.counts == (5, 5) and B.connected_components()[0] == 1
    rp2 = E.projective_plane().simplices(2)
    rest = rp2[~(rp2 == 0).any(axis=1)]
    relabelled = SimplicialComplex((2 * (rest - 1)) % 5)
    assert relabelled == M


def test_dunce_hat_structure():
    D = E.dunce_hat()
    tri = D.simplices(2)
    degree = Counter(e for t in tri.tolist() for e in combinations(t, 2))
    curve = {e for e, c in degree.items() if c == 3}
    assert curve == {(0, 1), (0, 2), (1, 2)}  # the curve a, three edges in three triangles each
    assert set(degree.values()) == {2, 3}
    for v in range(3, 8):  # interior points of the disk have circle links
        L = D.link(0, v)
        assert L.counts[0] == L.counts[1] and L.connected_components()[0] == 1
        assert all(c == 2 for c in Counter(L.simplices(1).ravel().tolist()).values())
    # the listed triples orient the disk: interior edges are traversed once each way, and the
    # curve edges reproduce the word a a a^{-1} (twice forwards, once backwards)
    directed = Counter((t[i], t[(i + 1) % 3]) for t in _DUNCE for i in range(3))
    for (u, w), c in directed.items():
        if (min(u, w), max(u, w)) in curve:
            assert (c, directed[(w, u)]) == ((2, 1) if (u, w) in {(0, 1), (1, 2), (2, 0)} else (1, 2))
        else:
            assert c == 1 and directed[(w, u)] == 1


def test_listed_torus_triangles_are_coherently_oriented():
    i = np.arange(7)
    rows = np.concatenate([np.stack([i, i + 1, i + 3], 1), np.stack([i, i + 3, i + 2], 1)]) % 7
    signs = SimplicialComplex.orientation_of(rows)
    T = E.torus()
    o = np.zeros(T.n_simplices(2), int)
    o[T.index(2, rows)] = signs
    assert abs(np.sum(o * T.orientation())) == T.n_simplices(2)


# ------------------------------------------------------------------ lens spaces
@pytest.mark.parametrize("p", range(1, 7))
def test_lens_space_is_an_honest_quotient(p):
    for q in range(p):
        if gcd(p, q) != 1:
            continue
        cover, quot = _lens_cover(p, q, all_cells=True)
        C, Q = SimplicialComplex(cover), SimplicialComplex(quot)
        # Z/p acts freely on every skeleton and the orbit space keeps all simplices distinct
        assert C.counts == tuple(p * c for c in Q.counts)
        L = E.lens_space(p, q)
        assert Q == L  # one tetrahedron per orbit gives the same complex
        assert L.counts[0] == 9 * p + 6 and L.counts[3] == 54 * p
    assert H(C) == sphere_homology(3) and C.is_manifold()  # the cover is a 3-sphere


def test_lens_space_2_1_is_rp3():
    assert H(E.lens_space(2, 1)) == H(E.projective_space(3))


# ------------------------------------------------------------------ products, joins, cones: Künneth, χ
def _primary(rank, torsion):
    out = []
    for t in torsion:
        p = 2
        while t > 1:
            q = 1
            while t % p == 0:
                t //= p
                q *= p
            if q > 1:
                out.append(q)
            p += 1
    return rank, sorted(out)


def _kunneth(HX, HY, n):
    """Integer homology of X × Y in degree n from the Künneth theorem, in primary form."""
    rank, tors = 0, []
    for i, j in iproduct(range(len(HX)), range(len(HY))):
        (a, TA), (b, TB) = _primary(*HX[i]), _primary(*HY[j])
        mixed = [gcd(s, t) for s in TA for t in TB if gcd(s, t) > 1]
        if i + j == n:  # H_i ⊗ H_j
            rank += a * b
            tors += TA * b + TB * a + mixed
        if i + j == n - 1:  # Tor(H_i, H_j)
            tors += mixed
    return rank, sorted(tors)


def _check_kunneth(X, Y):
    HX, HY, HP = H(X), H(Y), H(E.product(X, Y))
    assert len(HP) == len(HX) + len(HY) - 1
    for n, h in enumerate(HP):
        assert _primary(*h) == _kunneth(HX, HY, n), n


@pytest.mark.parametrize(
    "X, Y",
    [
        (E.projective_plane, E.projective_plane),
        (E.klein_bottle, lambda: E.sphere(1)),
        (E.projective_plane, E.moebius_strip),
        (E.dunce_hat, E.torus),
    ],
)
def test_kunneth_named(X, Y):
    _check_kunneth(X(), Y())


small_complexes = st.lists(
    st.lists(st.integers(0, 5), min_size=1, max_size=3, unique=True), min_size=1, max_size=7
).map(SimplicialComplex)


@settings(max_examples=25, deadline=None)
@given(small_complexes, small_complexes)
def test_kunneth_and_euler_characteristic_of_products(X, Y):
    P = E.product(X, Y)
    assert P.n_vertices == X.n_vertices * Y.n_vertices
    assert P.dim == X.dim + Y.dim
    assert P.euler_characteristic == X.euler_characteristic * Y.euler_characteristic
    _check_kunneth(X, Y)


@settings(max_examples=30, deadline=None)
@given(small_complexes, small_complexes)
def test_join_cone_suspension_euler_characteristics(X, Y):
    cx, cy = X.euler_characteristic, Y.euler_characteristic
    assert E.join(X, Y).euler_characteristic == cx + cy - cx * cy
    assert E.cone(X).euler_characteristic == 1
    assert E.suspension(X).euler_characteristic == 2 - cx
    C = E.cone(X)
    assert C.n_vertices == X.n_vertices + 1 and C.dim == X.dim + 1
    assert np.all(C.simplices(C.dim)[:, -1] == X.n_vertices)  # the apex is the last vertex


def test_suspension_of_spheres_are_spheres():
    for n in range(0, 3):
        S = E.suspension(E.sphere(n))
        assert H(S) == sphere_homology(n + 1) and S.is_manifold()


def test_every_shipped_data_file_is_recorded_with_its_origin():
    """Issue 42, point 11: the wheel ships only data whose origin and licence dhlb/data/README.md states."""
    import pathlib

    from dhlb.io.examples import EXAMPLES

    data = pathlib.Path(__file__).resolve().parents[1] / "dhlb" / "data"
    record = (data / "README.md").read_text(encoding="utf-8")
    shipped = sorted(p.name for p in data.iterdir() if p.name != "README.md" and not p.name.startswith("."))
    assert sorted(EXAMPLES) == shipped
    for name in shipped:
        row = next((line for line in record.splitlines() if line.startswith(f"| `{name}`")), None)
        assert row is not None, f"{name} is shipped but not in dhlb/data/README.md"
        assert any(w in row or w in record.split("| file |")[0] for w in ("CC0", "MIT", "generated by dhlb",
                                                                            "dhlb's own")), name
    assert "octopus" not in " ".join(shipped)
