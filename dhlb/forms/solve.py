"""Solving ``dα = β`` for discrete forms, and integrating closed 1-forms over spanning trees.

Methods, by coefficient group of β (a k-form, k ≥ 1):

* **R, C** — least squares ``min ‖d_{k-1} α − β‖₂``; exact iff the residual vanishes
  (Lemma 2 of the seed: β is exact iff it pairs to zero with every cycle, i.e. iff it is
  orthogonal to ``ker ∂_k``, the orthogonal complement of ``im d_{k-1}``).  For k = 1 a
  closed β is integrated over a spanning forest instead (root values 0).
* **Z** — exact integer linear algebra (:func:`dhlb.topology.intlinalg.solve_integer`);
  for k = 1 integration over a spanning forest (the incidence matrix is unimodular).
* **S¹** — Lemma 3 / Remark 5 made algorithmic.  Lift β to real angles Ξ.  (i) Closedness
  mod 2π: ``dΞ = 2π m`` with integer m, else not exact.  (ii) If ``m ≠ 0``, solve
  ``d_k n₁ = −m`` over Z (unsolvable: a torsion obstruction, not exact); ``γ = Ξ + 2π n₁`` is
  a closed real form.  (iii) Solve ``dα = γ`` over R; if exact, done.  (iv) Otherwise adjust by
  integer periods: with a Z-basis ``c_1..c_ℓ`` of ``ker ∂_k``
  (:func:`~dhlb.topology.intlinalg.integer_kernel_basis`) β is exact iff every period
  ``⟨γ, c_i⟩ ∈ 2πZ``; then an integer form ``n₂`` with ``⟨n₂, c_i⟩ = −⟨γ, c_i⟩/2π`` exists
  (Lemma 1) and ``γ + 2π n₂`` is exact over R.  The solution is wrapped into (−π, π].
* **C*** — via ``C* ≅ R_{>0} × S¹``: ``log|β|`` is solved over R, ``arg β`` over S¹, and
  ``α = exp(a + i θ)``.

``tol`` is a per-simplex tolerance (default: relative 1e-9, see
:meth:`dhlb.forms.groups.Group.default_tol`); checks of sums over several simplices scale it by
the number of terms.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph
from scipy.sparse import linalg as spla

from dhlb.errors import ConvergenceError, InvalidCochainError, NotClosedError, NotExactError
from dhlb.forms.chain import Chain
from dhlb.forms.cochain import Cochain
from dhlb.forms.groups import DEFAULT_RTOL, TWO_PI, get_group, wrap_angle
from dhlb.forms.integrate import integrate_closed_1form
from dhlb.topology._names import described_simplex as simplex_name

if TYPE_CHECKING:
    from dhlb.forms.groups import Group

__all__ = ["SolveResult", "solve_d", "is_exact", "integrate_closed_1form"]

_DENSE_LIMIT = 40_000  # matrix entries up to which least squares uses a dense SVD solve (≈ 10 ms)


@dataclass(frozen=True)
class SolveResult:
    """Result of :func:`solve_d`.

    Every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    solution : Cochain
        A (k−1)-form α (one particular solution).
    residual : float
        ``max_σ dist(dα(σ), β(σ))`` in the group (absolute value; S¹: wrapped angle; C*:
        ``|log(dα/β)|``).
    exact : bool
        True if the residual is within the tolerance, i.e. β = dα.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])           # edges (0,1), (0,2), (1,2)
    >>> res = solve_d(Cochain(X, 1, [1.0, 3.0, 2.0]))
    >>> res.exact, round(res.residual, 6), res.solution.values.round(6).tolist()
    (True, 0.0, [0.0, 1.0, 3.0])
    >>> solve_d(Cochain(X, 1, [1.0, 0.0, 0.0])).exact
    False
    """

    solution: Cochain
    residual: float
    exact: bool


# ---------------------------------------------------------------------------- real least squares
def _lstsq(X, k: int, b: np.ndarray) -> np.ndarray:
    """A least-squares solution x of ``d_{k-1} x ≈ b`` (real matrix, real or complex b)."""
    A = X.boundary(k).T.astype(np.float64).tocsr()
    m, n = A.shape
    if n == 0 or m == 0:
        return np.zeros(n, dtype=b.dtype)
    if m * n <= _DENSE_LIMIT:
        return np.linalg.lstsq(A.toarray(), b, rcond=None)[0]
    parts = (b.real, b.imag) if np.iscomplexobj(b) else (b,)
    if k == 1:  # graph Laplacian with one pinned vertex per component: a direct SPD solve
        _, lab = csgraph.connected_components(abs(A.T @ A), directed=False)
        pins = np.zeros(n)
        pins[np.unique(lab, return_index=True)[1]] = 1.0
        lu = spla.splu((A.T @ A + sp.diags(pins)).tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        sols = [lu.solve(A.T @ p) for p in parts]
    else:
        sols = []
        for p in parts:
            out = spla.lsmr(A, p, atol=1e-14, btol=1e-14, conlim=1e14, maxiter=20 * max(m, n))
            if out[1] == 7:
                raise ConvergenceError(f"least squares for d alpha = beta (k={k}) did not converge in {out[2]} steps")
            sols.append(out[0])
    return sols[0] + 1j * sols[1] if len(sols) == 2 else sols[0]


def _residual(alpha: Cochain, beta: Cochain) -> float:
    g = get_group(beta.group)
    dist = g.distance(g.op(alpha.d().values, g.inv(beta.values)))
    return float(dist.max(initial=0.0))


def _solve_linear(beta: Cochain, tol) -> SolveResult:
    X, k, g = beta.complex, beta.k, get_group(beta.group)
    tol = g.default_tol(beta.values) if tol is None else tol
    if k == 1:
        try:
            f = integrate_closed_1form(beta, tol=tol)
            return SolveResult(f, _residual(f, beta), True)
        except NotClosedError:
            pass
    alpha = Cochain._wrap(X, k - 1, _lstsq(X, k, beta.values).astype(g.dtype), g)
    res = _residual(alpha, beta)
    return SolveResult(alpha, res, res <= tol)


def _not_exact_1form(beta: Cochain, tol) -> Cochain:
    try:
        return integrate_closed_1form(beta, tol=tol)
    except NotClosedError as exc:
        err = NotExactError(str(exc).replace("only closed forms are", "only forms with zero periods are"))
        err.cycle, err.defect = exc.cycle, exc.defect
        raise err from None


def _solve_integer(beta: Cochain) -> SolveResult:
    from dhlb.topology.intlinalg import solve_integer

    X, k = beta.complex, beta.k
    if k == 1:
        f = _not_exact_1form(beta, 0)
        return SolveResult(f, 0.0, True)
    x = solve_integer(X.boundary(k).T.tocsr(), beta.values)
    if x is None:
        real = _solve_linear(beta.to_group("R"), None)
        if real.exact:
            why = f"it is exact over R but not over Z (a torsion obstruction: H^{k}(X; Z) has torsion)"
        else:
            i = int(np.argmax(np.abs(real.solution.d().values - beta.values)))
            why = (
                f"it is not even exact over R (least-squares residual {real.residual:.3g}, "
                f"largest on the {simplex_name(X, k, i)})"
            )
        raise NotExactError(f"the integer {k}-form is not d of an integer {k - 1}-form: {why}")
    if x.dtype == object:
        raise NotExactError("an integer solution exists but does not fit into int64")
    return SolveResult(Cochain(X, k - 1, x, "Z"), 0.0, True)


def _solve_periods(C: sp.csc_matrix, p: np.ndarray):
    """Integer form n with ``Cᵀ n = p`` (C: a Z-basis of cycles, one per column).

    Fast path: every cycle has a *private* simplex (coefficient ±1, in no other basis cycle);
    put the prescribed period there.  Otherwise exact integer solving.
    """
    from dhlb.topology.intlinalg import solve_integer

    R = C.tocsr()
    R.eliminate_zeros()
    single = np.flatnonzero((np.diff(R.indptr) == 1) & (np.abs(R.data[np.minimum(R.indptr[:-1], R.nnz - 1)]) == 1))
    cols = R.indices[R.indptr[single]]
    got, first = np.unique(cols, return_index=True)
    if got.size == C.shape[1]:
        n = np.zeros(C.shape[0], np.int64)
        rows = single[first]
        n[rows] = p[got] * R.data[R.indptr[rows]]
        return n
    return solve_integer(C.T.tocsr(), p)


def _solve_circle(beta: Cochain, tol) -> SolveResult:
    from dhlb.topology.intlinalg import integer_kernel_basis, solve_integer

    X, k, g = beta.complex, beta.k, get_group("S1")
    tol = g.default_tol(beta.values) if tol is None else tol
    if k == 1:
        f = _not_exact_1form(beta, tol)
        return SolveResult(f, _residual(f, beta), True)
    gamma = beta.values.astype(np.float64)
    if k + 1 <= X.dim:  # (i) closed mod 2π, (ii) make the lift closed over R
        dxi = X.boundary(k + 1).T @ gamma
        m = np.round(dxi / TWO_PI)
        off = np.abs(dxi - TWO_PI * m)
        if np.any(off > tol * (k + 2)):
            i = int(np.argmax(off))
            raise NotExactError(
                f"the S1 {k}-form is not closed: dβ = {wrap_angle(dxi[i]):.6g} ≠ 0 (mod 2π) on the "
                f"{simplex_name(X, k + 1, i)}; only closed forms are exact"
            )
        if np.any(m):
            n1 = solve_integer(X.boundary(k + 1).T.tocsr(), -m.astype(np.int64))
            if n1 is None:
                raise NotExactError(
                    f"the S1 {k}-form is closed but not exact: the integer {k + 1}-form dβ/2π is not d of an "
                    f"integer form (a torsion obstruction, H^{k + 1}(X; Z) has torsion)"
                )
            gamma = gamma + TWO_PI * n1
    x = _lstsq(X, k, gamma)
    lin_tol = max(tol, DEFAULT_RTOL * max(1.0, float(np.abs(gamma).max(initial=0.0))))
    if np.abs(X.boundary(k).T @ x - gamma).max(initial=0.0) > lin_tol:  # (iv) integer periods
        C = sp.csc_matrix(integer_kernel_basis(X.boundary(k)))
        per = C.T @ gamma / TWO_PI
        q = np.round(per)
        length = np.asarray(abs(C).sum(axis=0)).ravel()
        off = TWO_PI * np.abs(per - q) - lin_tol * np.maximum(1.0, length)
        if np.any(off > 0):
            j = int(np.argmax(off))
            cyc = Chain(X, k, C[:, j].toarray().ravel())
            defect = wrap_angle(TWO_PI * per[j])
            shown = [simplex_name(X, k, i) for i in np.flatnonzero(cyc.coefficients)[:6]]
            err = NotExactError(
                f"the S1 {k}-form is not exact: its period over a {k}-cycle through {', '.join(shown)}"
                f"{' …' if len(shown) == 6 else ''} is {defect:.6g} ≠ 0 (mod 2π) (cycle: err.cycle)"
            )
            err.cycle, err.defect = cyc, defect
            raise err
        n2 = _solve_periods(C, -q.astype(np.int64))
        if n2 is None:  # pragma: no cover - impossible for a Z-basis of ker ∂_k (Lemma 1)
            raise NotExactError("integer period adjustment failed although all periods are in 2πZ")
        gamma = gamma + TWO_PI * n2
        x = _lstsq(X, k, gamma)
    alpha = Cochain(X, k - 1, x, "S1")
    res = _residual(alpha, beta)
    if res > tol * (k + 1):  # pragma: no cover - numerical failure of the real solve
        raise ConvergenceError(f"the S1 potential has residual {res:.3g} > tol; the real solve lost accuracy")
    return SolveResult(alpha, res, True)


def _solve_cstar(beta: Cochain, tol) -> SolveResult:
    X, k = beta.complex, beta.k
    g = get_group("C*")
    tol = g.default_tol(beta.values) if tol is None else tol
    if k == 1:
        f = _not_exact_1form(beta, tol)
        return SolveResult(f, _residual(f, beta), True)
    modulus = _solve_linear(Cochain(X, k, np.log(np.abs(beta.values)), "R"), tol)
    if not modulus.exact:
        raise NotExactError(
            f"the C* {k}-form is not exact: log|β| is not exact over R (residual {modulus.residual:.3g})"
        )
    phase = _solve_circle(beta.to_group("S1"), tol)
    alpha = Cochain(X, k - 1, np.exp(modulus.solution.values + 1j * phase.solution.values), "C*")
    return SolveResult(alpha, _residual(alpha, beta), True)


# ---------------------------------------------------------------------------- public entry points
def solve_d(beta: Cochain, group: str | Group | None = None, tol: float | None = None) -> SolveResult:
    """Find a (k−1)-form α with ``dα = β`` (see the module docstring for the methods).

    Parameters
    ----------
    beta : Cochain
        A k-form, k ≥ 1.
    group : str, optional
        Solve in this group instead of ``beta.group`` (β is converted with
        :meth:`Cochain.to_group`).
    tol : float, optional
        Per-simplex tolerance (default: relative 1e-9).

    Returns
    -------
    SolveResult
        ``.solution`` (α), ``.residual``, ``.exact``.  Over R and C a non-exact β gives the
        least-squares α with ``exact=False``.

    Raises
    ------
    InvalidCochainError
        ``beta`` is not a :class:`Cochain`, is a 0-form, ``group`` is unknown, or β has no
        standard conversion to ``group``.
    NotExactError
        Over Z, S¹ and C* when β is not exact; the message names a violating cycle or simplex.
    ConvergenceError
        The sparse least-squares solve (k ≥ 2 on a large complex) did not converge.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.forms import Cochain
    >>> X = SimplicialComplex([(0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 2, 3)])   # a 2-sphere
    >>> beta = Cochain(X, 2, [1.0, 1.0, 0.5, 0.5])          # zero flux through the sphere
    >>> r = solve_d(beta)
    >>> r.exact, bool(r.solution.d().allclose(beta))
    (True, True)
    >>> vals = [3.0, -3.0, 2 * np.pi - 6.0, 0.0]              # flux -2π
    >>> solve_d(Cochain(X, 2, vals)).exact                    # least squares only
    False
    >>> r = solve_d(Cochain(X, 2, vals, "S1"))                # but 2π ≡ 0 in S¹
    >>> r.exact, bool(r.solution.d().allclose(Cochain(X, 2, vals, "S1")))
    (True, True)
    """
    if not isinstance(beta, Cochain):
        raise InvalidCochainError(f"solve_d needs a Cochain, got {type(beta).__name__}")
    if group is not None:
        beta = beta.to_group(group)
    if beta.k == 0:
        raise InvalidCochainError("β is a 0-form: there are no (−1)-forms to solve dα = β for")
    g = get_group(beta.group)
    X, k = beta.complex, beta.k
    if beta.values.size == 0:  # nothing to match; α: the identity (k−1)-form
        alpha = Cochain.identity(X, k - 1, g)
        return SolveResult(alpha, 0.0, True)
    if g.name in ("R", "C"):
        return _solve_linear(beta, tol)
    if g.name == "Z":
        return _solve_integer(beta)
    if g.name == "S1":
        return _solve_circle(beta, tol)
    return _solve_cstar(beta, tol)


def is_exact(beta: Cochain, tol: float | None = None) -> bool:
    """True if ``β = dα`` for some (k−1)-form α in β's group (0-forms: iff β is the identity).

    Parameters
    ----------
    beta : Cochain
        A k-form in any group.
    tol : float, optional
        Per-simplex tolerance (default: relative 1e-9, see
        :meth:`dhlb.forms.groups.Group.default_tol`).

    Returns
    -------
    bool
        Whether :func:`solve_d` finds an α with ``dα = β`` within ``tol`` (a k-form that is not
        exact gives ``False``, no error).

    Raises
    ------
    ConvergenceError
        The sparse least-squares solve of :func:`solve_d` did not converge.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.forms import Cochain
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])                 # a circle
    >>> is_exact(Cochain(X, 1, [1, 1, 1], "Z")), is_exact(Cochain(X, 1, [1, 2, 1], "Z"))
    (False, True)
    """
    if beta.k == 0:
        g = get_group(beta.group)
        t = g.default_tol(beta.values) if tol is None else tol
        return bool(np.all(g.distance(beta.values) <= t))
    try:
        return solve_d(beta, tol=tol).exact
    except NotExactError:
        return False
