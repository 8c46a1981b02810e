"""Typed exceptions of dhlb, all in one place.

Every error raised by dhlb on bad input is a subclass of :class:`DhlbError`;
where the problem is a bad *value* it is also a :class:`ValueError`, so code
written against the standard library keeps working.  Messages name the
offending simplex, vertex, edge, file line, ... and say what to do about it.

Examples
--------
>>> import dhlb
>>> try:
...     dhlb.SimplicialComplex([(0, 1, 1)])
... except dhlb.errors.InvalidSimplexError as err:
...     print(type(err).__name__)
InvalidSimplexError
"""

from __future__ import annotations

from typing import ClassVar

__all__ = [
    # base classes
    "DhlbError", "DhlbWarning",
    # any layer: values, shapes, types, parameters
    "NonFiniteError", "ShapeError", "InvalidTypeError", "InvalidParameterError", "ResourceLimitError",
    # topology: simplices, complexes, manifolds
    "InvalidSimplexError", "EmptyComplexError", "RaggedInputError", "SimplexNotFoundError", "NonManifoldError",
    "NonOrientableError", "InconsistentOrientationError", "DegenerateSimplexError", "UnreferencedVertexError",
    "UnreferencedVertexWarning", "MeshRepairWarning", "InvalidMatrixError",
    # forms
    "InvalidCochainError", "NotClosedError", "NotExactError", "NotAPathError",
    # bundles
    "InvalidConnectionError", "CurvatureMismatchError", "IntegralityError", "SectionZeroError",
    # geometry
    "InvalidMetricError",
    # linear algebra
    "InvalidOperatorError", "NotSemidefiniteError", "ConvergenceError", "InsufficientMemoryError",
    # applications
    "CurveIntersectionError", "UnresolvedFluxWarning",
    # files and pictures
    "MeshParseError", "OutputError", "OverwriteError", "ViewerUnavailableError",
    # helpers for messages
    "format_bytes", "differing_digits",
]


class DhlbError(Exception):
    """Base class of every exception raised deliberately by dhlb."""


class InvalidSimplexError(DhlbError, ValueError):
    """A simplex is malformed: repeated, negative or non-integer vertex labels."""


class EmptyComplexError(InvalidSimplexError):
    """No simplices were given where at least one is needed."""


class RaggedInputError(InvalidSimplexError):
    """Rows of an array-like input have different lengths where equal ones are needed."""


class SimplexNotFoundError(DhlbError, KeyError):
    """A simplex looked up in a complex is not part of it."""

    def __str__(self) -> str:  # KeyError quotes its message; keep it readable
        return str(self.args[0]) if self.args else ""


class NonFiniteError(DhlbError, ValueError):
    """Coordinates or values contain NaN or infinity."""


class MeshParseError(DhlbError, ValueError):
    """A file cannot be parsed; the message names the file and the line.

    Parameters
    ----------
    message : str
        What is wrong.
    path : str or None, optional
        The file; when given, the message starts with ``"{path}: "``.
    line : int or None, optional
        The 1-based line number in ``path``; when given (with ``path``), the message starts with
        ``"{path}, line {line}: "``.
    found : {"volume", "surface"} or None, optional
        The file holds the other kind of mesh: tetrahedra where a surface was to be read
        (``"volume"``), or only triangles where a volume was (``"surface"``).  The message then ends
        with the reader to use (:func:`dhlb.io.read_volume`, :func:`dhlb.io.read_surface`); the
        command line names its commands instead.

    Attributes
    ----------
    path : str or None
        The file, as given.
    line : int or None
        The line number, as given.
    found : str or None
        As given.
    reason : str
        The message without the file, the line and the reader to use.

    Examples
    --------
    >>> print(MeshParseError("expected 3 vertex indices", path="m.off", line=7))
    m.off, line 7: expected 3 vertex indices
    >>> print(MeshParseError("a volume mesh (12 tetrahedra)", path="t.mesh", found="volume"))
    t.mesh: a volume mesh (12 tetrahedra); read it with dhlb.io.read_volume
    """

    READERS: ClassVar[dict[str, str]] = {"volume": "dhlb.io.read_volume", "surface": "dhlb.io.read_surface"}
    """The reader to name for each kind of mesh found."""

    def __init__(self, message: str, path: str | None = None, line: int | None = None, *, found: str | None = None):
        where = ""
        if path is not None:
            where = f"{path}"
            if line is not None:
                where += f", line {line}"
            where += ": "
        hint = f"; read it with {self.READERS[found]}" if found in self.READERS else ""
        super().__init__(where + message + hint)
        self.path = path
        self.line = line
        self.found = found if found in self.READERS else None
        self.reason = message


