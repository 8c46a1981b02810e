"""dhlb — discrete hermitian line bundles over simplicial complexes of any dimension."""
from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version

try:
    __version__ = _version("dhlb")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

from dhlb import errors

__all__ = ["errors", "__version__"]

from dhlb import examples, io
from dhlb.bundles import (
    HermitianLineBundle,
    VectorBundle,
    bundles_with_curvature,
    check_integrality,
    find_isomorphism,
    flat_line_bundles,
    index_form,
    is_isomorphic,
    line_bundle_with_curvature,
)
from dhlb.forms import Chain, Cochain, SolveResult, integrate_closed_1form, is_exact, solve_d
from dhlb.geometry import EuclideanComplex
from dhlb.topology import SimplicialComplex

__all__ += [
    "SimplicialComplex",
    "examples",
    "Chain",
    "Cochain",
    "SolveResult",
    "integrate_closed_1form",
    "is_exact",
    "solve_d",
    "HermitianLineBundle",
    "VectorBundle",
    "bundles_with_curvature",
    "check_integrality",
    "find_isomorphism",
    "flat_line_bundles",
    "index_form",
    "is_isomorphic",
    "line_bundle_with_curvature",
    "EuclideanComplex",
    "io",
]
