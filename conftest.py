"""Collection rules for the doctests of the package (``--doctest-modules`` over ``dhlb/``).

Deprecation shims (:mod:`dhlb._deprecation`) have no doctests of their own; collecting them would read
every forwarded attribute and emit one DeprecationWarning per name. ``tests/test_deprecated_paths.py``
imports each of them instead. Doctests that need the optional networkx are skipped without it.
"""

import pathlib
from importlib.util import find_spec

import pytest

HAS_NETWORKX = find_spec("networkx") is not None
NEEDS_NETWORKX = ("SimplicialComplex.from_graph", "SimplicialComplex.to_networkx")


def pytest_ignore_collect(collection_path: pathlib.Path, config):
    """Skip the deprecation shims (their attributes are read in tests/test_deprecated_paths.py)."""
    if collection_path.suffix == ".py" and "dhlb" in collection_path.parts:
        text = collection_path.read_text(encoding="utf-8")
        if "moved_module(__name__" in text or "moved_package(__name__" in text:
            return True
        if collection_path.name == "networkx_bridge.py" and not HAS_NETWORKX:
            return True  # the optional extra dhlb[graph]
    return None


def pytest_collection_modifyitems(items):
    """Skip the examples of the two graph methods of SimplicialComplex when networkx is missing."""
    if HAS_NETWORKX:
        return
    for item in items:
        if item.name.endswith(NEEDS_NETWORKX) and "dhlb/topology" in item.nodeid:
            item.add_marker(pytest.mark.skip(reason='needs networkx: pip install "dhlb[graph]"'))
