"""Every public function and class (in ``__all__`` of dhlb and its subpackages) has a runnable example.

The examples themselves run as doctests (``--doctest-modules`` in the pytest configuration).
"""

from __future__ import annotations

import importlib
import inspect

import pytest

PACKAGES = ["dhlb", "dhlb.topology", "dhlb.forms", "dhlb.bundles", "dhlb.geometry", "dhlb.fem", "dhlb.fields",
            "dhlb.stripes", "dhlb.vortex", "dhlb.io", "dhlb.render", "dhlb.examples", "dhlb.linalg",
            "dhlb.strategies", "dhlb.conformal"]


def _public_objects():
    seen = {}
    for name in PACKAGES:
        mod = importlib.import_module(name)
        for attr in getattr(mod, "__all__", []):
            obj = getattr(mod, attr)
            if (inspect.isfunction(obj) or inspect.isclass(obj)) and id(obj) not in seen:
                seen[id(obj)] = (f"{name}.{attr}", obj)
    return list(seen.values())


OBJECTS = _public_objects()


def test_there_are_public_objects():
    assert len(OBJECTS) > 150


@pytest.mark.parametrize("name, obj", OBJECTS, ids=[n for n, _ in OBJECTS])
def test_public_object_has_a_runnable_example(name, obj):
    doc = inspect.getdoc(obj) or ""
    assert "Examples" in doc and ">>>" in doc, f"{name} has no runnable Examples section in its docstring"
