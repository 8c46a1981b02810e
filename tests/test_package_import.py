"""`import dhlb` is light (lazy submodules) and every layer is reachable as an attribute."""

import subprocess
import sys

import pytest


def _run(code):
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()


def test_import_dhlb_loads_no_layer_and_no_scipy():
    out = _run("import sys, dhlb; print(sorted(m for m in sys.modules if m.startswith('dhlb')), "
               "'scipy' in sys.modules, 'numpy' in sys.modules)")
    assert out == ["['dhlb']", "False", "False"]


@pytest.mark.parametrize("attr", ["fem.mass_matrix", "linalg.smallest_eigenpairs", "fields.direction_field",
                                  "stripes.stripe_pattern", "mesh.validate_surface", "vortex.vortex_filaments",
                                  "SimplicialComplex",
                                  "EuclideanComplex", "errors.DhlbError", "io.read_surface"])
def test_layers_are_attributes(attr):
    import dhlb

    obj = dhlb
    for part in attr.split("."):
        obj = getattr(obj, part)
    assert callable(obj)


def test_old_solver_module_is_a_deprecated_alias():
    out = _run("import warnings, sys; warnings.simplefilter('error'); "
               "exec('try:\\n import dhlb.fem.solvers\\nexcept DeprecationWarning as e:\\n print(\"deprecated\")')")
    assert out == ["deprecated"]
    import dhlb.fem
    import dhlb.linalg

    assert dhlb.fem.smallest_eigenpairs is dhlb.linalg.smallest_eigenpairs


def test_reading_a_mesh_file_does_not_load_the_mesh_machinery():
    # dhlb.io imported dhlb.mesh (and with it topology and scipy.sparse.csgraph) eagerly: 0.54 s against 0.18 s
    import subprocess
    import sys

    code = ("import sys, dhlb.io; "
            "print(sorted(m for m in ('dhlb.mesh.surface', 'dhlb.mesh.tet', 'dhlb.topology') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out
