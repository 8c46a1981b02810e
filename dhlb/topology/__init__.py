"""Layer 1: abstract simplicial complexes, chains, boundary maps, integer (co)homology."""
from dhlb.topology.complex import SimplicialComplex
from dhlb.topology.homology import (
    CohomologyGroup,
    HomologyGroup,
    betti_numbers,
    cohomology,
    cohomology_from_boundaries,
    homology,
    homology_from_boundaries,
)
from dhlb.topology.intlinalg import (
    hermite_normal_form,
    integer_kernel_basis,
    is_unimodular,
    smith_normal_form,
    solve_integer,
)
from dhlb.topology.manifold import (
    ManifoldReport,
    fundamental_cycle,
    is_consistently_oriented,
    manifold_report,
    require_manifold,
)
from dhlb.topology.structure import closed_star, components, incidence, subcomplex
from dhlb.topology.subdivision import barycentric_subdivision, relabeled

__all__ = [
    "SimplicialComplex",
    "CohomologyGroup",
    "HomologyGroup",
    "betti_numbers",
    "cohomology",
    "cohomology_from_boundaries",
    "homology",
    "homology_from_boundaries",
    "hermite_normal_form",
    "integer_kernel_basis",
    "is_unimodular",
    "smith_normal_form",
    "solve_integer",
    "ManifoldReport",
    "fundamental_cycle",
    "is_consistently_oriented",
    "manifold_report",
    "require_manifold",
    "closed_star",
    "components",
    "incidence",
    "barycentric_subdivision",
    "relabeled",
    "subcomplex",
]
