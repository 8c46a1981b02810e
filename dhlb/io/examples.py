"""Small meshes bundled with dhlb (``dhlb/data/``), for examples, doctests and ``dhlb info``."""

from __future__ import annotations

from importlib import resources

__all__ = ["EXAMPLES", "example_path"]

#: file name -> one-line description
EXAMPLES = {
    "torus.obj": "closed torus surface, 288 vertices, 576 triangles (genus 1, H = Z, Z^2, Z)",
    "solid-torus.mesh": "solid torus, 144 vertices, 384 tetrahedra, boundary triangles included (H = Z, Z, 0, 0)",
    "spot.obj": "Keenan Crane's cow Spot (CC0), 2930 vertices, 5856 triangles, closed genus 0",
    "saddle.obj": "saddle z = (x² − y²)/2 over the unit disk, 631 vertices, 1176 triangles, one boundary loop",
    "double-torus.obj": "closed genus-2 surface (MIT, geometry-processing-js), 3070 vertices, 6144 triangles",
    "spot-tet.mesh": "the solid cow Spot (CC0), tetrahedralized by dhlb.mesh.tetrahedralize: 1980 vertices, "
                     "6428 tetrahedra",
}


def example_path(name: str = "torus.obj") -> str:
    """Path of a bundled example mesh.

    Parameters
    ----------
    name : str
        One of :data:`EXAMPLES` (``"torus.obj"``, ``"solid-torus.mesh"``, ``"spot.obj"``, ``"saddle.obj"``,
        ``"double-torus.obj"``, ``"spot-tet.mesh"``).

    Returns
    -------
    str
        The path of the file in the installed package (``dhlb/data/``).

    Raises
    ------
    FileNotFoundError
        Unknown name (the message lists the available ones).

    Examples
    --------
    >>> from dhlb.io import example_path
    >>> example_path("torus.obj").endswith("torus.obj")
    True
    """
    if name not in EXAMPLES:
        raise FileNotFoundError(f"no bundled example {name!r}; available: {', '.join(EXAMPLES)}")
    return str(resources.files("dhlb").joinpath("data", name))