class NonManifoldError(DhlbError, ValueError):
    """The complex is not a (pseudo)manifold where one is required."""


class NonOrientableError(DhlbError, ValueError):
    """The complex is not orientable where an orientation is required."""


class InconsistentOrientationError(DhlbError, ValueError):
    """Top simplices are not consistently oriented (a shared face is traversed twice the same way)."""


class DegenerateSimplexError(DhlbError, ValueError):
    """A simplex has zero (or numerically zero) volume."""


class UnreferencedVertexError(DhlbError, ValueError):
    """A vertex is referenced by no simplex where every vertex must be used."""


class NotClosedError(DhlbError, ValueError):
    """A form that must be closed is not; the message names a violating simplex or cycle."""


class NotExactError(DhlbError, ValueError):
    """A closed form is not exact; the message names a cycle with a nonzero period."""


class NotAPathError(DhlbError, ValueError):
    """A vertex sequence is not an edge path of the complex."""


class InvalidConnectionError(DhlbError, ValueError):
    """Transport matrices are not invertible / unitary / orthogonal, or have the wrong shape."""


class CurvatureMismatchError(DhlbError, ValueError):
    """A curvature 2-form does not match the holonomy of the connection."""


class IntegralityError(DhlbError, ValueError):
    """A 2-form is not integral (Weil): some integer 2-cycle has a period outside 2πZ.

    Parameters
    ----------
    message : str
        What is wrong.
    cycle : object, optional
        The offending integer 2-cycle (e.g. an int array of coefficients on the triangles), if known.
    defect : float or None, optional
        How far its period is from the nearest multiple of 2π, if known.

    Attributes
    ----------
    cycle : object
        The offending cycle, as given.
    defect : float or None
        The defect, as given.

    Examples
    --------
    >>> IntegralityError("period 1.0 is not in 2πZ", defect=1.0).defect
    1.0
    """

    def __init__(self, message: str, cycle=None, defect: float | None = None):
        super().__init__(message)
        self.cycle = cycle
        self.defect = defect


class SectionZeroError(DhlbError, ValueError):
    """A section vanishes at a vertex where a nowhere-vanishing section is required."""


class InvalidMetricError(DhlbError, ValueError):
    """A discrete metric is not positive definite on some simplex."""


class ConvergenceError(DhlbError, RuntimeError):
    """An iterative solver did not reach its tolerance.

    Parameters
    ----------
    message : str
        What did not converge, and what to do about it.
    result : object, optional
        The partial result, kept as the attribute ``result``.

    Attributes
    ----------
    result : object or None
        The partial result (e.g. an :class:`~dhlb.linalg.EigenResult` with ``converged=False``).

    Examples
    --------
    >>> ConvergenceError("not converged", result=None).result is None
    True
    """

    def __init__(self, message: str, *, result=None):
        super().__init__(message)
        self.result = result


class InsufficientMemoryError(DhlbError, MemoryError):
    """A factorization (or another step) would need more memory than is available.

    Parameters
    ----------
    message : str
        What would need the memory, and what to do about it.
    needed : int, optional
        The estimated number of bytes needed (0 when unknown).
    available : int, optional
        The number of bytes available (0 when unknown).

    Attributes
    ----------
    needed, available : int
        The estimate and the available bytes, as in the message.

    Examples
    --------
    >>> err = InsufficientMemoryError("too big", needed=2**33, available=2**30)
    >>> isinstance(err, MemoryError), err.needed // err.available
    (True, 8)
    """

    def __init__(self, message: str, *, needed: int = 0, available: int = 0):
        super().__init__(message)
        self.needed, self.available = int(needed), int(available)


class DhlbWarning(UserWarning):
    """Base class of dhlb's warnings."""


class UnreferencedVertexWarning(DhlbWarning):
    """Vertices that no simplex uses were dropped (the map to the input indices is kept).

    Parameters
    ----------
    message : str
        The warning in the library's words.
    dropped : sequence of int, optional
        The input rows of the dropped vertices (kept as the attribute ``dropped``, a tuple), so that a
        caller (the command line) can say it in its own words.
    cell : str, optional
        The kind of cell that uses none of them (``"face"``, ``"tetrahedron"``, ...).
    """

    def __init__(self, message: str = "", *, dropped=(), cell: str = "cell"):
        super().__init__(message)
        self.dropped = tuple(int(i) for i in dropped)
        self.cell = cell


