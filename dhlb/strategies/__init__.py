"""Hypothesis strategies for property-based verification with dhlb (optional extra ``dhlb[strategies]``).

Draw simplicial complexes, manifolds whose invariants are known from their construction
(:class:`Known`), embedded surface meshes, connections, hermitian line bundles satisfying Weil's
integrality, vector bundles, cochains and sections, and state conjectures as hypothesis tests:
hypothesis searches for a counterexample and shrinks it to a small one.

* complexes: :func:`simplicial_complexes`, :func:`simplex_lists`, :func:`pure_simplex_lists`,
  :func:`relabelings`
* known spaces: :func:`closed_surfaces`, :func:`closed_manifolds`, :func:`balls` (records
  :class:`Known`)
* meshes: :func:`surface_meshes`
* bundles and forms: :func:`connections`, :func:`hermitian_line_bundles`, :func:`vector_bundles`,
  :func:`cochains`, :func:`sections`

Every strategy is built from hypothesis's own combinators, so examples start small and
counterexamples shrink; drawing 100 examples of any of them takes a few seconds at most.

Examples
--------
>>> from hypothesis import given, settings
>>> from dhlb.strategies import closed_surfaces
>>> @settings(max_examples=25)
... @given(closed_surfaces())
... def euler_characteristic_is_known(k):
...     assert k.complex.euler_characteristic == k.euler_characteristic
>>> euler_characteristic_is_known()
"""

from dhlb._install import install_hint

try:
    import hypothesis  # noqa: F401
except ImportError as exc:  # pragma: no cover - exercised with hypothesis uninstalled
    raise ImportError(
        "dhlb.strategies needs the 'hypothesis' package: " + install_hint("hypothesis", "strategies")
    ) from exc

from dhlb.strategies.bundles import cochains, connections, hermitian_line_bundles, sections, vector_bundles
from dhlb.strategies.complexes import (
    Known,
    balls,
    closed_manifolds,
    closed_surfaces,
    pure_simplex_lists,
    relabelings,
    simplex_lists,
    simplicial_complexes,
)
from dhlb.strategies.meshes import surface_meshes

__all__ = [
    "Known",
    "simplicial_complexes",
    "simplex_lists",
    "pure_simplex_lists",
    "relabelings",
    "closed_surfaces",
    "closed_manifolds",
    "balls",
    "surface_meshes",
    "cochains",
    "connections",
    "hermitian_line_bundles",
    "vector_bundles",
    "sections",
]
