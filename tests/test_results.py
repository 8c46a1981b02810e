"""Every result: to_json() -> dict, summary_rows(), save(path) by extension, a picture — through one base."""

from __future__ import annotations

import json

import numpy as np
import pytest

from dhlb._result import Result, plugin
from dhlb.conformal import conformal_deformation
from dhlb.errors import InvalidParameterError
from dhlb.fields import direction_field
from dhlb.io import example_path, read_surface
from dhlb.mesh import box_tet_mesh
from dhlb.stripes import stripe_pattern
from dhlb.vortex import uniform_flow, vortex_filaments


@pytest.fixture(scope="module")
def results():
    V, F = read_surface(example_path("torus.obj"))
    field = direction_field(V, F, n=2)
    return {
        "field": field,
        "stripes": stripe_pattern(field, frequency=2.0),
        "vortex": vortex_filaments(box_tet_mesh(2), None, uniform_flow([0.1, 0, 0]), hbar=1.0),
        "conformal": conformal_deformation(box_tet_mesh(1), None, 0.5),
    }


FORMATS = {"field": [".npz", ".ply", ".vtu"], "stripes": [".obj", ".vtu"], "vortex": [".obj", ".ply", ".vtu"],
           "conformal": [".npz", ".mesh", ".vtk", ".vtu"]}


@pytest.mark.parametrize("kind", sorted(FORMATS))
def test_one_base_and_a_json_summary(results, kind, tmp_path):
    res = results[kind]
    assert isinstance(res, Result)
    data = res.to_json()
    assert isinstance(data, dict) and data
    rows = res.summary_rows()
    assert rows and all(isinstance(label, str) for label, _ in rows)
    [path] = res.save(tmp_path / "r.json")
    assert json.loads(open(path, encoding="utf-8").read()) == json.loads(json.dumps(data, allow_nan=False))


@pytest.mark.parametrize("kind", sorted(FORMATS))
def test_save_by_extension(results, kind, tmp_path):
    pytest.importorskip("meshio")
    res = results[kind]
    for ext in FORMATS[kind]:
        paths = res.save(tmp_path / f"r{ext}")
        assert paths and all((tmp_path / p).exists() or __import__("os").path.exists(p) for p in paths)
    with pytest.raises(InvalidParameterError, match=r"cannot save a \w+ as '\.xyz'.*use \.json"):
        res.save(tmp_path / "r.xyz")
    assert not (tmp_path / "r.xyz").exists()


def test_field_npz_keeps_the_input_numbering(results, tmp_path):
    res = results["field"]
    [path] = res.save(tmp_path / "f.npz")
    with np.load(path) as z:
        assert z["directions"].shape == res.input_directions().shape
        assert np.array_equal(z["face_index"], res.input_face_index())
        assert "NaN" in str(z["note"])


@pytest.mark.parametrize("kind", ["field", "stripes", "vortex"])
def test_pictures_come_from_the_render_registry(results, kind):
    png = results[kind]._repr_png_()
    assert png.startswith(b"\x89PNG")
    assert "<table>" in results[kind]._repr_html_()


def test_plugins_are_declared_and_found():
    from dhlb.io.results import write
    from dhlb.render.registry import picture, show

    assert plugin("write") is write and plugin("picture") is picture and plugin("show") is show
    with pytest.raises(KeyError):
        plugin("nothing")


def test_write_refuses_what_is_no_result(tmp_path):
    with pytest.raises(InvalidParameterError, match="takes a result"):
        plugin("write")(object(), tmp_path / "x.json")


def test_vortex_to_json_is_a_dict_and_the_old_string_form_warns(results):
    res = results["vortex"]
    assert isinstance(res.to_json(), dict)
    with pytest.warns(DeprecationWarning, match="json.dumps"):
        text = res.to_json(indent=1)
    assert json.loads(text) == json.loads(json.dumps(res.to_json()))
    with pytest.warns(DeprecationWarning, match=r"to_json\(\)"):
        assert res.to_dict() == res.to_json()
