"""The element kernels: closed forms (n = 2, 3) against the generic kernel, and 40-digit mpmath.

The kernels trust their input; validation happens once at the public boundary
(:func:`dhlb.fem.integrals.local_matrices`, ``EuclideanComplex``, ``HermitianLineBundle``).
"""

from math import factorial

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import errors
from dhlb.fem import kernels_closed
from dhlb.fem._fast_moments import PAT3, moments_3d, phi_2d
from dhlb.fem.integrals import local_edges, local_gauge_connection, local_matrices
from dhlb.fem.kernels import KERNELS, dense, element_kernel, generic_kernel

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


def _both(kernel, *args, **kw):
    """(M, A) dense from a kernel."""
    mo, md, ao, ad = kernel(*args, **kw)
    return dense(mo, md), dense(ao, ad)


def closed(gram, vol, om, r=None, **kw):
    return _both(KERNELS[gram.shape[-1] - 1], gram, vol, om, r, **kw)


def generic(gram, vol, om, r=None):
    return _both(generic_kernel, gram, vol, om, r)


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
    M, A = closed(gram, vol, om, r)
    Mr, Ar = generic(gram, vol, om, r)
    assert M.shape == A.shape == (m, n + 1, n + 1) and M.dtype == A.dtype == complex
    assert _rel_err(M, Mr) < TOL and _rel_err(A, Ar) < TOL
    # only the matrices asked for, with the same values (series truncated per function: to rounding)
    k = KERNELS[n]
    mo, md, ao, ad = k(None, vol, om, r, dirichlet=False)
    assert ao is None and ad is None and _rel_err(dense(mo, md), M) < 1e-15
    mo, md, ao, ad = k(gram, vol, om, r, mass=False)
    assert mo is None and md is None and np.array_equal(dense(ao, ad), A)
    # the public boundary validates, then runs the same kernel
    Mp, Ap = local_matrices(gram, vol, om, r)
    assert np.array_equal(Mp, M) and np.array_equal(Ap, A)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.sampled_from([2, 3]), log_w=st.floats(-300, -4),
       cancel=st.floats(-1e-6, 1e-6))
def test_small_curvature_and_near_cancellation(seed, n, log_w, cancel):
    """ω -> 0 (down to 1e-300) and phases that nearly cancel (Ω_abc ≈ -Ω_abd, Ω_abc ≈ Ω_abd)."""
    rng = np.random.default_rng(seed)
    gram, vol = _simplices(rng, n, 6)
    w = 10.0 ** log_w
    if n == 2:
        om = (w * rng.uniform(-1, 1, 6))[:, None]
    else:
        big = rng.uniform(0.1, 6.0, 6)
        o = np.column_stack([big, -big * (1 + cancel), w * rng.uniform(-1, 1, 6)])
        o[3:, 1] = big[3:] * (1 + cancel)                      # equal phases instead of opposite
        om = np.column_stack([o[:, 0], o[:, 1], o[:, 2], o[:, 0] - o[:, 1] + o[:, 2]])
    M, A = closed(gram, vol, om)
    Mr, Ar = generic(gram, vol, om)
    assert _rel_err(M, Mr) < TOL and _rel_err(A, Ar) < TOL


def test_registry_by_dimension():
    assert element_kernel(2) is kernels_closed.kernel_2d and element_kernel(3) is kernels_closed.kernel_3d
    assert element_kernel(1) is generic_kernel and element_kernel(4) is generic_kernel


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
    M, A = closed(gram, vol, om)
    Mr, Ar = generic(gram, vol, om)
    assert _rel_err(M, Mr) < TOL and _rel_err(A, Ar) < TOL