class MeshRepairWarning(DhlbWarning):
    """A defect of the input mesh was repaired (:mod:`dhlb.mesh.repair`); one warning per kind of repair.

    Parameters
    ----------
    message : str
        What was done, with counts and the first input rows.
    kind : str, optional
        The repair (``"split"``, ``"duplicates"``, ``"doubled"``, ``"degenerate"``, ``"mollify"``,
        ``"reorient"``, ``"merge-vertices"``, ``"drop-nonorientable"``), kept as the attribute ``kind``.
    count : int, optional
        How many elements were repaired (attribute ``count``).

    Examples
    --------
    >>> w = MeshRepairWarning("split 1 non-manifold vertex", kind="split", count=1)
    >>> isinstance(w, DhlbWarning), w.kind, w.count
    (True, 'split', 1)
    """

    def __init__(self, message: str = "", *, kind: str = "", count: int = 0):
        super().__init__(message)
        self.kind, self.count = str(kind), int(count)


class ShapeError(DhlbError, ValueError):
    """An array or matrix has the wrong shape or size (e.g. a non-square matrix, a length mismatch)."""


class InvalidOperatorError(DhlbError, ValueError):
    """A matrix is not Hermitian, not (semi)definite, or singular where the operation needs otherwise."""




class NotSemidefiniteError(InvalidOperatorError):
    """A matrix that must be positive semidefinite has an eigenvalue below the tolerance (found or proved).

    Raised by :func:`dhlb.linalg.smallest_eigenpairs` with its default ``psd=True``; pass
    ``psd=False`` for the smallest pairs of an indefinite matrix.

    Examples
    --------
    >>> issubclass(NotSemidefiniteError, InvalidOperatorError)
    True
    """


class InvalidMatrixError(DhlbError, ValueError):
    """A matrix or vector argument has the wrong shape or does not fit the operation.

    Also raised for a non-integer entry, or e.g. boundary matrices whose product is not zero.
    """




class InvalidParameterError(DhlbError, ValueError):
    """A numeric parameter (a dimension, a grid size, a lens-space pair, ...) is out of its range."""




class InvalidCochainError(DhlbError, ValueError):
    """Values of a discrete form or chain do not fit it.

    Wrong length, not integers (group Z), zero (group C*), an unknown coefficient group, or forms
    on different complexes/degrees combined.
    """


class CurveIntersectionError(DhlbError, ValueError):
    """Two curves whose linking number is asked for intersect (or touch to rounding accuracy)."""




class UnresolvedFluxWarning(DhlbWarning):
    """The curvature (flux) through some triangle exceeds π in modulus.

    The mesh does not resolve the feature there (e.g. a vortex core), so zeros of sections may be
    misplaced or lost.
    """




# --------------------------------------------------------------------------- outputs and budgets
class OutputError(DhlbError, OSError):
    """An output file cannot be written (disk full, no permission, missing folder, read-only file system).

    The message names the path; nothing half-written is left at that path.

    Parameters
    ----------
    path : str
        The output path.
    reason : str
        Why it cannot be written (e.g. the ``strerror`` of the underlying :class:`OSError`).

    Attributes
    ----------
    path, reason : str
        As given.

    Examples
    --------
    >>> err = OutputError("out/x.obj", "No space left on device")
    >>> print(err)
    cannot write out/x.obj: No space left on device
    >>> err.path, isinstance(err, OSError)
    ('out/x.obj', True)
    """

    def __init__(self, path: str, reason: str):
        super().__init__(f"cannot write {path}: {reason}")
        self.path = path
        self.reason = reason

    def __str__(self) -> str:  # OSError would print its args tuple
        return str(self.args[0]) if self.args else ""


class ViewerUnavailableError(DhlbError, RuntimeError):
    """No way to show a picture here: no display for a window, or no EGL/OpenGL for a headless screenshot.

    Examples
    --------
    >>> isinstance(ViewerUnavailableError("no display; pass screenshot="), RuntimeError)
    True
    """


