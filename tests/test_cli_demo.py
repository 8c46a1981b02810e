"""``dhlb demo``: the main job runs on the bundled data, its checks pass, and index.html shows every picture."""

from __future__ import annotations

import json
import re

import pytest

from dhlb.cli import main

pytest.importorskip("matplotlib")

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    return out


def test_demo_runs_all_steps_and_passes_its_checks(demo, capsys):
    code = main(["demo", "-o", str(demo), "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert code == 0
    assert summary["checks_passed"] is True
    steps = [s["step"] for s in summary["steps"]]
    assert sum(s.startswith("field") for s in steps) == 9          # n = 1, 2, 4 × s = −1, 0, 1
    assert any(s.startswith("aligned") for s in steps) and any(s.startswith("boundary") for s in steps)
    assert "stripes" in steps and "vortex ring" in steps and "vortex linked-rings" in steps
    for s in summary["steps"]:
        if s["step"].startswith("field"):                          # Poincaré–Hopf on Spot (χ = 2)
            assert s["details"]["index_sum"] == s["details"]["n"] * 2
    linked = next(s for s in summary["steps"] if s["step"] == "vortex linked-rings")
    assert abs(linked["details"]["linking_numbers"][0][1]) == 1
    # what a reader sees (issue 42, point 9): "1 filament", not "1 filaments"; "s = 0", not "s = +0"
    ring = next(s for s in summary["steps"] if s["step"] == "vortex ring")
    assert ring["result"].startswith("1 filament (")
    for s in summary["steps"]:
        assert "+0" not in s["step"] + s["caption"] and not re.search(r"\b1 (filaments|singularities)\b", s["result"])

    page = (demo / "index.html").read_text(encoding="utf-8")
    sources = re.findall(r'<img src="([^"]+)"', page)
    assert len(sources) == 2 * len(summary["steps"])                 # every result seen front and back
    assert sum(src.endswith("-back.png") for src in sources) == len(summary["steps"])
    assert "conformal Möbius" in steps and "conformal charges" in steps
    for src in sources:
        data = (demo / src).read_bytes()
        assert data[:8] == PNG_MAGIC, src
        assert len(data) > 5000, f"{src} is suspiciously small"
    assert (demo / "stripes.obj").exists() and (demo / "vortex-ring.obj").exists()
    if summary["web"]["views"]:                                      # with dhlb[web]: one view per result
        assert summary["web"]["views"] == len(summary["steps"]) == page.count('class="dhlb-rotate"')
        views = sum(f.stat().st_size for f in demo.glob("*.html") if f.name != "index.html" and "-views" not in f.name)
        assert summary["web"]["bytes"] == views + (demo / "plotly.min.js").stat().st_size
        assert summary["web"]["bytes"] < summary["web"]["folder_bytes"]


def test_demo_rejects_unknown_steps(tmp_path, capsys):
    assert main(["demo", "-o", str(tmp_path), "--only", "fields,nonsense"]) == 2
    assert "nonsense" in capsys.readouterr().err


def test_demo_output_must_be_a_directory(tmp_path, capsys):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["demo", "-o", str(f)]) == 2
    assert "not a directory" in capsys.readouterr().err