@pytest.mark.parametrize("n", [2, 3])
def test_flat_gives_p1_mass_and_stiffness(n):
    gram, vol = _simplices(np.random.default_rng(n), n, 5)
    M, A = closed(gram, vol, np.zeros((5, 1 if n == 2 else 4)))
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
    M, A = closed(gram, vol, om, r)
    monkeypatch.setitem(kernels_closed._CHUNKS, n, 5)
    M5, A5 = closed(gram, vol, om, r)
    assert np.abs(M5 - M).max() <= 1e-15 * np.abs(M).max() and np.abs(A5 - A).max() <= 1e-15 * np.abs(A).max()
    Mo, Md, Ao, Ad = KERNELS[n](gram, vol, om, r)
    e = local_edges(n)
    for off, diag, X in ((Mo, Md, M5), (Ao, Ad, A5)):
        assert np.array_equal(off.T, X[:, e[:, 1], e[:, 0]]) and np.array_equal(np.conj(off.T), X[:, e[:, 0], e[:, 1]])
        assert np.array_equal(diag.T, X[:, np.arange(n + 1), np.arange(n + 1)].real)
        assert not np.diagonal(X, axis1=1, axis2=2).imag.any()


@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("request_", [(True, True), (True, False), (False, True)])
def test_split_entries_are_the_kernel_entries_to_the_bit(n, request_, monkeypatch):
    """The real/imaginary split of the assembly, with the connection gathered per block, is the kernel's output."""
    mass, dirichlet = request_
    rng = np.random.default_rng(11)
    gram, vol = _simplices(rng, n, 23)
    om = _curvature(rng, n, 23, 10.0 ** rng.uniform(-6, 1.5, 23), rng.integers(0, 6, 23))
    r = _random_gauge(rng, om, n)
    monkeypatch.setitem(kernels_closed._CHUNKS, n, 5)
    ref = KERNELS[n](gram, vol, om, r, mass=mass, dirichlet=dirichlet)
    rows = rng.permutation(r.size).reshape(r.shape)                    # r as per-edge values of a complex
    per_edge = np.empty(r.size, complex)
    per_edge[rows] = r
    for got in (kernels_closed.split_entries(n, gram, vol, om, r, mass=mass, dirichlet=dirichlet),
                kernels_closed.split_entries(n, gram, vol, om, per_edge, mass=mass, dirichlet=dirichlet, rows=rows)):
        for i, (x, y) in enumerate(zip(ref, got)):
            assert (x is None) == (y is None) == (not (mass if i < 2 else dirichlet))
            if x is not None and i % 2 == 0:
                assert y.shape == (2, *x.shape) and np.array_equal(x.real, y[0]) and np.array_equal(x.imag, y[1])
            elif x is not None:
                assert np.array_equal(x, y)


def test_empty_batch_and_gram_layouts():
    """No simplices; a Gram stack stored simplex axis last (as EuclideanComplex keeps it) gives the same."""
    for n in (2, 3):
        out = KERNELS[n](np.zeros((0, n + 1, n + 1)), np.zeros(0), np.zeros((0, 1 if n == 2 else 4)))
        assert [x.shape for x in out] == [(3 * n - 3, 0), (n + 1, 0)] * 2
    rng = np.random.default_rng(2)
    gram, vol = _simplices(rng, 3, 7)
    om = _curvature(rng, 3, 7, np.full(7, 2.0), np.zeros(7, int))
    soa = np.moveaxis(np.ascontiguousarray(np.moveaxis(gram, 0, -1)), -1, 0)
    for a, b in zip(KERNELS[3](gram, vol, om), KERNELS[3](soa, vol, om)):
        assert np.array_equal(a, b)


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


_EXPECTED = {
    "asymmetric gram": errors.InvalidMetricError, "nan gram": errors.NonFiniteError,
    "rows not summing to zero": errors.InvalidMetricError, "negative gram": errors.InvalidMetricError,
    "degenerate gram": errors.InvalidMetricError, "volume": errors.DegenerateSimplexError,
    "nan curvature": errors.NonFiniteError, "complex curvature": errors.CurvatureMismatchError,
    "non-unit connection": errors.InvalidConnectionError, "holonomy": errors.CurvatureMismatchError,
    "connection shape": errors.ShapeError, "volume count": errors.ShapeError, "not closed": errors.NotClosedError,
}


@pytest.mark.parametrize("n", [2, 3])
def test_bad_input_raises_a_typed_error_at_the_boundary(n):
    """The public local matrices validate (the kernels do not) and name the offending simplex."""
    for name, args in _bad_inputs(n).items():
        with pytest.raises(_EXPECTED[name]) as got:
            local_matrices(**args)
        if "shape" not in name and "count" not in name and "complex" not in name:
            assert "simplex" in str(got.value), (name, str(got.value))