class OverwriteError(DhlbError, ValueError):
    """An output path is (or resolves to) one of the input files; dhlb never replaces an input.

    Parameters
    ----------
    path : str
        The output path.
    role : str, optional
        What the file at ``path`` is, as a noun phrase (``"the input mesh"``).

    Attributes
    ----------
    path, role : str
        As given.

    Examples
    --------
    >>> print(OverwriteError("spot.obj", "the input mesh"))
    refusing to write spot.obj: it is the input mesh; choose another output name
    """

    def __init__(self, path: str, role: str = "an input file"):
        super().__init__(f"refusing to write {path}: it is {role}; choose another output name")
        self.path = path
        self.role = role


class ResourceLimitError(InvalidParameterError):
    """A parameter would make the work exceed the memory (or time) budget; refused before starting.

    The message names the parameter, its value, the estimate and the allowed range.

    Parameters
    ----------
    parameter : str
        The name of the parameter (e.g. a command-line option ``"--box"``).
    value : object
        Its value.
    estimate_bytes : float
        The estimated memory the work would need, in bytes.
    limit_bytes : float
        The memory allowed, in bytes.
    advice : str, optional
        What to do instead; appended to the message after ``"; "``.

    Attributes
    ----------
    parameter : str
        As given.
    value : object
        As given.
    estimate_bytes, limit_bytes : float
        As given, converted to float.

    Examples
    --------
    >>> err = ResourceLimitError("--box", 400, 3.1e11, 4e9, "use --box 150 or less")
    >>> print(err)
    --box = 400 needs about 310 GB of memory (estimate), more than the 4 GB allowed; use --box 150 or less
    >>> err.estimate_bytes > err.limit_bytes
    True
    """

    def __init__(self, parameter: str, value, estimate_bytes: float, limit_bytes: float, advice: str = ""):
        msg = (
            f"{parameter} = {value} needs about {format_bytes(estimate_bytes)} of memory (estimate), "
            f"more than the {format_bytes(limit_bytes)} allowed"
        )
        super().__init__(msg + (f"; {advice}" if advice else ""))
        self.parameter = parameter
        self.value = value
        self.estimate_bytes = float(estimate_bytes)
        self.limit_bytes = float(limit_bytes)


class InvalidTypeError(DhlbError, TypeError, ValueError):
    """An argument has the wrong kind of value: complex where reals are meant, text where numbers are.

    Examples
    --------
    >>> isinstance(InvalidTypeError("hbar must be a real number, got str '1'"), (TypeError, ValueError))
    True
    """




def format_bytes(n: float) -> str:
    """A byte count for messages: ``'310 GB'``, ``'12 MB'`` (decimal units, 2 significant digits).

    Parameters
    ----------
    n : float
        A number of bytes.

    Returns
    -------
    str
        ``n`` with at most 2 significant digits and the largest of the units TB, GB, MB, kB that is at most ``|n|``,
        or as a whole number of bytes (``'512 B'``) below 1 kB.

    Examples
    --------
    >>> format_bytes(3.1e11), format_bytes(12_345_678), format_bytes(512)
    ('310 GB', '12 MB', '512 B')
    """
    n = float(n)
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if abs(n) >= size:
            return f"{float(f'{n / size:.2g}'):g} {unit}"
    return f"{n:.0f} B"


def differing_digits(a: float, b: float, min_digits: int = 6) -> tuple[str, str]:
    """Format two floats with just enough significant digits that the printed texts differ.

    For messages that compare two numbers (e.g. :class:`CurvatureMismatchError`): ``%.6g`` can
    print two different numbers identically; this adds digits until they differ (at most 17,
    which is exact for float64).

    Parameters
    ----------
    a, b : float
        The two numbers.
    min_digits : int, optional
        The number of significant digits to start from.

    Returns
    -------
    sa, sb : str
        ``a`` and ``b`` with the fewest significant digits (at least ``min_digits``) at which the texts differ;
        their ``repr`` when they do not differ at 17 digits (equal numbers).

    Examples
    --------
    >>> differing_digits(1.0000001, 1.0000002)
    ('1.0000001', '1.0000002')
    >>> differing_digits(0.5, 0.25)
    ('0.5', '0.25')
    """
    a, b = float(a), float(b)
    for digits in range(min_digits, 18):
        sa, sb = f"{a:.{digits}g}", f"{b:.{digits}g}"
        if sa != sb:
            return sa, sb
    return repr(a), repr(b)
