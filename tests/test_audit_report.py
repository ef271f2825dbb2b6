"""``rotorkit audit`` on the compressor example: the self-contained HTML report, rendered in headless Chromium."""

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = Path("/usr/bin/chromium")
needs_chromium = pytest.mark.skipif(not CHROMIUM.exists(), reason="headless Chromium (Debian package 'chromium', "
                                    "/usr/bin/chromium) is not installed: the report is not rendered")


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("MPLBACKEND", "Agg")
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[name] = "1"  # small dense eigen-solutions: one thread each is faster on a shared machine
    return env


def _audit(*args):
    return subprocess.run([sys.executable, "-m", "rotorkit.cli", "audit", *args], capture_output=True, text=True,
                          env=_env(), cwd=ROOT, timeout=900)


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("audit")
    run = _audit("examples/compressor.toml", "--operating", "8000:10500 rpm", "--out", str(out),
                 "--power", "1.5 MW,1.5 MW,1.4 MW,1.3 MW", "--impeller-diameter", "480 mm,460 mm,440 mm,420 mm",
                 "--restrictive-width", "25 mm,25 mm,24 mm,22 mm", "--density-ratio", "1.2,1.2,1.15,1.15",
                 "--clearance", "6=0.4 mm", "--clearance", "16=0.35 mm")
    assert run.returncode == 0, run.stderr
    return out, run.stdout


@pytest.mark.slow
def test_audit_writes_a_self_contained_report(report):
    import rotorkit

    out, stdout = report
    assert "API 617 audit:" in stdout
    for name in ("report.html", "modes.csv", "stability.csv", "shear_moment.csv", "critical_map.csv",
                 "unbalances.csv", "clearances.csv"):
        assert (out / name).stat().st_size > 0
    text = (out / "report.html").read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and text.rstrip().endswith("</html>")
    # offline: no link or source outside the file (figures are data: URIs)
    assert not re.search(r"""(src|href)\s*=\s*["'](?!data:)""", text)
    assert "http://" not in text and "https://" not in text
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    assert len(images) >= 6  # rotor, deflection, shear/moment, map, a mode, stability
    for heading in ("Summary", "Inputs", "Model", "Static analysis", "Undamped critical speed map",
                    "Unbalance response", "Amplitudes at the probes and close clearances", "Level I stability"):
        assert f"<h2>{heading}</h2>" in text
    # the new checks: the unbalance multiple named, the placement rule, the probe limit, the clearances
    assert "2 x U_r (API 617 8th ed. 4.8.2.7: 2 x U_r)" in text
    assert "placement: one lobe" in text
    assert "A_vl = 25.4 um" in text and "clearance st. 6 (400 um)" in text and "clearance st. 16 (350 um)" in text
    assert "probe amplitude" in stdout and "close clearance at st. 16" in stdout
    assert f"rotorkit {rotorkit.__version__}" in text
    assert ("PASS" in text) or ("FAIL" in text)
    # the per-impeller Wachel inputs as the user wrote them, not a Python list
    assert "1.5 MW, 1.5 MW, 1.4 MW, 1.3 MW" in text and "['1.5 MW'" not in text


@pytest.mark.slow
def test_audit_csv_agrees_with_the_summary(report):
    out, stdout = report
    rows = (out / "stability.csv").read_text().splitlines()
    q = np.array([float(r.split(",")[0]) for r in rows[1:]])
    assert q[0] == 0.0 and np.all(np.diff(q) > 0)
    assert (out / "modes.csv").read_text().count("\n") >= 2   # a header and at least one mode in range
    rows = (out / "clearances.csv").read_text().splitlines()
    assert rows[0].startswith("mode,station,diametral_clearance_m")
    stations = {r.split(",")[1]: float(r.split(",")[2]) for r in rows[1:]}
    assert stations["6"] == pytest.approx(0.4e-3) and stations["16"] == pytest.approx(0.35e-3)


def _render(page, tmp_path):
    """Screenshot of ``page`` by headless Chromium: (PNG path, the console messages it logged)."""
    shot = tmp_path / (page.stem + ".png")
    run = subprocess.run([str(CHROMIUM), "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                          "--no-first-run", "--disable-background-networking", "--disable-component-update",
                          "--disable-sync", f"--user-data-dir={tmp_path / ('profile-' + page.stem)}",
                          f"--screenshot={shot}", "--window-size=1200,2400", "--enable-logging=stderr", "--v=0",
                          page.resolve().as_uri()], capture_output=True, text=True, timeout=180)
    console = [line for line in run.stderr.splitlines() if ":CONSOLE" in line]
    return shot, console


def _non_blank(png):
    from matplotlib.image import imread

    pixels = imread(str(png))[..., :3]
    dark = np.mean(np.min(pixels, axis=-1) < 0.9)
    return pixels.std() > 0.02 and dark > 0.01


@needs_chromium
def test_the_console_check_catches_a_script_error(tmp_path):
    page = tmp_path / "broken.html"
    page.write_text("<html><body><p>x</p><script>console.error('bad'); notAFunction();</script></body></html>")
    _, console = _render(page, tmp_path)
    assert any("bad" in line for line in console) and any("notAFunction" in line for line in console)


@pytest.mark.slow
@needs_chromium
def test_report_renders_in_headless_chromium(report, tmp_path):
    out, _ = report
    shot, console = _render(out / "report.html", tmp_path)
    assert shot.stat().st_size > 0
    assert console == []
    assert _non_blank(shot)


