"""Fast local FEM matrices (n = 2, 3) against the reference ``local_matrices`` and 40-digit mpmath."""

from math import factorial

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import errors
from dhlb.fem import _fast_local
from dhlb.fem._fast_local import fast_local_entries, fast_local_matrices
from dhlb.fem._fast_moments import PAT3, moments_3d, phi_2d
from dhlb.fem._local_data import local_edges, local_gauge_connection
from dhlb.fem._local_matrices import local_matrices

TOL = 1e-13


def _simplices(rng, n, m, jitter=0.3):
    """Well-shaped random simplices: Gram matrices of barycentric gradients and volumes."""
    base = np.vstack([np.zeros(n), np.eye(n)])
    P = rng.uniform(0.3, 3.0, (m, 1, 1)) * (base + jitter * rng.standard_normal((m, n + 1, n)))
    D = P[:, 1:] - P[:, :1]
    grads = np.empty((m, n + 1, n))
    grads[:, 1:] = np.transpose(np.linalg.inv(D), (0, 2, 1))
    grads[:, 0] = -grads[:, 1:].sum(1)
    gram = grads @ np.transpose(grads, (0, 2, 1))
    return gram, np.abs(np.linalg.det(D)) / factorial(n)


def _curvature(rng, n, m, scales, kinds):
    """Closed curvature per simplex with a magnitude per row and special coincidences (kinds)."""
    if n == 2:
        om = (scales * rng.uniform(-1, 1, m))[:, None]
        om[kinds == 1] = 0.0
        return om
    o = scales[:, None] * rng.uniform(-1, 1, (m, 3))
    o[kinds == 1] = 0.0                                   # exactly flat
    near = kinds == 2                                     # Ω_012 ≈ Ω_013: coinciding phases of pair (0, 1)
    o[near, 1] = o[near, 0] * (1 + 1e-9 * rng.uniform(-1, 1, near.sum()))
    o[kinds == 3, 1] = 0.0                                # one phase of pair (0, 1) exactly 0
    opp = kinds == 4                                      # opposite phases
    o[opp, 1] = -o[opp, 0]
    o[kinds == 5, 2] = o[kinds == 5, 0] + o[kinds == 5, 1]   # Ω_123 = 0 and more coincidences
    return np.column_stack([o[:, 0], o[:, 1], o[:, 2], o[:, 0] - o[:, 1] + o[:, 2]])


def _random_gauge(rng, om, n):
    e = local_edges(n)
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, (om.shape[0], n + 1)))
    return local_gauge_connection(om, dim=n) * g[:, e[:, 0]] * np.conj(g[:, e[:, 1]])


def _rel_err(X, R):
    """Largest |X - R| per simplex relative to max |R| of that simplex."""
    return (np.abs(X - R).max(axis=(1, 2)) / np.abs(R).max(axis=(1, 2))).max()


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.sampled_from([2, 3]), m=st.integers(1, 40),
       log_lo=st.floats(-9, 1.7), log_hi=st.floats(-9, 1.7), gauge=st.booleans())
def test_agrees_with_local_matrices(seed, n, m, log_lo, log_hi, gauge):
    """Random simplices, curvature per face between 1e-9 and 50, mixed in one batch, special phases."""
    rng = np.random.default_rng(seed)
    gram, vol = _simplices(rng, n, m)
    scales = 10.0 ** rng.uniform(min(log_lo, log_hi), max(log_lo, log_hi), m)
    om = _curvature(rng, n, m, scales, rng.integers(0, 6, m))
    r = _random_gauge(rng, om, n) if gauge else None
    M, A = fast_local_matrices(gram, vol, om, r)
    Mr, Ar = local_matrices(gram, vol, om, r)
    assert M.shape == A.shape == (m, n + 1, n + 1) and M.dtype == A.dtype == complex
    assert _rel_err(M, Mr) < TOL and _rel_err(A, Ar) < TOL
    Mu, Au = fast_local_matrices(gram, vol, om, r, check=False)
    assert np.array_equal(Mu, M) and np.array_equal(Au, A)


@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("value", [0.0, 1e-300, 1e-9, 0.25, 0.2500001, 2.999, 3.0, 3.001, 7.0, 50.0, 1e4])
def test_thresholds_and_extremes(n, value):
    """Every evaluation branch and its boundaries (series / recurrence), both signs, against the reference."""
    rng = np.random.default_rng(7)
    gram, vol = _simplices(rng, n, 8)
    if n == 2:
        om = value * np.array([1, -1, 1, -1, 1, -1, 1, -1.0])[:, None]
    else:
        o = value * np.array([[1, 1, 1], [1, -1, 0.5], [-1, 1e-3, 1], [0.5, 1, -1], [1, 0, 0],
                              [0, 1, 0], [1, 1 + 1e-12, 1 - 1e-12], [-1, -1, 0.99]])
        om = np.column_stack([o[:, 0], o[:, 1], o[:, 2], o[:, 0] - o[:, 1] + o[:, 2]])
    M, A = fast_local_matrices(gram, vol, om)
    Mr, Ar = local_matrices(gram, vol, om)
    assert _rel_err(M, Mr) < TOL and _rel_err(A, Ar) < TOL


