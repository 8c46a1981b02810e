"""Dropping the values an object has cached with :func:`functools.cached_property`.

Large objects (a mesh, its complex, its geometry) cache derived arrays on first use; before a
factorization that needs the memory, :meth:`dhlb.mesh.SurfaceMesh.release_caches` drops them, and
they are recomputed on the next access.

Examples
--------
>>> from functools import cached_property
>>> class C:
...     @cached_property
...     def big(self):
...         return [0] * 10
>>> c = C(); _ = c.big
>>> drop_cached(c), "big" in vars(c)
(1, False)
"""

from __future__ import annotations

from functools import cached_property

__all__ = ["drop_cached"]


def drop_cached(obj, keep=()) -> int:
    """Delete the values of ``obj``'s cached properties (except those named in ``keep``); return how many."""
    held = vars(obj)
    names = {name for klass in type(obj).__mro__ for name, attr in vars(klass).items()
             if isinstance(attr, cached_property) and name in held and name not in keep}
    for name in names:
        del held[name]
    return len(names)
