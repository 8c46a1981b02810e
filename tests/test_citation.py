"""CITATION.cff: valid Citation File Format 1.2.0, same version as the package, cites the seed's work."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CFF = ROOT / "CITATION.cff"
REQUIRED = ("cff-version", "message", "title", "authors", "version", "license", "references")


def _top_level(text):
    """``{key: raw value}`` of the top-level keys (no YAML library needed)."""
    out = {}
    for line in text.splitlines():
        m = re.match(r"^([A-Za-z][\w-]*):\s*(.*)$", line)
        if m:
            out[m.group(1)] = m.group(2).strip().strip('"')
    return out


def test_required_keys_and_version_match_pyproject():
    keys = _top_level(CFF.read_text(encoding="utf-8"))
    missing = [k for k in REQUIRED if k not in keys]
    assert not missing, f"CITATION.cff lacks {missing}"
    assert keys["cff-version"] == "1.2.0"
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")  # tomllib is Python >= 3.11 only
    project = pyproject.split("[project]", 1)[1].split("\n[", 1)[0]
    assert keys["version"] == re.search(r'^version = "(.*)"$', project, flags=re.M).group(1)
    assert keys["license"] == re.search(r'^license = "(.*)"$', project, flags=re.M).group(1)


def test_references_cite_the_dissertation_and_the_papers():
    text = CFF.read_text(encoding="utf-8")
    titles = re.findall(r'^\s+title:\s*"(.*)"$', text, flags=re.M)
    for title in ("Complex Line Bundles over Simplicial Complexes and their Applications",
                  "Globally Optimal Direction Fields", "Stripe Patterns on Surfaces", "Smoke Rings from Smoke"):
        assert title in titles


def _validate(path):
    create_citation = pytest.importorskip("cffconvert.cli.create_citation").create_citation
    create_citation(str(path), None).validate()


def test_cffconvert_validates():
    _validate(CFF)


def test_cffconvert_rejects_a_broken_copy(tmp_path):
    """The validation above can fail: the same file without its authors is refused."""
    text = CFF.read_text(encoding="utf-8")
    broken = re.sub(r'^authors:\n  - name: "dhlb developers"\n', "", text, flags=re.M)
    assert broken != text
    (tmp_path / "CITATION.cff").write_text(broken, encoding="utf-8")
    with pytest.raises(Exception, match="authors"):
        _validate(tmp_path / "CITATION.cff")