@pytest.mark.parametrize("args, match", [
    (["--operating", "9000 rpm"], "--operating"),
    (["--operating", "10500:8000 rpm"], "0 < MIN <= MAX"),
    (["--operating", "8000 rpm:1000 Hz"], "different units"),
    (["--operating", "8000:10500 rpm"], "--qa"),
    (["--operating", "8000:10500 rpm", "--power", "1 MW"], "--impeller-diameter"),
    (["--operating", "8000:10500 rpm", "--qa", "1e6", "--clearance", "6"], "STATION=CLEARANCE"),
    (["--operating", "8000:10500 rpm", "--qa", "1e6", "--clearance", "6=-0.4 mm"], "close_clearances['6']"),
    (["--operating", "8000:10500 rpm", "--qa", "1e6", "--clearance", "60=0.4 mm"], "station '60' unknown"),
    (["--operating", "8000:10500 rpm", "--qa", "1e6", "--probes", "3,99"], "['99'] unknown"),
])
def test_bad_audit_arguments_are_named(args, match):
    import contextlib
    import io

    from rotorkit.cli import main

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["audit", str(ROOT / "examples" / "compressor.toml"), *args])
    assert code == 2
    assert match in err.getvalue()


@pytest.fixture(scope="module")
def compressor_audit(report):  # after the command: the model's linear matrices are in the session's cache
    from rotorkit import load_model
    from rotorkit.analysis.api617 import api617_audit

    model = load_model(ROOT / "examples" / "compressor.toml")
    return model, api617_audit(model, ("8000 rpm", "10500 rpm"), q_a="1.5 MN/m",
                               close_clearances={6: "0.4 mm", "16": 0.35e-3})


@pytest.mark.slow
def test_compressor_audit_inputs_against_the_model_file(compressor_audit):
    import math

    model, audit = compressor_audit
    # journal loads: the bearings carry the rotor's whole weight (beams and impellers), in kg
    mass = sum(e.mass_value() for e in model.elements if type(e).__name__ == "BeamSegment")
    mass += sum(e.mass for e in model.elements if type(e).__name__ == "Disk")
    assert sum(audit.journal_loads.values()) == pytest.approx(mass, rel=1e-9)
    assert audit.critical_map.supports == ("3", "18")  # in station order (not sorted as text: "18" < "3")
    # the bearing curves drawn on the map are the file's kxx, kyy tables (piecewise linear in rad/s)
    table = [0, 400, 800, 1200, 1600]
    speeds, kxx = audit.critical_map.bearing_curves["linearbearing3 kxx"]
    assert kxx == pytest.approx(np.interp(speeds, table, [300e6, 340e6, 390e6, 450e6, 520e6]), rel=1e-9)
    speeds, kyy = audit.critical_map.bearing_curves["linearbearing18 kyy"]
    assert kyy == pytest.approx(np.interp(speeds, table, [200e6, 230e6, 270e6, 320e6, 380e6]), rel=1e-9)
    # the first mode (one lobe, between the bearings) gets one unbalance of 2 x 6350 (W1 + W2) / N g mm
    first = audit.modes[0]
    assert len(first.unbalances) == 1 and first.placement.kinds == ("mid-span",)
    n_rpm = 10500.0
    assert first.unbalances[0].magnitude == pytest.approx(2 * 6350 * mass / n_rpm * 1e-6, rel=1e-9)
    # ... near mid-span between the bearings (stations 3 and 18 of 20): at one of the middle stations
    assert first.unbalances[0].station in {"9", "10", "11", "12"}
    # A_vl at 10500 rpm: 25.4 sqrt(12000 / 10500) = 27.2 um, capped at 25.4 um
    amp = first.amplitude
    assert amp.vibration_limit == pytest.approx(25.4e-6) and amp.probes == ("3", "18")
    # A_max: the largest probe amplitude between 8000 and 10500 rpm, read off the response independently
    band = (first.speeds >= 8000 * math.pi / 30 * (1 - 1e-9)) & (first.speeds <= 10500 * math.pi / 30 * (1 + 1e-9))
    assert amp.max_amplitude == pytest.approx(max(first.amplitudes[p][band].max() for p in ("3", "18")))
    assert amp.probes_passed == (amp.max_amplitude < 25.4e-6)
    # S_cc = A_vl / A_max within [0.5, 6]; the scaled clearance amplitude against 75 % of the clearance
    assert amp.scale_factor == pytest.approx(min(6.0, max(0.5, 25.4e-6 / amp.max_amplitude)))
    trip = audit.trip_speed
    for check, c in zip(amp.clearances, (0.4e-3, 0.35e-3)):
        upto = first.speeds <= trip * (1 + 1e-12)
        assert check.amplitude == pytest.approx(amp.scale_factor * first.amplitudes[check.station][upto].max())
        assert check.limit == pytest.approx(0.75 * c) and check.passed == (check.amplitude < 0.75 * c)
    # the pk-pk amplitudes are twice the orbit's major semi-axis (the response drawn for the AF)
    assert first.amplitudes[first.probe] == pytest.approx(2 * first.response)
    # its peak is where the 1x line meets the mode, below the operating range here
    assert first.amplification.critical_speed < 8000 * math.pi / 30
    # the static loads balance: shear and moment close at the free right end
    assert audit.shear_moment.closure[0] < 1e-6 * mass * 9.81
    # Level I: at the mid-span station by default, Q_A as given
    assert audit.stability.q_a == pytest.approx(1.5e6)
    assert audit.stability.stations == ("11",)
