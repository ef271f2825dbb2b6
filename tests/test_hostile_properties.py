"""Property-based hostile input: model files and command lines drawn at random (issue 23, "Tests").

Two strategies, next to the element and scene strategies of ``test_properties.py``:

- model files: the TOML text of valid models (the presets written out by
  ``dumps_model``, the compressor example, a Jeffcott rotor with a ``[run]``
  table), then mutated: a value replaced by a hostile literal (negative, huge,
  ``nan``, a string, an array, a table, a path, a NUL byte), a line deleted,
  doubled or inserted, the text cut short, stray characters;
- command lines: for every command, its positional scene (a preset, a model
  file, a missing path, a folder, ``/dev/null``) and a random subset of its own
  options (read from the parser itself, so a new option is fuzzed too) with
  values drawn from numbers, ranges, orders, assignments, paths and garbage.

Properties: reading a model file gives a Model or a ``RotorkitError`` (never
another exception); a command returns 0 or exits 2 with a message on stderr,
never raising; nothing takes more than a few seconds (an alarm fails a hang);
nothing is written outside the temporary folder. Commands stop where the work
would begin (``Model.compile`` and the equation printer raise a sentinel), so
a run that the arguments allow counts as accepted without running.
Deterministic (``derandomize``) and fast: the whole file runs in about half a
minute.
"""

import contextlib
import signal
import string
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, note, settings
from hypothesis import strategies as st

import rotorkit as rk
from rotorkit.errors import RotorkitError
from rotorkit.modelfile import dumps_model, loads_model

ROOT = Path(__file__).resolve().parent.parent
SETTINGS = dict(derandomize=True, database=None, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])
#: seconds one example may take before it counts as a hang
ALARM = 20

JEFFCOTT = """\
format = "rotorkit-model"
version = 1
name = "jeffcott"

[[element]]
type = "Rotor"
name = "R"
stations = [1]
speed = "3000 rpm"

[[element]]
type = "Disk"
station = 1
mass = 2.0
radius = 0.1
eccentricity = "20 um"

[[element]]
type = "ElasticSupport"
station = 1
stiffness = 2e4
damping = 8.0

[[element]]
type = "RubStator"
station = 1
clearance = 1e-4
contact_stiffness = 1e6
friction_coefficient = 0.1

[run]
bending = "x1"
orbit_station = 1
clearance_parameter = "rub1_clearance"
"""


@pytest.fixture(scope="module")
def base_files():
    texts = [JEFFCOTT, (ROOT / "examples" / "compressor.toml").read_text()]
    for name in ("al31f", "rig"):
        texts.append(dumps_model(rk.preset(name)))
    for text in texts:
        assert isinstance(loads_model(text)[0], rk.Model)  # control: every base is a valid model file
    return texts


@contextlib.contextmanager
def alarm(seconds=ALARM):
    def hung(signum, frame):
        raise AssertionError(f"no answer within {seconds} s: a hang")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


# -- model files ------------------------------------------------------------------------------------------------
HOSTILE_LITERALS = [
    "-1.0", "0", "0.0", "-0.0", "1e308", "1e-320", "nan", "inf", "-inf", "99999999999999999999999999", "-5",
    '"3000 rpm"', '"1 kg"', '"abc"', '""', '"-1 m"', '"1e999 N/m"', '"2 ** 1000"', '"../../../tmp/escape"',
    '"x1"', '"x99"', '"\\u0000"', "true", "[]", "[1, 2]", "[[1], [2]]", '["a", 1]', "{}", "{ a = 1 }",
    '{ type = "Material" }', "1979-05-27", '"\U0001F600"', '"ﬁ"', "[" * 40 + "]" * 40,
]
KEYS = ["mass", "stiffness", "station", "stations", "speed", "radius", "name", "type", "elements", "clearance",
        "contact_stiffness", "n_balls", "inner_race_radius", "outer_race_radius", "length", "outer_diameter",
        "bending", "torsion", "orbit_station", "clearance_parameter", "format", "version", "material", "table",
        "speed_ratio", "reference", "kxx", "kzz", "friction_coefficient", "eccentricity"]


@st.composite
def model_files(draw, bases):
    """(description, text): a valid model file, mutated zero to four times."""
    lines = draw(st.sampled_from(bases)).splitlines()
    done = []
    for _ in range(draw(st.integers(0, 4))):
        kind = draw(st.sampled_from(["value", "value", "value", "delete", "double", "insert", "cut", "chars"]))
        i = draw(st.integers(0, max(len(lines) - 1, 0)))
        if kind == "value":
            assigned = [k for k, line in enumerate(lines) if " = " in line and not line.startswith("#")]
            if not assigned:
                continue
            k = draw(st.sampled_from(assigned))
            key = lines[k].split(" = ", 1)[0]
            lines[k] = f"{key} = {draw(st.sampled_from(HOSTILE_LITERALS))}"
            done.append(f"{key} = ...")
        elif kind == "delete" and lines:
            done.append(f"deleted {lines.pop(i)!r}")
        elif kind == "double" and lines:
            lines.insert(i, lines[i])
            done.append(f"doubled {lines[i]!r}")
        elif kind == "insert":
            line = f"{draw(st.sampled_from(KEYS))} = {draw(st.sampled_from(HOSTILE_LITERALS))}"
            lines.insert(i, line)
            done.append(f"inserted {line!r}")
        elif kind == "cut":
            lines = lines[:i]
            done.append(f"cut at line {i}")
        elif kind == "chars":
            junk = draw(st.text(alphabet=string.printable + "\x00é☃\ufeff", min_size=1, max_size=6))
            lines.insert(i, junk)
            done.append(f"inserted {junk!r}")
    return "; ".join(done) or "unchanged", "\n".join(lines) + "\n"


