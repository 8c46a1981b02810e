"""Ruff (pycodestyle, pyflakes, isort, bugbear, pyupgrade, numpy, ruff and numpydoc docstring rules,
configured in ``pyproject.toml``) is clean over the whole repository."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _ruff_command() -> list[str] | None:
    try:
        import ruff  # noqa: F401  (the PyPI package ships the binary)
    except ImportError:
        exe = shutil.which("ruff")
        return [exe] if exe else None
    return [sys.executable, "-m", "ruff"]


def test_ruff_check_is_clean():
    cmd = _ruff_command()
    if cmd is None:
        pytest.skip("ruff is not installed (pip install 'dhlb[test]' installs it)")
    proc = subprocess.run([*cmd, "check", ".", "--no-cache", "--output-format", "concise"], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"ruff check found problems:\n{proc.stdout}\n{proc.stderr}"
