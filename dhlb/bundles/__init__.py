"""Layer 3: discrete vector bundles with connection and hermitian line bundles with curvature.

Seed part 3, §3–§8: vector bundles, monodromy and Theorem 2 (:mod:`.vector_bundle`,
:mod:`.paths`, :mod:`.morphisms`), line bundles and connection forms (:mod:`.line_bundle`),
hermitian line bundles with curvature (:mod:`.hermitian`), Weil's theorem (:mod:`.weil`) and
the index formula (:mod:`.index`).
"""

from dhlb.bundles.morphisms import (
    direct_sum,
    dual,
    find_isomorphism,
    gauge,
    hom,
    is_isomorphic,
    is_morphism,
    tensor,
)
from dhlb.bundles.paths import LoopGroupPresentation, loop_group_presentation
from dhlb.bundles.vector_bundle import VectorBundle
from dhlb.topology.graph import SpanningForest, fundamental_cycles, spanning_forest

__all__ = [
    "VectorBundle",
    "direct_sum",
    "dual",
    "find_isomorphism",
    "gauge",
    "hom",
    "is_isomorphic",
    "is_morphism",
    "tensor",
    "LoopGroupPresentation",
    "SpanningForest",
    "fundamental_cycles",
    "loop_group_presentation",
    "spanning_forest",
]

from dhlb.bundles.hermitian import HermitianLineBundle
from dhlb.bundles.index import index_form, index_sum, rotation_form
from dhlb.bundles.line_bundle import (
    LineBundleClass,
    connection_form,
    form_class,
    integrate_exact_form,
    line_bundle_class,
)
from dhlb.bundles.weil import (
    BundlesWithCurvature,
    bundles_with_curvature,
    check_integrality,
    flat_line_bundles,
    integer_cycle_basis,
    line_bundle_with_curvature,
)

__all__ += [
    "LineBundleClass",
    "connection_form",
    "form_class",
    "integrate_exact_form",
    "line_bundle_class",
    "HermitianLineBundle",
    "BundlesWithCurvature",
    "bundles_with_curvature",
    "check_integrality",
    "flat_line_bundles",
    "integer_cycle_basis",
    "line_bundle_with_curvature",
    "index_form",
    "index_sum",
    "rotation_form",
]
