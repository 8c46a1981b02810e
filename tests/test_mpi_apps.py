"""The distributed applications (field, vortex) under ``mpirun -n 1, 2, 3``: skipped without petsc4py and mpirun.

Runs tests/mpi/app_checks.py (owned rows bit for bit equal to the serial assembly, eigenvalues and
singularities equal to the default backend's, the linked rings) for P = 1, 2 and 3 ranks (oversubscribed
on a 2-core machine) and compares the runs with each other; and the command line under ``mpirun -n 2``:
``dhlb field --backend petsc`` writes the default backend's singularities, a bad mesh ends every rank
with one error line.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from dhlb.linalg.backends_petsc import petsc_available
from tests.mpi_launch import MPIRUN, mpirun

ROOT = Path(__file__).resolve().parents[1]
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not (petsc_available() and MPIRUN), reason="needs petsc4py/slepc4py and mpirun")]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    out = {}
    for n in (1, 2, 3):
        path = tmp_path_factory.mktemp(f"p{n}") / "out.json"
        proc, _ = mpirun(n, [str(ROOT / "tests" / "mpi" / "app_checks.py"), str(path)])
        assert proc.returncode == 0, proc.stdout + proc.stderr
        out[n] = json.loads(path.read_text())
    return out


@pytest.mark.parametrize("n", [1, 2, 3])
def test_every_check_passes(runs, n):
    assert all(v["ok"] for v in runs[n].values()), runs[n]


def test_owned_rows_are_the_serial_rows_and_parts_are_balanced(runs):
    for n in (1, 2, 3):
        r = runs[n]["check_field_rows_bitwise"]
        assert r["bitwise_rows"] and len(r["owned"]) == n
        N = sum(r["owned"])
        assert all(loc < N for loc in r["local"]) or n == 1       # no rank holds the whole mesh
        assert runs[n]["check_tet_rows_bitwise"]["bitwise_rows"]


def test_results_do_not_depend_on_the_rank_count(runs):
    f = [runs[n]["check_field"] for n in (1, 2, 3)]
    assert f[0]["sing_faces"] == f[1]["sing_faces"] == f[2]["sing_faces"]
    assert f[0]["sing_index"] == f[1]["sing_index"] == f[2]["sing_index"]
    lam = [x["eigenvalue"] for x in f]
    assert max(abs(x / lam[0] - 1) for x in lam) <= 1e-12
    v = [runs[n]["check_vortex"] for n in (1, 2, 3)]
    assert v[0]["n_filaments"] == v[1]["n_filaments"] == v[2]["n_filaments"] == 2
    for a in v[1:]:
        assert _curve_distance(v[0]["points"], a["points"]) <= 1e-10


def _curve_distance(A, B) -> float:
    """The largest point distance between two sets of closed polylines, matched up to order and start point."""
    worst = 0.0
    for p in A:
        p, best = np.array(p), np.inf
        for q in B:
            q = np.array(q)
            if q.shape == p.shape:
                k = int(np.argmin(np.linalg.norm(q - p[0], axis=1)))  # loops start at the smallest crossing
                best = min(best, np.abs(np.roll(q, -k, axis=0) - p).max())   # in the numbering of the run
        worst = max(worst, best)
    return worst


def test_command_line_field_on_two_ranks_writes_the_default_fields_singularities(tmp_path):
    mesh = str(ROOT / "tests" / "data" / "bunny-7k.obj")
    proc, _ = mpirun(2, ["-m", "dhlb", "field", mesh, "--n", "4", "--backend", "petsc", "--no-png",
                          "-o", str(tmp_path / "field")])
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.count("34 singularities") == 1           # rank 0 alone prints
    from dhlb.cli import main

    assert main(["field", mesh, "--n", "4", "--no-png", "-q", "-o", str(tmp_path / "ref")]) == 0
    got, ref = (json.loads((tmp_path / f"{b}.json").read_text()) for b in ("field", "ref"))
    assert abs(got["eigenvalue"] / ref["eigenvalue"] - 1) < 1e-12
    assert got["solver"]["parallel"]["ranks"] == 2
    a, b = np.load(tmp_path / "field.npz"), np.load(tmp_path / "ref.npz")
    for key in ("singular_faces", "singular_index", "face_index"):
        assert np.array_equal(a[key], b[key]), key
    ua, ub = a["u"], b["u"]                 # the same section up to the eigenvector's arbitrary phase
    phase = np.vdot(ub, ua) / abs(np.vdot(ub, ua))
    assert np.abs(ua - phase * ub).max() <= 1e-6 * np.abs(ub).max()


def test_command_line_vortex_on_two_ranks_finds_the_linked_rings(tmp_path):
    proc, _ = mpirun(2, ["-m", "dhlb", "vortex", "--box", "16", "--velocity", "linked-rings",
                          "--backend", "petsc", "--json"])
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    assert len(data["filaments"]) == 2 and all(f["closed"] for f in data["filaments"])
    assert data["linking_numbers"] == [[0, 1], [1, 0]]


def test_a_bad_mesh_ends_every_rank_with_one_error_line(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n")
    proc, elapsed = mpirun(2, ["-m", "dhlb", "field", str(bad), "--backend", "petsc", "--no-png",
                                "-o", str(tmp_path / "out")], timeout=120)
    assert proc.returncode != 0 and elapsed < 60
    lines = [ln for ln in proc.stderr.splitlines() if "error" in ln.lower()]
    assert len(lines) == 1 and "line 3" in lines[0] and "non-finite" in lines[0], proc.stderr


def test_command_line_stripes_on_two_ranks_gives_the_default_zeros(tmp_path):
    # stripes has no distributed driver yet: every rank solves the whole problem through the petsc backend
    mesh = str(ROOT / "tests" / "data" / "bunny-7k.obj")
    proc, _ = mpirun(2, ["-m", "dhlb", "stripes", mesh, "--spacing", "6", "--backend", "petsc",
                          "--no-png", "-q", "-o", str(tmp_path / "s.obj")])
    assert proc.returncode == 0, proc.stderr
    from dhlb.cli import main

    assert main(["stripes", mesh, "--spacing", "6", "--no-png", "-q", "-o", str(tmp_path / "ref.obj")]) == 0
    got, ref = (json.loads((tmp_path / f"{b}.json").read_text()) for b in ("s", "ref"))
    assert got["zeros"]["faces"] == ref["zeros"]["faces"] and got["zeros"]["index"] == ref["zeros"]["index"]


def test_command_line_conformal_on_two_ranks_gives_the_default_eigenvalue():
    # conformal has no distributed driver yet: every rank solves the whole problem through the petsc backend
    mesh = str(ROOT / "tests" / "data" / "octopus-low-tet.mesh")
    proc, _ = mpirun(2, ["-m", "dhlb", "conformal", mesh, "--backend", "petsc", "--json"])
    assert proc.returncode == 0, proc.stderr
    got = json.loads(proc.stdout)
    assert got["statistics"]["solver"]["backend"] == "petsc"
    import contextlib
    import io

    from dhlb.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["conformal", mesh, "--json"]) == 0
    ref = json.loads(out.getvalue())
    assert abs(got["eigenvalue"] / ref["eigenvalue"] - 1) < 1e-8
