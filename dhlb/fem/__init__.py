"""Layer 4: finite elements on hermitian line bundles — Θ/Λ/Ξ integrals, mass and Dirichlet matrices.

The solvers live in :mod:`dhlb.linalg`; their public names are re-exported here.
"""
from dhlb.fem.assembly import bundle_matrices, dirichlet_matrix, lumped_mass, mass_matrix
from dhlb.fem.connection import (
    TET_PSD_TOL,
    connection_laplacian,
    connection_mass,
    cotan_edge_weights,
    tet_connection_laplacian,
)
from dhlb.fem.integrals import (
    expi_divided_difference,
    expi_moment,
    lambda_,
    local_dirichlet_matrices,
    local_mass_matrices,
    local_matrices,
    theta,
    xi,
)
from dhlb.linalg import (
    EigenResult,
    SolverOptions,
    available_backends,
    backward_errors,
    select_backend,
    smallest_eigenpairs,
    solve,
)

__all__ = [
    "bundle_matrices",
    "dirichlet_matrix",
    "lumped_mass",
    "mass_matrix",
    "connection_laplacian",
    "tet_connection_laplacian",
    "TET_PSD_TOL",
    "connection_mass",
    "cotan_edge_weights",
    "expi_divided_difference",
    "expi_moment",
    "lambda_",
    "local_dirichlet_matrices",
    "local_mass_matrices",
    "local_matrices",
    "theta",
    "xi",
    "available_backends",
    "select_backend",
    "EigenResult",
    "SolverOptions",
    "backward_errors",
    "smallest_eigenpairs",
    "solve",
]
