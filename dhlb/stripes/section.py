"""The section ψ of a stripe pattern after the eigenvector: the unit-modulus iteration and Algorithm 9.

The seed (part 2, §2.1, Eq. 2.3) defines the energy of a **unit** function φ (``|φ| = 1``) and then
relaxes the constraint: the minimum of ``E(ψ)/‖ψ‖²`` over *all* ψ is the smallest eigenvector of
``A x = λ M x``. That eigenvector localizes where the requested frequency fits best (a surface
whose girth changes gets the stripe count of one level everywhere, with ``|ψ|`` tiny elsewhere).
:func:`unit_section` goes back to the constraint: starting from the eigenvector it iterates

    ``x ← normalize_per_vertex(M K⁻¹ M x)``,   ``K = A − σM``  (σ < λ₁, K positive definite),

with the factorization of ``K`` the eigensolver already made. For a lumped (diagonal) ``M``,
``normalize(M K⁻¹ M x) = normalize(K⁻¹ M x)`` (a positive factor per vertex does not change a
phase), the iteration measured in issue 18. ``proofs/unit_section_iteration.py`` derives:

* it is the generalized power method for ``max g(x) = xᴴ M K⁻¹ M x`` over ``|x_i| = 1``:
  ``g`` is convex, so ``g(x_{t+1}) >= g(x_t)`` at every step;
* Cauchy–Schwarz gives ``(xᴴ M x)² <= g(x) · xᴴ K x``, i.e. the unit energy satisfies
  ``ρ(x) = xᴴAx / xᴴMx >= σ + xᴴMx / g(x)``, with equality exactly for eigenvectors: raising g
  lowers this bound, but ρ itself **can** increase in a step (the script exhibits one);
* hence the guard: the result is never worse than the (normalized) start, in particular never worse
  than the eigenvector.

**When it stops** (issue 28). Not on the energy: near a saddle — the eigenvector of a rotation-symmetric
tube, where every level carries one count — ρ is flat, and a step that changes it by 7e-4 (relative)
says nothing about being done (a three-level tube stopped there after one step with the eigenvector's
count everywhere). The iteration stops when the **iterate** stops moving and keeps contracting:
``‖x_t − x_{t−1}‖ <= unit_tol · ‖x_t‖`` in the norm of ``diag(M)`` (for unit-modulus values: the
RMS phase change in radians), with ``‖x_t − x_{t−1}‖ < ‖x_{t−1} − x_{t−2}‖`` (a saddle being left
moves faster and faster; an attracting fixed point slower and slower) and at least
:data:`MIN_UNIT_STEPS` steps (the first one mostly undoes the start's perturbation). ``converged``
means exactly that.

On scanned meshes that point is far: the dislocations keep creeping for hundreds of steps while the unit
energy barely changes (issue 42, measured with ``benchmarks/bench_stripes.py --scans``: the fixed point
after up to 180 steps on kitten, fertility and the bunnies, at a unit energy 3.9 % lower to 3.7 % higher
than the flat stretch before it, once 10 % lower: docs/stripes.md). So the iteration also stops,
``stopped == "stalled"``, when the unit energies of the last :data:`STALL_STEPS` + 1 iterates lie within
``energy_tol`` (relative, default 1e-3) of each other, after at least :data:`MIN_STALL_STEPS` steps: the
energy is flat, not merely its minimum (a rising energy is motion). That is not a fixed point
(``converged`` False) and says so; ``energy_tol=0`` iterates on to the fixed point or
:data:`MAX_UNIT_ITERATIONS` steps (``stopped == "limit"``).

**What it returns.** When it converged, the fixed point, if its unit energy is at most the start's;
otherwise (not converged, or a fixed point worse than the start) the iterate of lowest unit energy
seen. Why not always the lowest: ρ is not monotone along the way, and its minimum along the path is a
snapshot of dislocations still gliding to their places (a tube of radii 1 / 1.4 / 1.6: the lowest
iterate, 1 % below the fixed point, had its dislocation two rings inside a level; on tubes with short
levels it even had another level's count). The fixed point does not depend on where the path was.

The iteration is local. On an exactly rotation-symmetric mesh the eigenvector is a single Fourier
mode ``e^{imθ} f(z)`` and every iterate stays that mode: a saddle point that only rounding errors
leave (a 64 × 138 tube stalled there after one step with 12 stripes on every level). So the
iteration starts from the normalized eigenvector with a seeded random phase perturbation of
``kick = 0.3`` rad per vertex (the guard still compares with the unperturbed start); with it every
tube of the tests, symmetric or jittered, reaches the per-level counts.

For the real 2N formulation of a line field (unknowns ``(Re ψ_i, Im ψ_i)`` interleaved) the
constraint is ``|ψ_i| = 1`` for each base vertex, i.e. on both lifts ``i`` and ``N + i`` of the
double cover (their values are ``ψ_i`` and ``conj ψ_i``): each pair is normalized as a 2-vector.

:func:`power_section` is the seed's Algorithm 9: a fixed number of inverse power steps
``x ← K⁻¹ M x / ‖·‖_M`` from a uniformly random start (20 in the paper), for reproducing figures.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> from dhlb.stripes.section import unit_section
>>> n, r = 12, np.exp(2j * np.pi * 3 / 12)   # a ring whose connection turns by 2π·3: three windings
>>> i = np.arange(n)
>>> D = sp.csr_matrix((np.r_[-r * np.ones(n), np.ones(n)], (np.r_[i, i], np.r_[i, (i + 1) % n])), shape=(n, n))
>>> A, M = (D.conj().T @ D).tocsr(), sp.identity(n, dtype=complex, format="csr")   # Σ |z_{i+1} − r z_i|²
>>> lu = sp.linalg.splu((A + 1e-8 * M).tocsc())
>>> it = unit_section(A, M, lu.solve, np.exp(0.3j * i))          # a start with the wrong winding
>>> bool(it.start_energy > 1 > 1e-9 > it.unit_energy), np.allclose(np.abs(it.x), 1.0)
(True, True)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb.errors import InvalidParameterError, NonFiniteError
from dhlb.stripes.options import UNIT_RTOL, SectionOptions

if TYPE_CHECKING:
    from collections.abc import Callable

__all__ = ["UNIT_RTOL", "SectionIteration", "normalize_per_vertex", "power_section", "unit_energy", "unit_section"]

MAX_UNIT_ITERATIONS = 200
"""Default maximum of unit-modulus steps (each one back-solve with the eigensolver's factorization).

A safety net: tubes reach their fixed point in 4–20 steps; on the shared meshes the default ends at a fixed
point or on the flat unit energy (:data:`STALL_STEPS`) in 6–107 (issue 42: ``benchmarks/bench_stripes.py
--scans``)."""
STALL_STEPS = 5
"""Window of the second stopping rule: the unit energy of the last ``STALL_STEPS + 1`` iterates lies within
``energy_tol`` (relative) of the newest one."""
MIN_STALL_STEPS = 10
"""Steps always taken before the flat-energy rule is tested (leaving a saddle starts slowly)."""
MIN_UNIT_STEPS = 3
"""Steps always taken before the stopping rule is tested (the first one mostly undoes the start's perturbation)."""
UNIT_KICK = 0.3
"""Default amplitude (radians) of the seeded random phase perturbation of the start (see :func:`unit_section`)."""
POWER_ITERATIONS = 20
"""Default number of inverse power steps of ``section="power"`` (the seed's figures, Alg. 9)."""


@dataclass
class SectionIteration:
    """Record of :func:`unit_section` or :func:`power_section`.

    Attributes
    ----------
    x : ndarray
        The returned iterate (unit modulus per vertex for ``"unit"``; M-normalized for ``"power"``).
    kind : str
        ``"unit"`` or ``"power"``.
    iterations : int
        Back-solves done.
    energies : list of float
        Unit energy ``ρ(normalize(x_t))`` of the start (t = 0) and of every iterate.
    best_iteration : int
        The t whose iterate is returned (``"unit"``: the fixed point when it converged and is not worse
        than the start, else the lowest unit energy seen; ``"power"``: the last).
    converged : bool
        ``"unit"``: the iterate stopped moving (the rule in the module docstring); ``"power"``: True.
    increases : int
        Steps in which the unit energy went up (the guard kept the better iterate).
    stopped : {"converged", "stalled", "limit", "count"}
        Why the iteration ended: ``"converged"``, the iterate stopped moving (a fixed point);
        ``"stalled"``, the unit energy stayed within ``energy_tol`` over the last :data:`STALL_STEPS`
        steps (not a fixed point: the dislocations creep on); ``"limit"``, the maximum number of steps;
        ``"count"``: ``"power"`` ran its number of steps.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from dhlb.stripes.section import unit_section
    >>> A = sp.csr_matrix([[1.0, -1.0], [-1.0, 1.0]], dtype=complex); M = sp.identity(2, dtype=complex, format="csr")
    >>> it = unit_section(A, M, sp.linalg.splu((A + 1e-9 * M).tocsc()).solve, np.array([1.0, 0.5j]))
    >>> it.kind, it.best_iteration >= 1, round(it.unit_energy, 9)
    ('unit', True, 0.0)
    """

    x: np.ndarray
    kind: str
    iterations: int
    energies: list = field(default_factory=list)
    best_iteration: int = 0
    converged: bool = True
    increases: int = 0
    stopped: str = "converged"

    @property
    def unit_energy(self) -> float:
        """Unit energy of the returned iterate."""
        return float(self.energies[self.best_iteration])

    @property
    def start_energy(self) -> float:
        """Unit energy of the (normalized) start."""
        return float(self.energies[0])

    def to_json(self) -> dict:
        """JSON-ready summary (energies rounded to float).

        Examples
        --------
        >>> from dhlb.stripes.section import SectionIteration
        >>> SectionIteration(None, "unit", 2, [3.0, 2.0, 2.5], 1, True, 1).to_json()["unit_energy"]
        2.0
        """
        return {"kind": self.kind, "iterations": int(self.iterations), "unit_energy": self.unit_energy,
                "unit_energy_start": self.start_energy, "best_iteration": int(self.best_iteration),
                "converged": bool(self.converged), "stopped": self.stopped, "increases": int(self.increases),
                "energies": [float(e) for e in self.energies]}


def normalize_per_vertex(x, complex_form: bool = True, fallback=None) -> np.ndarray:
    """``x_i / |x_i|`` per vertex: complex entries, or interleaved ``(Re, Im)`` pairs (``complex_form=False``).

    Where ``x_i = 0`` the value of ``fallback`` (default ``1``, i.e. phase 0) is used.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.stripes.section import normalize_per_vertex
    >>> normalize_per_vertex(np.array([3 + 4j, 0, 2j])).round(3).tolist()
    [(0.6+0.8j), (1+0j), 1j]
    >>> normalize_per_vertex(np.array([3.0, 4.0, 0.0, -2.0]), complex_form=False).tolist()
    [0.6, 0.8, 0.0, -1.0]
    """
    x = np.asarray(x)
    z = x if complex_form else x[0::2] + 1j * x[1::2]
    mod = np.abs(z)
    if fallback is None:
        fb = np.ones_like(z)
    else:
        f = np.asarray(fallback)
        fb = f if complex_form else f[0::2] + 1j * f[1::2]
    u = np.where(mod > 0, z / np.where(mod > 0, mod, 1.0), fb)
    if complex_form:
        return u.astype(np.complex128)
    out = np.empty(2 * u.size)
    out[0::2], out[1::2] = u.real, u.imag
    return out


def unit_energy(A, M, x) -> float:
    """The Rayleigh quotient ``ρ(x) = Re(xᴴ A x) / Re(xᴴ M x)`` (the seed's energy of a unit function).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from dhlb.stripes.section import unit_energy
    >>> A = sp.csr_matrix([[1.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> unit_energy(A, M, np.array([1.0, -1.0]))
    2.0
    """
    x = np.asarray(x)
    return float(np.real(np.vdot(x, A @ x)) / np.real(np.vdot(x, M @ x)))


def _mass_operator(M, mass):
    """``v ↦ M v``; for a diagonal (lumped) ``M`` the product with ``mass``, its diagonal: the same numbers, faster."""
    C = M.tocoo()
    diagonal = bool(np.all((C.row == C.col) | (C.data == 0)))
    return (lambda v: mass * v) if diagonal else (lambda v: M @ v)


def _rayleigh(A, Mv, x) -> float:
    """:func:`unit_energy` with ``M`` as an operator."""
    return float(np.real(np.vdot(x, A @ x)) / np.real(np.vdot(x, Mv(x))))


def _check_iterations(name, value, low=1):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < low:
        raise InvalidParameterError(f"{name} must be an integer >= {low}, got {value!r}")
    return int(value)


def unit_section(
    A,
    M,
    solve: Callable,
    x0,
    *,
    complex_form: bool = True,
    kick: float = UNIT_KICK,
    options: SectionOptions | None = None,
    **deprecated,
) -> SectionIteration:
    """Minimize the unit energy from ``x0``: ``x ← normalize_per_vertex(M K⁻¹ M x)``, keeping the best iterate.

    Parameters
    ----------
    A, M : (n, n) sparse matrix
        The stripe energy and mass (Hermitian, or real symmetric for the 2N form).
    solve : callable
        ``solve(b) = K⁻¹ b`` for a positive definite ``K = A − σM`` (σ below the smallest
        eigenvalue; e.g. ``EigenResult.factor.solve`` with ``factor_shift="floor"``).
    x0 : (n,) array
        Start (normalized per vertex first), e.g. the smallest eigenvector.
    complex_form : bool
        Complex unknowns (True) or interleaved ``(Re ψ_i, Im ψ_i)`` pairs (False).
    kick : float >= 0
        Amplitude (radians) of a random phase ``e^{i kick u_i}``, ``u_i`` uniform in [−1, 1], applied to
        the normalized start before the first step, so that symmetric saddle points are left (see
        the module docstring). ``energies[0]`` is the unperturbed start's.
    options : SectionOptions, optional
        ``iterations``: the maximum number of steps (each one back-solve; default
        :data:`MAX_UNIT_ITERATIONS`); ``unit_tol``: stop when the step ``‖x_t − x_{t−1}‖`` (norm of
        ``diag(M)``) is at most ``unit_tol · ‖x_t‖`` and smaller than the step before, after at least
        :data:`MIN_UNIT_STEPS` steps (or when ρ reaches the rounding level); ``energy_tol``: stop, after at
        least :data:`MIN_STALL_STEPS` steps, when the unit energies of the last :data:`STALL_STEPS` + 1
        iterates lie within ``energy_tol`` (relative) of each other (0: never); ``seed``: of the
        perturbation (default 0: deterministic).
        ``kind`` is not used.
    **deprecated
        The keywords ``maxiter`` (→ ``options.iterations``), ``rtol`` (→ ``options.unit_tol``) and
        ``seed`` of dhlb 0.1, with a :class:`DeprecationWarning`.

    Returns
    -------
    SectionIteration
        ``x``: the fixed point, or the iterate of lowest unit energy (the guard of the module docstring).

    Raises
    ------
    NonFiniteError
        ``x0`` has a NaN or infinite entry.
    InvalidParameterError
        ``kick`` negative or not finite; an old keyword together with ``options``.
    TypeError
        An unknown keyword argument.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from dhlb.stripes import SectionOptions
    >>> from dhlb.stripes.section import unit_section
    >>> A = sp.csr_matrix([[2.0, -1.0, -1.0], [-1.0, 2.0, -1.0], [-1.0, -1.0, 2.0]], dtype=complex)
    >>> M = sp.identity(3, dtype=complex, format="csr")
    >>> it = unit_section(A, M, sp.linalg.splu((A + 1e-9 * M).tocsc()).solve, np.array([1, 1j, -1]))
    >>> it.energies[0] > it.unit_energy, round(it.unit_energy, 8), it.converged
    (True, 0.0, True)
    >>> unit_section(A, M, sp.linalg.splu((A + 1e-9 * M).tocsc()).solve, np.array([1, 1j, -1]),
    ...              options=SectionOptions(iterations=0)).iterations
    0
    """
    (options,) = fold_deprecated_kwargs("unit_section", deprecated, (
        "options", options, SectionOptions(), {"maxiter": "iterations", "rtol": "unit_tol", "seed": "seed"}))
    maxiter = MAX_UNIT_ITERATIONS if options.iterations is None else int(options.iterations)
    rtol, etol, seed = options.unit_tol, options.energy_tol, 0 if options.seed is None else options.seed
    x0 = np.asarray(x0)
    if not np.all(np.isfinite(x0)):
        raise NonFiniteError("the start vector x0 contains NaN or inf")
    diag = np.asarray(A.diagonal()).real
    mass = np.asarray(M.diagonal()).real
    atol = 1e-12 * float(np.sum(np.abs(diag)) / np.sum(mass))  # rounding level of ρ (scale: mean diagonal ratio)
    if not (np.isfinite(kick) and kick >= 0):
        raise InvalidParameterError(f"kick must be a number >= 0 (radians), got {kick!r}")
    x = normalize_per_vertex(x0, complex_form)
    dtype = np.result_type(A.dtype, M.dtype, x.dtype)
    A, M = A.astype(dtype, copy=False), M.astype(dtype, copy=False)   # cast once, not in every product
    Mv = _mass_operator(M, mass.astype(dtype))
    rho = _rayleigh(A, Mv, x)
    energies, best, best_x = [rho], 0, x
    if kick and maxiter:
        rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        z = x if complex_form else x[0::2] + 1j * x[1::2]
        z = z * np.exp(1j * kick * rng.uniform(-1.0, 1.0, z.size))
        x = z if complex_form else np.column_stack([z.real, z.imag]).ravel()
    norm = float(np.sqrt(np.sum(mass * np.abs(x) ** 2)))        # the step is measured in the norm of diag(M)
    stopped, increases, t, step = "limit", 0, 0, np.inf
    for t in range(1, maxiter + 1):
        y = Mv(solve(Mv(x)))
        new_x = normalize_per_vertex(y, complex_form, fallback=x)
        last, step = step, float(np.sqrt(np.sum(mass * np.abs(new_x - x) ** 2))) / norm
        x = new_x
        new = _rayleigh(A, Mv, x)
        energies.append(new)
        increases += new > rho
        rho = new
        if new < energies[best]:
            best, best_x = t, x
        # converged: the iterate itself stopped moving (not the energy, which is flat on a plateau)
        # and the steps contract (a fixed point that attracts, not a saddle being left)
        if (t >= MIN_UNIT_STEPS and step <= rtol and step < last) or abs(new) <= atol:
            stopped = "converged"
            break
        # stalled: the unit energy is flat over the last steps (dislocations creeping on a scan, module docstring)
        if etol and t >= MIN_STALL_STEPS and np.ptp(energies[-STALL_STEPS - 1:]) <= etol * abs(new):
            stopped = "stalled"
            break
    if maxiter == 0:
        stopped = "converged"
    if stopped == "converged" and t and energies[t] <= energies[0]:
        best, best_x = t, x     # the fixed point itself, not a snapshot of the path to it (module docstring)
    return SectionIteration(best_x, "unit", t if maxiter else 0, energies, best, stopped == "converged", increases,
                            stopped)


def power_section(A, M, solve: Callable, iterations: int = POWER_ITERATIONS, *, seed=None,
                  complex_form: bool = True) -> SectionIteration:
    """The seed's Algorithm 9: ``iterations`` inverse power steps from a uniformly random start.

    ``x`` starts as ``UNIFORMRAND`` (entries in [0, 1) of the real 2N vector; in the complex form
    its realification), then ``x ← K⁻¹ M x``, ``x ← x / sqrt(xᴴ M x)``.

    Parameters
    ----------
    A, M : sparse (n, n)
    solve : callable, ``K⁻¹ b`` (see :func:`unit_section`)
    iterations : int >= 1
    seed : int or numpy Generator, optional
    complex_form : bool

    Returns
    -------
    SectionIteration
        ``energies`` holds the unit energy of every iterate normalized per vertex.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from dhlb.stripes.section import power_section
    >>> A = sp.diags([0.0, 1.0, 4.0, 9.0]).tocsr(); M = sp.identity(4, format="csr")   # 2 vertices, real form
    >>> it = power_section(A, M, sp.linalg.splu((A + 1e-9 * M).tocsc()).solve, 5, seed=0, complex_form=False)
    >>> it.iterations, np.round(np.abs(it.x), 6).tolist()
    (5, [1.0, 0.0, 0.0, 0.0])
    """
    iterations = _check_iterations("iterations", iterations, 1)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    n = A.shape[0]
    x = rng.uniform(0.0, 1.0, 2 * n if complex_form else n)
    if complex_form:
        x = x[0::2] + 1j * x[1::2]
    energies = [unit_energy(A, M, normalize_per_vertex(x, complex_form))]
    for _ in range(iterations):
        x = solve(M @ x)
        x = x / np.sqrt(np.real(np.vdot(x, M @ x)))
        energies.append(unit_energy(A, M, normalize_per_vertex(x, complex_form)))
    return SectionIteration(x, "power", iterations, energies, iterations, True, 0, "count")
