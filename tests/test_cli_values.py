"""Every numeric value of every ``dhlb`` subcommand is checked at parse time: a bad one exits 2 naming the option.

The options are found by walking :func:`dhlb.cli.build_parser`; the bad values of each are built from its
argparse ``type`` (issue 28 C). An option with an unchecked ``type=int``, or an untyped option that is not
listed below as text, fails :func:`test_every_option_value_is_checked_or_declared_text`.
"""

from __future__ import annotations

import argparse

import pytest

from dhlb.cli import build_parser, main
from dhlb.cli._common import backend_choice, nonempty_text, repair_choice
from dhlb.cli.field import parse_singularity
from dhlb.io import example_path

TEXT_OPTIONS = {  # (command, option) whose values are text (paths, names, specs), not numbers
    ("conformal", "mesh"), ("conformal", "--format"), ("conformal", "--u"),
    ("field", "mesh"), ("field", "--align"), ("field", "--format"),
    ("stripes", "file"), ("stripes", "--field"), ("stripes", "--format"),
    ("view", "base"), ("view", "--screenshot"), ("view", "--html"),
    ("vortex", "mesh"), ("vortex", "--format"),
    ("info", "file"), ("info", "--format"), ("demo", "--only"),
}
COMMON = {"-o", "--output"}


def _name(action) -> str:
    return action.option_strings[-1] if action.option_strings else action.dest


def _value_actions():
    """``(command, action)`` for every option of every subcommand that takes a value."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for command, p in sorted(sub.choices.items()):
        for action in p._actions:
            if action.nargs == 0 or COMMON & set(action.option_strings):
                continue  # flags (--json, --quiet, --help) and the common -o
            yield command, action


def _bad_and_good(action) -> tuple[list[str], str] | None:
    """Values the option's type must refuse, and one it must accept; None for an unchecked type."""
    t = action.type
    if action.choices is not None:
        allowed = {str(c) for c in action.choices}
        return [b for b in ("-3", "0", "3", "nan", "1e400", "no-such-choice") if b not in allowed], str(
            next(iter(action.choices)))
    bounds = getattr(t, "bounds", None)
    if bounds is not None and len(bounds) == 2:                       # int_in_range(low, high)
        low, high = bounds
        return [str(low - 1), str(high + 1), "-3", "1.5", "nan", "inf", "1e400", "x"], str(low)
    if bounds is not None and len(bounds) == 4:                       # finite_float(low, high, ...)
        low, high, low_open, high_open = bounds
        bad = ["nan", "inf", "-inf", "1e400", "-1e400", "x"]
        if low is not None:
            bad.append(repr(float(low)) if low_open else repr(low - 1.0))
        if high is not None:
            bad.append(repr(float(high)) if high_open else repr(high + 1.0))
        lo, hi = (-1.0 if low is None else low), (1.0 if high is None else high)
        good = 0.5 * (lo + hi) if low is None or high is None or lo < hi else lo
        good = lo + 1.0 if high is None and low is not None else hi - 1.0 if low is None and high is not None else good
        return bad, repr(good)
    if hasattr(t, "count"):                                           # number_tuple("X,Y,Z")
        k = t.count
        ones = ["1"] * k
        return [",".join(ones[:-1]), ",".join(ones + ["1"]), ",".join(["nan"] + ones[1:]),
                ",".join(ones[:-1] + ["inf"]), ",".join(["1e400"] * k), ",".join(["x"] * k)], ",".join(ones)
    if t is nonempty_text:
        return ["", "  "], "ring"
    if t is parse_singularity:
        return ["nan,0,0:1", "0,0,inf:1", "-3:1", "0:1.5", "0:x", "1,2:1", "0"], "0:1"
    if t is backend_choice:
        return ["bogus", "", "SUPERLU", "super lu", "auto,superlu"], "superlu"
    if t is repair_choice:
        return ["splt", "safe,none", "none,split", "3", "safe,bogus"], "safe,merge-vertices"
    return None


CASES = [(c, a) for c, a in _value_actions() if (c, _name(a)) not in TEXT_OPTIONS]


def test_every_option_value_is_checked_or_declared_text():
    unchecked = [f"dhlb {c} {_name(a)} (type {getattr(a.type, '__name__', a.type)})"
                 for c, a in CASES if _bad_and_good(a) is None]
    assert not unchecked, ("options without a parse-time check (give them a type from dhlb.cli._common, or list "
                           f"text options in TEXT_OPTIONS): {unchecked}")
    assert len(CASES) >= 15                                     # the walk found the numeric options
    assert {"--n", "--s", "--lambda", "--spacing", "--size", "--box", "--view", "--charge"} <= {_name(a)
                                                                                               for _, a in CASES}


@pytest.mark.parametrize("command, action", CASES, ids=[f"{c} {_name(a)}" for c, a in CASES])
def test_bad_values_exit_2_naming_the_option(command, action, capsys):
    cases = _bad_and_good(action)
    assert cases is not None, f"{_name(action)} has no parse-time check"
    bad, good = cases
    assert bad
    conv = action.type or str
    conv(good)                                                  # the check does not refuse everything
    for value in bad:
        code = main([command, f"{_name(action)}={value}"])
        err = capsys.readouterr().err
        assert code == 2, (command, _name(action), value, err)
        assert f"argument {'/'.join(action.option_strings)}:" in err, (value, err)


def test_n_minus_3_is_a_usage_error(tmp_path, capsys):
    # issue 28: exited 1 ("n must be an integer >= 1", raised by the library) before
    code = main(["field", example_path("torus.obj"), "--n", "-3", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and "argument --n: -3 is out of range" in err, err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv, words", [
    (["view", "x", "--view", "1,nan,0"], "argument --view: '1,nan,0' is not three finite numbers X,Y,Z"),
    (["conformal", "--charge", "0,0,2"], "argument --charge: '0,0,2' is not four finite numbers X,Y,Z,Q"),
    (["stripes", "m.obj", "--spacing", "0"], "argument --spacing: '0' is out of range: give a finite number > 0"),
    (["field", "m.obj", "--s", "inf"], "argument --s: 'inf' is not a finite number in [-1, 1]"),
    (["vortex", "--circulation", "1e400"], "argument --circulation: '1e400' is not a finite number"),
])
def test_messages_name_the_option_and_the_range(argv, words, capsys):
    assert main(argv) == 2
    assert words in capsys.readouterr().err
