"""dhlb — discrete hermitian line bundles over simplicial complexes of any dimension."""
from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("dhlb")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

from dhlb import errors  # noqa: E402

__all__ = ["errors", "__version__"]

from dhlb.topology import SimplicialComplex  # noqa: E402

__all__ += ["SimplicialComplex"]
