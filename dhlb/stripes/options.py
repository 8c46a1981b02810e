"""The method knobs of :func:`~dhlb.stripes.stripe_pattern` and of its section step, as frozen values.

Examples
--------
>>> from dhlb.stripes import SectionOptions, StripeOptions
>>> opts = StripeOptions(energy="fem", section=SectionOptions(kind="power", iterations=30, seed=1))
>>> opts.section.kind, opts.replace(orthogonal=True).orthogonal, opts.orthogonal
('power', True, False)
"""

from __future__ import annotations

import dataclasses
import numbers
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dhlb._deprecation import check_choice, check_flag, check_integer, check_number
from dhlb.errors import InvalidParameterError
from dhlb.stripes.energy import ENERGIES

__all__ = ["ENERGY_RTOL", "SECTIONS", "UNIT_RTOL", "SectionOptions", "StripeOptions"]

SECTIONS = ("unit", "eigenvector", "power")
"""The kinds of section ψ a stripe pattern can use (:class:`SectionOptions`)."""
METHODS = ("intrinsic", "extrinsic")
"""How ω̂ is computed (:func:`dhlb.stripes.stripe_form`)."""
COMPONENTS = ("all", "largest")
"""The values of ``components`` (:func:`dhlb.mesh.validate_surface`)."""
MAX_ITERATIONS = 100_000
"""The most steps of ``section="unit"`` or ``"power"`` (one back-solve each)."""
UNIT_RTOL = 1e-3
"""Default step tolerance of ``section="unit"``: stop when the iterate moved by less than this (relative,
norm of diag(M): the RMS phase change in radians) in a step, and less than in the step before."""
ENERGY_RTOL = 1e-3
"""Default flat-energy tolerance of ``section="unit"``: stop when the unit energy changed by less than this
(relative) over the last steps (:data:`dhlb.stripes.section.STALL_STEPS`)."""


@dataclass(frozen=True)
class SectionOptions:
    """Which section ψ gives a stripe pattern, and how it is iterated.

    Parameters
    ----------
    kind : {"unit", "eigenvector", "power"}
        * ``"unit"`` (default): the smallest eigenvector, then the unit-modulus iteration
          ``x ← normalize_per_vertex(M K⁻¹ M x)`` with the eigensolver's factorization of
          ``K = A + εM`` (:func:`dhlb.stripes.section.unit_section`): it returns the iterate of lowest
          *unit* energy (the seed's energy of a unit function, part 2 §2.1, before the relaxation
          Eq. 2.3), so each level of a surface with varying girth keeps its own number of stripes,
          joined by dislocations. Never higher unit energy than ``"eigenvector"``.
        * ``"eigenvector"``: the smallest eigenvector of the relaxed problem (the seed's §2.1 / §4.2).
        * ``"power"``: the seed's Algorithm 9, ``iterations`` inverse power steps (default 20) from a
          uniformly random start (``seed``), for reproducing published figures.
    iterations : int, optional
        ``"unit"``: the maximum number of steps (default 200; 0 = the normalized eigenvector);
        ``"power"``: the number of steps (default 20; at least 1). At most 100000 (one back-solve each).
        An integer (not a bool).
    seed : int >= 0 or numpy Generator, optional
        Random start of ``"power"``; for ``"unit"`` the seed of the small phase perturbation of the
        start (default 0, deterministic). An integer seed is passed to :func:`numpy.random.default_rng`,
        which refuses negative ones.
    unit_tol : float > 0
        ``"unit"`` stops when the iterate moved by less than this in one step (relative, in the norm of
        ``diag(M)``: the RMS phase change in radians) and less than in the step before: a fixed point,
        ``converged``. Finite.
    energy_tol : float >= 0
        ``"unit"`` also stops, after at least 10 steps, when the unit energy stayed within this (relative)
        over the last 5 steps: ``stopped == "stalled"``. On scanned meshes the dislocations keep creeping
        for hundreds of steps at a nearly constant energy (issue 42); 0 iterates on to the fixed point or
        ``iterations``. Default ``1e-3``. Finite.

    Raises
    ------
    InvalidParameterError
        ``kind`` not one of :data:`SECTIONS`, ``iterations`` not an integer in range, ``unit_tol`` not a
        finite positive number, ``energy_tol`` not a finite number >= 0, ``seed`` neither an integer >= 0
        nor a Generator. Checked at construction,
        and again by :meth:`replace`.

    Examples
    --------
    >>> SectionOptions(kind="power", iterations=0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: SectionOptions.iterations must be between 1 and 100000 (...) ..., got 0
    """

    kind: str = "unit"
    iterations: int | None = None
    seed: Any = None
    unit_tol: float = UNIT_RTOL
    energy_tol: float = ENERGY_RTOL

    _EXAMPLE = "kind='eigenvector'"   # the example of a right call (dhlb._deprecation.check_option_group)

    def __post_init__(self) -> None:
        check_choice(self.kind, "SectionOptions.kind: the section", SECTIONS)
        iterations = self.iterations
        if iterations is not None:
            check_integer(iterations, "SectionOptions.iterations", 0)
            low = 1 if self.kind == "power" else 0
            if not low <= int(iterations) <= MAX_ITERATIONS:
                raise InvalidParameterError(f"SectionOptions.iterations must be between {low} and {MAX_ITERATIONS} "
                                            f"(one back-solve each) for kind={self.kind!r}, got {iterations!r}")
        check_number(self.unit_tol, "SectionOptions.unit_tol", "a positive number (finite)", lambda x: x > 0)
        check_number(self.energy_tol, "SectionOptions.energy_tol", "a finite number >= 0 (0: off)", lambda x: x >= 0)
        seed = self.seed
        if seed is not None and not isinstance(seed, np.random.Generator):
            if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, numbers.Integral):
                raise InvalidParameterError(f"SectionOptions.seed must be an integer or a numpy Generator, "
                                            f"got {seed!r}")
            if seed < 0:
                raise InvalidParameterError(f"SectionOptions.seed must be >= 0 (numpy refuses negative seeds), "
                                            f"got {seed!r}")

    def replace(self, **changes: Any) -> SectionOptions:
        """A copy with some fields changed (:func:`dataclasses.replace`; validated again).

        Parameters
        ----------
        **changes
            Field names and their new values.

        Returns
        -------
        SectionOptions

        Examples
        --------
        >>> SectionOptions().replace(kind="eigenvector").kind
        'eigenvector'
        """
        return dataclasses.replace(self, **changes)


