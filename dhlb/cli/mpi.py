"""``dhlb`` under MPI: ``mpirun -n P python -m dhlb.cli.mpi COMMAND ...`` (the petsc backend, docs/mpi.md)."""

from __future__ import annotations

import contextlib
import io
import os
import sys
import tempfile

from dhlb.cli import _MPI_SIZE_VARIABLES, build_parser, main
from dhlb.cli._common import run_command
from dhlb.linalg.backends import _REGISTRY, register_backend
from dhlb.linalg.backends_petsc import PetscBackend, comm_rank_size, install_abort_hook

__all__ = ["launched_by_mpirun", "mpi_main"]



def launched_by_mpirun() -> bool:
    """Whether this process is one of several started by ``mpirun``/``mpiexec`` (read from the environment).

    ``dhlb ...`` then runs as :func:`mpi_main`; no MPI library is loaded to find out.

    Examples
    --------
    >>> isinstance(launched_by_mpirun(), bool)
    True
    """
    import os

    import dhlb.cli

    if dhlb.cli._MPI_MAIN_RUNNING:
        return False
    for name in _MPI_SIZE_VARIABLES:
        try:
            if int(os.environ.get(name, "1")) > 1:
                return True
        except ValueError:
            continue
    return False


def mpi_main(argv=None) -> int:
    """``dhlb`` under MPI: every rank runs the command, rank 0 alone reads the mesh, writes outputs and prints.

    Run as ``mpirun -n P dhlb field MESH --backend petsc -o OUT`` (``dhlb`` comes here when started by
    mpirun) or ``mpirun -n P python -m dhlb.cli.mpi ...``. With ``--backend petsc``, ``field`` (smoothest)
    and ``vortex`` run distributed (:mod:`dhlb.fields.distributed`, :mod:`dhlb.vortex.distributed`: no
    rank holds a global matrix); the other commands run the replicated petsc backend, and ranks other
    than 0 write their copy of the outputs into a private temporary directory (deleted afterwards).
    Ranks other than 0 print nothing; the exit code is the largest over all ranks, and a rank whose
    command failed while the others wait in a collective call ends the run after
    :data:`GRACE_SECONDS`.

    Parameters
    ----------
    argv : list of str, optional
        The arguments after ``dhlb`` (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit code, the largest over all ranks (0 ok, 1 failure, 2 usage error).

    Examples
    --------
    >>> mpi_main(["--version"])  # doctest: +ELLIPSIS
    dhlb ...
    0
    """
    import dhlb.cli

    if "petsc" not in _REGISTRY:
        register_backend("petsc", PetscBackend, ("petsc4py", "slepc4py", "mpi4py"))
    # dhlb.cli.main, called below, must not come back here (the flag lives in dhlb.cli, never run as __main__:
    # `python -m dhlb.cli.mpi` imports this module a second time under its own name)
    dhlb.cli._MPI_MAIN_RUNNING = True
    rank, size = comm_rank_size()
    argv = list(sys.argv[1:] if argv is None else argv)
    if size == 1:
        return main(argv)
    install_abort_hook()
    if rank == 0:
        code = main(argv)
    else:
        with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()), \
                contextlib.redirect_stderr(io.StringIO()):
            try:
                args, extra = build_parser().parse_known_args(argv)
            except SystemExit as exc:
                args, extra, code = None, [], exc.code if isinstance(exc.code, int) else 2
            if args is not None and not extra and getattr(args, "command", None):
                out = getattr(args, "output", None)
                if isinstance(out, str) and out not in ("", "-"):
                    args.output = os.path.join(tmp, os.path.basename(os.path.normpath(out)) or "out")
                code = run_command(args)
            elif args is not None:
                code = 2
    from mpi4py import MPI  # present: comm_rank_size() returned size > 1

    _leave_together(MPI.COMM_WORLD, int(code))
    return int(MPI.COMM_WORLD.allreduce(int(code), op=MPI.MAX))


GRACE_SECONDS = 20.0
"""How long a rank whose command failed waits for the others before it ends the whole run (``MPI_Abort``)."""


def _leave_together(comm, code: int) -> None:
    """Wait until every rank has finished its command; a failed rank ends all ranks if the others do not come.

    An error found by all ranks together (bad input found on rank 0 is raised on every rank) lets every
    rank arrive here. An error on one rank only (its local part) leaves the others waiting inside a
    collective call: the failed rank, having printed its one error line, then calls ``MPI_Abort``.
    """
    import time

    req = comm.Ibarrier()
    deadline = time.monotonic() + GRACE_SECONDS
    while not req.Test():
        if code != 0 and time.monotonic() > deadline:
            sys.stderr.flush()
            comm.Abort(code)
        time.sleep(0.005)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(mpi_main())
