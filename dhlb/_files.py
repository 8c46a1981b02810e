"""Safe output files (layer 0, used by every writer): write to a temporary file and rename, never replace an input.

Small tools every writer and command uses:

* :func:`atomic_write` — a context manager that opens a temporary file next to the target and
  renames it onto the target only when the ``with`` block finishes without an error. An
  interrupted or failed run leaves the target as it was (absent or the old file) and no
  temporary file. ``OSError`` (disk full, no permission, missing folder) becomes
  :class:`~dhlb.errors.OutputError`, a one-line message naming the path.
* :func:`atomic_path` — the same for writers that need a file name (meshio, matplotlib): a
  temporary path with the target's extension, renamed onto the target at the end.
* :func:`refuse_overwrite` — raises :class:`~dhlb.errors.OverwriteError` when an output path
  is one of the input files (same path after resolving symlinks and ``..``, or the same file
  through a hard link).

Examples
--------
>>> import os, tempfile
>>> from dhlb._files import atomic_write, refuse_overwrite
>>> with tempfile.TemporaryDirectory() as d:
...     out = os.path.join(d, "result.txt")
...     refuse_overwrite([out], [os.path.join(d, "mesh.obj")])
...     with atomic_write(out) as fh:
...         _ = fh.write("done")
...     print(open(out).read(), sorted(os.listdir(d)))
done ['result.txt']
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Iterable, Iterator
from typing import IO, Any

from dhlb.errors import OutputError, OverwriteError

__all__ = ["atomic_path", "atomic_write", "refuse_overwrite", "output_error"]


def output_error(path: str | os.PathLike[str], exc: OSError) -> OutputError:
    """The :class:`~dhlb.errors.OutputError` for an ``OSError`` met while writing ``path``.

    Examples
    --------
    >>> import errno
    >>> print(output_error("a/b.obj", OSError(errno.ENOSPC, "No space left on device")))
    cannot write a/b.obj: No space left on device (the disk is full)
    """
    import errno

    reason = exc.strerror or str(exc) or type(exc).__name__
    hint = {
        errno.ENOSPC: " (the disk is full)",
        errno.EDQUOT: " (the disk quota is exceeded)",
        errno.EFBIG: " (the file size limit is exceeded)",
        errno.EACCES: " (no permission; choose another folder)",
        errno.EPERM: " (no permission; choose another folder)",
        errno.EROFS: " (read-only file system)",
        errno.ENOENT: " (the folder does not exist)",
        errno.EISDIR: " (it is a directory)",
        errno.ENOTDIR: " (a part of the path is not a folder)",
    }.get(exc.errno or 0, "")
    return OutputError(os.fspath(path), reason + hint)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[str]:
    """A temporary path beside ``path`` (same extension) that is renamed onto ``path`` at the end.

    For writers that want a file name rather than a file object (meshio, matplotlib's format
    detection). The target appears (or is replaced) only when the ``with`` block ends normally;
    otherwise the temporary file is removed.

    Raises
    ------
    OutputError
        ``path`` is a directory, or an ``OSError`` (missing folder, no permission, disk full) met
        while writing or renaming (one line naming ``path``).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     with atomic_path(os.path.join(d, "a.txt")) as tmp:
    ...         _ = open(tmp, "w").write("x")
    ...         hidden = os.path.basename(tmp).startswith(".") and tmp.endswith(".txt")
    ...     print(hidden, os.listdir(d))
    True ['a.txt']
    """
    path = os.fspath(path)
    if os.path.isdir(path):
        raise OutputError(path, "it is a directory; give a file name")
    folder, name = os.path.split(os.path.abspath(path))
    stem, ext = os.path.splitext(name)
    tmp = os.path.join(folder, f".{stem}.{secrets.token_hex(4)}.tmp{ext}")
    try:
        yield tmp
        os.replace(tmp, path)
    except OSError as exc:
        _remove(tmp)
        raise output_error(path, exc) from None
    except BaseException:
        _remove(tmp)
        raise


@contextlib.contextmanager
def atomic_write(
    path: str | os.PathLike[str], mode: str = "w", encoding: str | None = "utf-8"
) -> Iterator[IO[Any]]:
    """Open ``path`` for writing through a temporary file renamed onto it at the end.

    Parameters
    ----------
    path : str or path-like
        The target file. Its folder must exist.
    mode : {'w', 'wb'}
        Text or binary.
    encoding : str or None
        Text encoding (text mode only).

    Yields
    ------
    file object
        Write to it; the target appears (or is replaced) only when the block ends normally.

    Raises
    ------
    OutputError
        The folder does not exist, is not writable, the disk is full, or ``path`` is a directory
        (one line naming ``path``). The temporary file is removed.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "x.bin")
    ...     with atomic_write(p, "wb") as fh:
    ...         _ = fh.write(b"abc")
    ...     try:
    ...         with atomic_write(p, "wb") as fh:
    ...             _ = fh.write(b"half")
    ...             raise KeyboardInterrupt
    ...     except KeyboardInterrupt:
    ...         pass
    ...     print(open(p, "rb").read(), os.listdir(d))
    b'abc' ['x.bin']
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_write mode must be 'w' or 'wb', got {mode!r}")
    with atomic_path(path) as tmp:
        try:
            fh = open(tmp, mode.replace("w", "x"), **({"encoding": encoding} if mode == "w" else {}))
        except OSError as exc:
            raise output_error(path, exc) from None
        with fh:
            yield fh
            fh.flush()


def _remove(tmp: str) -> None:
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def _same_file(a: str, b: str) -> bool:
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist
        return False


def refuse_overwrite(
    output_paths: Iterable[str | os.PathLike[str] | None],
    input_paths: Iterable[str | os.PathLike[str] | None],
    role: str = "an input file",
) -> None:
    """Raise :class:`~dhlb.errors.OverwriteError` if an output path is one of the inputs.

    Paths are compared after resolving symlinks and ``..`` and by file identity (hard links);
    ``None`` and ``'-'`` (stdout) entries are ignored. Two outputs that are the same file are
    refused too (the second would replace the first).

    Parameters
    ----------
    output_paths, input_paths : iterable of (str or path-like or None)
        The files to be written and the files read.
    role : str
        How the message calls an input ("the input mesh", ...).

    Raises
    ------
    OverwriteError
        An output path is the same file as an input path, or as an earlier output path.

    Examples
    --------
    >>> refuse_overwrite(["out.obj"], ["in.obj"])
    >>> refuse_overwrite(["./sub/../in.obj"], ["in.obj"], role="the input mesh")
    Traceback (most recent call last):
    ...
    dhlb.errors.OverwriteError: refusing to write ./sub/../in.obj: it is the input mesh; choose another output name
    """
    outs = [os.fspath(p) for p in output_paths if p is not None and os.fspath(p) != "-"]
    ins = [os.fspath(p) for p in input_paths if p is not None and os.fspath(p) != "-"]
    for out in outs:
        for inp in ins:
            if _same_file(out, inp):
                raise OverwriteError(out, role if role != "an input file" else f"the input file {inp}")
    for i, a in enumerate(outs):
        for b in outs[i + 1 :]:
            if _same_file(a, b):
                raise OverwriteError(b, f"also the output {a}")
