"""The structural type the topology algorithms take: anything shaped like a simplicial complex.

The algorithm modules (structure, manifold, orientation, homology, subdivision, ...) annotate
their complex argument with :class:`ComplexLike` and build new complexes with ``type(X)(...)``,
so none of them imports :mod:`dhlb.topology.complex`, which delegates down to them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    import numpy as np
    import scipy.sparse as sp

__all__ = ["ComplexLike"]


class ComplexLike(Protocol):
    """What the topology algorithms read from a complex (see :class:`dhlb.SimplicialComplex`)."""

    @property
    def dim(self) -> int: ...

    @property
    def n_vertices(self) -> int: ...

    @property
    def vertex_labels(self) -> np.ndarray: ...

    @property
    def counts(self) -> tuple[int, ...]: ...

    def simplices(self, k: int) -> np.ndarray: ...

    def n_simplices(self, k: int) -> int: ...

    def faces(self, k: int) -> np.ndarray: ...

    def boundary(self, k: int) -> sp.csr_matrix: ...

    def index(self, k: int, rows) -> np.ndarray: ...