def test_mutated_model_files_give_a_model_or_a_named_error(base_files):
    @settings(max_examples=150, **SETTINGS)
    @given(case=model_files(base_files))
    def check(case):
        how, text = case
        note(how)
        with alarm():
            try:
                model, run = loads_model(text)
            except RotorkitError as err:
                assert str(err).strip(), "a named error must say what is wrong"
                event(f"refused: {type(err).__name__}")
                return
        event("read")
        assert isinstance(model, rk.Model)
        again, run_again = loads_model(dumps_model(model, run=run))  # what is read can be written and read back
        assert again.parameters == model.parameters and run_again == run

    check()


# -- command lines ----------------------------------------------------------------------------------------------
class ReachedWork(Exception):
    """The arguments were accepted: the command got as far as compiling (or deriving) a model."""


def _commands():
    """{command: (positional dests, {option: choices or None})}, read from rotorkit's own parser."""
    import argparse

    from rotorkit.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    out = {}
    for name, p in sub.choices.items():
        positional = [a.dest for a in p._actions if not a.option_strings]
        options = {a.option_strings[-1]: (None if a.nargs == 0 else (list(a.choices) if a.choices else ()))
                   for a in p._actions if a.option_strings and "--help" not in a.option_strings}
        out[name] = (positional, options)
    return out


COMMANDS = _commands()


def values(tmp):
    """Option values: numbers, ranges, orders, assignments, paths (all inside ``tmp``) and garbage."""
    paths = [str(tmp / "out"), str(tmp / "out" / "deeper"), str(tmp / "a_file"), "", "/dev/null", str(tmp / "x.csv")]
    return st.one_of(
        st.integers(-10**12, 10**12).map(str), st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.sampled_from(["0", "-1", "1", "3", "1e400", "nan", "1/0", "1/2", "HP - LP", "0:100:5", "200:3000:100000000",
                         "1:0:3", "a:b:c", "10,20,30", "rub_stiffness=1e6:2e6:2", "rub_stiffness=1e6",
                         "friction_coefficient=0.1", "x=1", "=", "x2", "x99", "../../escape", "3000 rpm",
                         "1 kg", "not a url", "tcp://", "DOP853", "Radau", "RK23", "nope", "\x01", "ﬁ"]),
        st.sampled_from(paths),
        st.text(max_size=8),
    )


@st.composite
def command_lines(draw, tmp, model_file):
    name = draw(st.sampled_from(sorted(COMMANDS)))
    positional, options = COMMANDS[name]
    argv = [name]
    for dest in positional:
        if dest == "action":
            argv.append(draw(st.sampled_from(["info", "nope"])))  # never 'clear': the session's cache stays
        else:
            argv.append(draw(st.sampled_from(["al31f", "rig", "jeffcott", str(model_file), str(tmp / "missing.toml"),
                                              str(tmp), "/dev/null", ""])))
    chosen = draw(st.lists(st.sampled_from(sorted(options)), max_size=4)) if options else []
    for option in chosen:
        kind = options[option]
        argv.append(option)
        if kind is None:  # a flag
            continue
        if kind and draw(st.booleans()):
            argv.append(str(draw(st.sampled_from(kind))))
        else:
            argv.append(draw(values(tmp)))
    if "--out" in options and "--out" not in chosen and name != "export":
        argv += ["--out", str(tmp / "out")]  # the default (./rotorkit-out) is inside tmp too: the cwd is tmp
    return argv


def _listing(folder):
    return sorted(p.name for p in folder.iterdir())


def test_command_lines_exit_0_or_2_with_a_message_and_write_only_inside_the_temporary_folder(
        tmp_path, monkeypatch, capsys):
    from rotorkit.cli import main

    tmp = tmp_path / "work"
    tmp.mkdir()
    (tmp / "a_file").write_text("not a folder")
    model_file = tmp / "jeffcott.toml"
    model_file.write_text(JEFFCOTT)
    monkeypatch.chdir(tmp)
    monkeypatch.setenv("HOME", str(tmp))

    def work(*args, **kwargs):
        raise ReachedWork

    monkeypatch.setattr(rk.Model, "compile", work)
    monkeypatch.setattr("rotorkit.codegen.linear_cache.equations_text", work)
    outside = {folder: _listing(folder) for folder in (ROOT, ROOT / "tests", ROOT / "examples", tmp_path)}
    seen = {"accepted": 0, "refused": 0}

    @settings(max_examples=150, **SETTINGS)
    @given(argv=command_lines(tmp, model_file))
    def check(argv):
        note(repr(argv))
        with alarm():
            try:
                code = main(argv)
            except ReachedWork:
                seen["accepted"] += 1
                event(f"{argv[0]}: accepted")
                return
        err = capsys.readouterr().err
        event(f"{argv[0]}: exit {code}")
        assert code in (0, 2), f"exit code {code}: {err}"
        if code == 2:
            seen["refused"] += 1
            assert err.strip() and ("error" in err or "usage" in err), "exit 2 without a message"
        assert (tmp / "a_file").read_text() == "not a folder"  # a file given as an output folder is never touched

    check()
    assert seen["accepted"] and seen["refused"]  # both branches were exercised
    for folder, before in outside.items():
        assert _listing(folder) == before, f"something was written in {folder}"
