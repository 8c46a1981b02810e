"""dhlb — discrete hermitian line bundles over simplicial complexes of any dimension."""
from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version

try:
    __version__ = _version("dhlb")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

import lazy_loader as _lazy

# Lazy submodules (the scientific-Python pattern, SPEC 1): ``import dhlb`` loads almost nothing;
# ``dhlb.fem``, ``dhlb.SimplicialComplex``, ... are imported on first access.
_SUBMODULES = ["errors", "topology", "forms", "bundles", "geometry", "linalg", "fem", "mesh", "fields", "stripes",
               "vortex", "conformal", "strategies", "io", "render", "examples", "cli",
               "surface", "volume", "commands"]  # the last three: deprecated aliases
_ATTRS = {
    "topology": ["SimplicialComplex"],
    "forms": ["Chain", "Cochain", "SolveResult", "integrate_closed_1form", "is_exact", "solve_d"],
    "bundles": ["HermitianLineBundle", "VectorBundle", "bundles_with_curvature", "check_integrality",
                "find_isomorphism", "flat_line_bundles", "index_form", "is_isomorphic", "line_bundle_with_curvature"],
    "geometry": ["EuclideanComplex"],
}
__getattr__, __dir__, _names = _lazy.attach(__name__, submodules=_SUBMODULES, submod_attrs=_ATTRS)
__all__ = ["__version__", "errors", "examples", "io", *[n for names in _ATTRS.values() for n in names]]
