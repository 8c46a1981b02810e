"""Layer 2: discrete differential forms (cochains) with coefficients in Z, R, C, S¹ and C*.

* :class:`Cochain` — a k-form: values, exterior derivative, group law, pairing with chains.
* :class:`Chain` — an integer k-chain (with :meth:`Chain.path` for edge paths).
* :func:`solve_d` — a potential α with dα = β in any group; :func:`integrate_closed_1form`
  integrates a closed 1-form over a spanning forest.
* :mod:`dhlb.forms.groups` — the coefficient groups.
"""
from dhlb.forms.cochain import Chain, Cochain
from dhlb.forms.groups import GROUP_NAMES, get_group, wrap_angle
from dhlb.forms.solve import SolveResult, integrate_closed_1form, is_exact, solve_d

__all__ = [
    "Cochain",
    "Chain",
    "SolveResult",
    "solve_d",
    "is_exact",
    "integrate_closed_1form",
    "wrap_angle",
    "get_group",
    "GROUP_NAMES",
]
