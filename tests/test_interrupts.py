"""A Ctrl-C that other code swallowed is raised again at the next checkpoint (rotorkit/interrupts.py).

Seen in CI: a SIGINT sent just as ``rotorkit run`` went from the derivation to the integration was lost, and
the run went on to the end (exit 0). Here the swallowing is made deterministic."""

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from rotorkit import interrupts, simulate
from rotorkit.errors import SimulationError

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(not hasattr(signal, "SIGINT") or sys.platform == "win32", reason="POSIX signals")


def run_script(code, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=600)


SWALLOW = """
    import os, signal, time

    def swallow_a_ctrl_c():
        try:  # "other code": the signal arrives here, and this catches it
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)
        except KeyboardInterrupt:
            pass
"""


@pytest.mark.parametrize("engine", ["scipy", "compiled"])
def test_simulate_stops_at_its_next_step_once_a_ctrl_c_was_received(monkeypatch, engine):
    from sweep_models import build_jeffcott

    backend = "python" if engine == "scipy" else "c"
    if engine == "compiled":
        from rotorkit.codegen import cbuild

        if cbuild.compiler() is None:
            pytest.skip("no C compiler: the compiled engine runs the c back end here")
    system = build_jeffcott(rub_stiffness=0.0).compile(backend=backend)
    monkeypatch.setattr(interrupts, "received", True)
    with pytest.raises(SimulationError, match=r"interrupted \(Ctrl-C\) at t = ") as err:
        simulate(system, (0.0, 50.0), engine=engine)
    assert err.value.partial.t.size == 0 or err.value.partial.t[-1] < 50.0
    monkeypatch.setattr(interrupts, "received", False)
    assert simulate(system, (0.0, 0.01), engine=engine).stats["success"]


def test_the_handler_records_the_signal_and_check_raises_it_again(tmp_path):
    done = run_script(SWALLOW + """
    import signal
    from rotorkit import interrupts

    interrupts.check()  # nothing received yet: nothing raised
    with interrupts.watching():
        assert signal.getsignal(signal.SIGINT) is not signal.default_int_handler
        swallow_a_ctrl_c()
        print("received", interrupts.received)
        try:
            interrupts.check()
        except KeyboardInterrupt:
            print("raised again")
    # a Python session that called rotorkit.cli.main keeps its own Ctrl-C
    print("after", signal.getsignal(signal.SIGINT) is signal.default_int_handler, interrupts.received)
    interrupts.check()
    """, tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:3] == ["received True", "raised again", "after True False"]


def test_watching_leaves_an_ignored_sigint_ignored(tmp_path):
    """A run started in the background (SIGINT ignored) must stay immune to the terminal's Ctrl-C."""
    done = run_script("""
    import os, signal, time
    from rotorkit import interrupts

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    with interrupts.watching():
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.2)
        print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN, interrupts.received)
    print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN)
    """, tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["True", "False", "True"]


def test_a_run_whose_ctrl_c_was_swallowed_before_the_integration_stops_and_writes_nothing(tmp_path):
    done = run_script(SWALLOW + f"""
    import sys
    sys.path.insert(0, {str(ROOT / "tests")!r})
    from sweep_models import build_jeffcott
    import rotorkit.cli.run as run_command
    from rotorkit.cli import main

    build_jeffcott(rub_stiffness=0.0).save("jeffcott.toml")
    load_preset = run_command.load_preset

    def loading_and_swallowing(args):  # the model is read; a Ctrl-C comes and is swallowed
        loaded = load_preset(args)
        swallow_a_ctrl_c()
        return loaded

    run_command.load_preset = loading_and_swallowing
    sys.exit(main(["run", "jeffcott.toml", "--backend", "python", "--engine", "scipy", "--t-end", "200",
                   "--no-figures", "--out", "out"]))
    """, tmp_path)
    assert done.returncode == 2, done.stderr
    assert "interrupted (Ctrl-C) at t = 0 s" in done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "out").exists()
