"""Every exception class of dhlb.errors is documented in the one table of docs/api/errors.md."""

import inspect
import pathlib

import dhlb.errors as E

DOC = pathlib.Path(__file__).resolve().parents[1] / "docs" / "api" / "errors.md"


def test_every_exception_is_in_the_table():
    text = DOC.read_text(encoding="utf-8")
    classes = [n for n in E.__all__ if inspect.isclass(getattr(E, n))]
    missing = [n for n in classes if f"| `{n}` |" not in text]
    assert not missing, f"add these to the table in docs/api/errors.md: {missing}"


def test_errors_are_typed_and_exported_once():
    assert len(E.__all__) == len(set(E.__all__))
    for n in E.__all__:
        obj = getattr(E, n)
        if inspect.isclass(obj):
            assert issubclass(obj, (E.DhlbError, E.DhlbWarning)), n