@dataclass(frozen=True)
class StripeOptions:
    """How :func:`~dhlb.stripes.stripe_pattern` computes a pattern (solver knobs: :class:`dhlb.linalg.SolverOptions`).

    Parameters
    ----------
    energy : {"cotan", "fem"}
        The seed's cotangent energy (default) or the curvature-corrected FEM energy (see
        :mod:`dhlb.stripes.energy`).
    orthogonal : bool
        Also compute the pattern of the directions turned by 90° (``N × X``), as ``result.orthogonal``.
        Every flag of this class is ``True`` or ``False`` (a numpy bool counts, a truthy string does not).
    method : {"intrinsic", "extrinsic"}
        How ω̂ is computed (:func:`dhlb.stripes.stripe_form`).
    lumped : bool, optional
        Lumped (diagonal) mass; ``None`` (default): lumped for ``"cotan"``, consistent for ``"fem"``
        (:func:`dhlb.stripes.energy.stripe_matrices`).
    branch_weight : float >= 0
        Factor of the branch triangles' contribution to the cotan weights (0: removed, as in the seed;
        :func:`dhlb.stripes.energy.stripe_matrices`). Finite.
    reorient : bool
        Passed to :func:`dhlb.mesh.validate_surface`.
    components : {"all", "largest"}
        Passed to :func:`dhlb.mesh.validate_surface`.
    warn_aliasing : bool
        Warn when stripes are narrower than two edges (the result stays correct, §4.3).
    progress : bool
        Report the patterns computed (one, or two with ``orthogonal``) on stderr with tqdm when the
        run is expected to take more than about two seconds; the CLI passes ``not --quiet``.
    section : SectionOptions
        Which section ψ gives the pattern (:class:`SectionOptions`).
    repair : str or RepairOptions
        Which defects of the input mesh are repaired (:mod:`dhlb.mesh.repair`; as
        :class:`dhlb.fields.FieldOptions`): ``"safe"`` (default), ``"none"``, ``"all"`` or a list.

    Raises
    ------
    InvalidParameterError
        ``energy`` not one of ``"cotan"``, ``"fem"``; ``method`` not one of ``"intrinsic"``, ``"extrinsic"``;
        ``components`` not ``"all"`` or ``"largest"``; a flag not a bool (``lumped``: or None);
        ``branch_weight`` not a finite number >= 0; ``section`` not a :class:`SectionOptions`; an unknown
        ``repair``. Checked at construction, and again by :meth:`replace`.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.stripes import StripeOptions, stripe_pattern
    >>> V, F = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]]
    >>> res = stripe_pattern(V, F, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25,
    ...                      options=StripeOptions(energy="fem", orthogonal=True))
    >>> res.energy, res.orthogonal is not None
    ('fem', True)
    """

    energy: str = "cotan"
    orthogonal: bool = False
    method: str = "intrinsic"
    lumped: bool | None = None
    branch_weight: float = 0.0
    reorient: bool = False
    components: str = "all"
    warn_aliasing: bool = True
    progress: bool = False
    section: SectionOptions = field(default_factory=SectionOptions)
    repair: Any = "safe"

    _EXAMPLE = "energy='fem'"   # the example of a right call (dhlb._deprecation.check_option_group)

    def __post_init__(self) -> None:
        from dhlb.mesh.repair import RepairOptions

        check_choice(self.energy, "StripeOptions.energy", ENERGIES)
        check_choice(self.method, "StripeOptions.method", METHODS)
        check_choice(self.components, "StripeOptions.components", COMPONENTS)
        for name in ("orthogonal", "reorient", "warn_aliasing", "progress"):
            check_flag(getattr(self, name), f"StripeOptions.{name}")
        check_flag(self.lumped, "StripeOptions.lumped", optional=True)
        check_number(self.branch_weight, "StripeOptions.branch_weight", "a finite number >= 0", lambda x: x >= 0)
        if not isinstance(self.section, SectionOptions):
            raise InvalidParameterError(f"StripeOptions.section must be a SectionOptions, e.g. "
                                        f"section=SectionOptions(kind='power'), got {self.section!r}")
        RepairOptions.parse(self.repair)

    def replace(self, **changes: Any) -> StripeOptions:
        """A copy with some fields changed (:func:`dataclasses.replace`; validated again).

        Parameters
        ----------
        **changes
            Field names and their new values.

        Returns
        -------
        StripeOptions

        Examples
        --------
        >>> StripeOptions().replace(energy="fem").energy
        'fem'
        """
        return dataclasses.replace(self, **changes)
