"""Layer 1: abstract simplicial complexes, chains, boundary maps, integer (co)homology."""
from dhlb.topology.complex import SimplicialComplex

__all__ = ["SimplicialComplex"]
