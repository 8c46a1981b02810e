"""Collection rule for the doctests of the package (``--doctest-modules`` over ``dhlb/``).

Deprecation shims (:mod:`dhlb._deprecation`) have no doctests of their own; collecting them would read
every forwarded attribute and emit one DeprecationWarning per name. ``tests/test_deprecated_paths.py``
imports each of them instead.
"""

import pathlib


def pytest_ignore_collect(collection_path: pathlib.Path, config):
    """Skip the deprecation shims (their attributes are read in tests/test_deprecated_paths.py)."""
    if collection_path.suffix == ".py" and "dhlb" in collection_path.parts:
        text = collection_path.read_text(encoding="utf-8")
        if "moved_module(__name__" in text or "moved_package(__name__" in text:
            return True
    return None
