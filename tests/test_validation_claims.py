"""The claim checker: the fixed 'shows a frequency' rule, and the full claim table."""

import numpy as np
import pytest

from rotorkit.analysis.signals import amplitude_spectrum
from rotorkit.validation import MIN_SNR, PRESENT_FRACTION, VERDICTS, ClaimResult, Study, format_table


def spectrum_of(*components, noise=1e-6, seed=0):
    t = np.arange(0.0, 4.0, 1e-4)
    rng = np.random.default_rng(seed)
    x = sum(a * np.sin(w * t) for w, a in components) + noise * rng.normal(size=t.size)
    return amplitude_spectrum(t, x, window=(2.2, 3.8))


def test_shows_follows_the_fixed_rule():
    spec = spectrum_of((1500.0, 1.0), (750.0, 3 * PRESENT_FRACTION), (2700.0, 0.3 * PRESENT_FRACTION))
    assert Study.shows(spec, 1500.0)
    assert Study.shows(spec, 750.0)  # 3 % of the largest peak
    assert not Study.shows(spec, 2700.0)  # 0.3 %: below PRESENT_FRACTION
    assert not Study.shows(spec, 1200.0)  # nothing there
    amp, share, snr = Study.level(spec, 750.0)
    assert share == pytest.approx(3 * PRESENT_FRACTION, rel=0.02) and snr > MIN_SNR


def test_noise_floor_rule():
    """A component 2 % of the top but buried in noise does not count."""
    spec = spectrum_of((1500.0, 1.0), (900.0, 0.02), noise=0.5)
    _, share, snr = Study.level(spec, 900.0)
    assert snr < MIN_SNR and not Study.shows(spec, 900.0)


def test_table_format():
    text = format_table([ClaimResult("a claim", "reproduced", "x 1 %"), ClaimResult("b", "partly", "y", "a note")])
    assert "reproduced      a claim" in text and "note: a note" in text and "1 reproduced, 1 partly" in text


@pytest.mark.slow
def test_validate_command_prints_every_claim(tmp_path, capsys):
    """The full check (about 30 s): every claim gets a verdict and measured numbers."""
    from rotorkit.cli import main
    from rotorkit.presets import preset_module

    assert main(["validate", "al31f", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    claims = preset_module("al31f").CLAIMS
    rows = [line for line in out.splitlines() if line.split("  ")[0].strip() in VERDICTS]
    assert len(rows) == len(claims)
    assert out.count("measured:") == len(claims)
    assert (tmp_path / "claims.txt").read_text().strip() == out.split("\nwrote")[0].strip()