@pytest.mark.parametrize("n", [2, 3])
def test_flat_gives_p1_mass_and_stiffness(n):
    gram, vol = _simplices(np.random.default_rng(n), n, 5)
    M, A = fast_local_matrices(gram, vol, np.zeros((5, 1 if n == 2 else 4)))
    p1 = (np.ones((n + 1, n + 1)) + np.eye(n + 1)) / ((n + 1) * (n + 2))
    assert np.abs(M - vol[:, None, None] * p1).max() < 1e-16
    assert np.abs(A - vol[:, None, None] * gram).max() <= 4e-16 * np.abs(A).max()


def _mp_dd(nodes):
    """exp at the (confluent) nodes: corner of the exponential of the Opitz matrix, 40 digits."""
    T = mp.zeros(len(nodes))
    for i, z in enumerate(nodes):
        T[i, i] = z
        if i + 1 < len(nodes):
            T[i, i + 1] = 1
    return complex(mp.expm(T)[0, len(nodes) - 1])


@pytest.mark.parametrize("scale", [1e-9, 0.01, 0.3, 1.0, 2.9, 3.2, 8.0, 50.0])
def test_moments_against_mpmath(scale):
    """The ten 3-D moment functions and the five 2-D φ's, relative error against 40 digits."""
    mp.mp.dps = 40
    rng = np.random.default_rng(int(scale * 1000) + 1)
    a1 = scale * rng.uniform(-1, 1, 6)
    a2 = np.concatenate([scale * rng.uniform(-1, 1, 2), a1[2:3], a1[3:4] * (1 + 1e-10), [0.0], -a1[5:6]])
    re, im = moments_3d(a1, a2)
    for i in range(6):
        for f, (w, a, b, c) in enumerate(PAT3):
            ref = w * _mp_dd([0] * a + [-1j * a1[i]] * b + [-1j * a2[i]] * c)
            assert abs(complex(re[f, i], im[f, i]) - ref) <= 2e-14 * abs(ref), (a1[i], a2[i], (a, b, c))
    w = np.concatenate([scale * rng.uniform(-1, 1, 4), [0.0]])
    re, im = phi_2d(w)
    for i, x in enumerate(w):
        E = {(a, b): _mp_dd([0] * a + [-1j * x] * b) for a, b in ((4, 1), (2, 1), (4, 3), (5, 2), (3, 2), (6, 1))}
        refs = [2 * E[4, 1], 2 * E[2, 1] - 4 * x**2 * E[4, 3], 4 * x**2 * E[5, 2] - 2j * x * E[4, 1],
                2j * x * E[3, 2], -8 * x**2 * E[6, 1]]
        for f, ref in enumerate(refs):
            assert abs(complex(re[f, i], im[f, i]) - ref) <= 2e-14 * abs(ref), (x, f)


@pytest.mark.parametrize("n", [2, 3])
def test_several_blocks_and_entries(n, monkeypatch):
    """Block boundaries (tiny blocks) change nothing; the compact entries are the matrix entries."""
    rng = np.random.default_rng(3)
    gram, vol = _simplices(rng, n, 23)
    om = _curvature(rng, n, 23, 10.0 ** rng.uniform(-6, 1.5, 23), rng.integers(0, 6, 23))
    r = _random_gauge(rng, om, n)
    M, A = fast_local_matrices(gram, vol, om, r)
    monkeypatch.setitem(_fast_local._CHUNKS, n, 5)
    M5, A5 = fast_local_matrices(gram, vol, om, r)
    assert np.abs(M5 - M).max() <= 1e-15 * np.abs(M).max() and np.abs(A5 - A).max() <= 1e-15 * np.abs(A).max()
    Mo, Md, Ao, Ad = fast_local_entries(gram, vol, om, r)
    e = local_edges(n)
    for off, diag, X in ((Mo, Md, M5), (Ao, Ad, A5)):
        assert np.array_equal(off.T, X[:, e[:, 1], e[:, 0]]) and np.array_equal(np.conj(off.T), X[:, e[:, 0], e[:, 1]])
        assert np.array_equal(diag.T, X[:, np.arange(n + 1), np.arange(n + 1)].real)
        assert not np.diagonal(X, axis1=1, axis2=2).imag.any()


def test_empty_batch_single_simplex_and_other_dimensions():
    M, A = fast_local_matrices(np.zeros((0, 4, 4)), np.zeros(0), np.zeros((0, 4)))
    assert M.shape == A.shape == (0, 4, 4)
    rng = np.random.default_rng(2)
    for n, om in ((2, [0.3]), (4, [0.1] * 10)):                  # one simplex / n = 4: passed on
        gram, vol = _simplices(rng, n, 1)
        args = (gram[0], vol[0], np.array(om) if n == 2 else np.zeros(10))
        for got, ref in zip(fast_local_matrices(*args), local_matrices(*args)):
            assert np.array_equal(got, ref)
    with pytest.raises(errors.ShapeError):
        fast_local_entries(gram, vol, np.zeros((1, 10)))         # the compact form is for n = 2, 3


def _changed(arr, index, value=None, factor=None, add=None):
    out = arr.copy()
    if value is not None:
        out[index] = value
    if factor is not None:
        out[index] *= factor
    if add is not None:
        out[index] += add
    return out


def _bad_inputs(n):
    """One fault per case, in the middle of a batch of six."""
    rng = np.random.default_rng(11)
    gram, vol = _simplices(rng, n, 6)
    om = _curvature(rng, n, 6, np.full(6, 0.7), np.zeros(6, int))
    r = _random_gauge(rng, om, n)
    rank_one = np.outer(*(2 * [np.ones(n + 1) - (n + 1) * np.eye(n + 1)[0]]))
    cases = {
        "asymmetric gram": {"gram": _changed(gram, (4, 0, 1), add=1e-3)},
        "nan gram": {"gram": _changed(gram, (3, 1, 1), value=np.nan)},
        "rows not summing to zero": {"gram": _changed(gram, 2, add=0.1)},
        "negative gram": {"gram": _changed(gram, 5, factor=-1.0)},
        "degenerate gram": {"gram": _changed(gram, 1, value=rank_one)},
        "volume": {"volume": _changed(vol, 2, value=-1.0)},
        "nan curvature": {"omega": _changed(om, (1, 0), value=np.nan)},
        "complex curvature": {"omega": om + 1j},
        "non-unit connection": {"connection": _changed(r, (3, 1), factor=1.01)},
        "holonomy": {"connection": _changed(r, (4, 0), factor=np.exp(0.3j))},
        "connection shape": {"connection": r[:, :2]},
        "volume count": {"volume": vol[:-1]},
    }
    if n == 3:
        cases["not closed"] = {"omega": _changed(om, (2, 3), add=0.5)}
    base = {"gram": gram, "volume": vol, "omega": om, "connection": r}
    return {k: {**base, **v} for k, v in cases.items()}


@pytest.mark.parametrize("n", [2, 3])
def test_bad_input_raises_the_reference_error(n):
    """Same typed error as local_matrices, same message (naming the same simplex)."""
    for name, args in _bad_inputs(n).items():
        with pytest.raises(errors.DhlbError) as ref:
            local_matrices(**args)
        with pytest.raises(type(ref.value)) as got:
            fast_local_matrices(**args)
        if "shape" not in name and "count" not in name:
            assert str(got.value) == str(ref.value), name


def test_doubtful_but_valid_gram_is_accepted():
    """Grams that fail the cheap tests but pass the exact ones (parse_gram) give the reference result."""
    q = np.linalg.svd(np.eye(3) - 1 / 3)[0][:, :2]              # orthonormal basis of 1^⊥
    thin = (q * [3e-13, 1.0]) @ q.T                             # λ_min / λ_max = 3e-13: rank 2 for parse_gram
    rows = _simplices(np.random.default_rng(5), 2, 1)[0][0]
    rows[0, 0] += 0.7e-8 * np.abs(rows).max()                   # row sum within 1e-8 but not within 0.5e-8
    gram = np.stack([thin, rows])
    assert not _fast_local._gram_surely_ok(np.ascontiguousarray(gram.reshape(2, 9).T), 2).any()
    vol, om = np.array([1e-6, 0.3]), np.array([[0.4], [2.0]])
    for got, ref in zip(fast_local_matrices(gram, vol, om), local_matrices(gram, vol, om)):
        assert _rel_err(got, ref) < TOL


def test_slightly_asymmetric_gram():
    """Symmetric only to 7e-11 (accepted): both read G_ab or G_ba in different places, so the
    results agree only to the size of the asymmetry -- the input does not define them better."""
    g = _simplices(np.random.default_rng(5), 2, 1)[0]
    g[0, 0, 1] += 0.7e-10 * np.abs(g).max()
    assert not _fast_local._gram_surely_ok(np.ascontiguousarray(g.reshape(1, 9).T), 2).any()
    for got, ref in zip(fast_local_matrices(g, [0.3], [[2.0]]), local_matrices(g, [0.3], [[2.0]])):
        assert _rel_err(got, ref) < TOL + 100 * 0.7e-10
