"""Check a paper's claims automatically from simulated spectra.

A *claim* is a function ``claim(study) -> ClaimResult`` that reads spectra
from a :class:`Study` (which simulates a preset under overrides, once per
override set) and says whether the model reproduces the statement, with
the numbers it measured.

What "a spectrum shows a frequency" means is fixed here, once, before
looking at any result, and never tuned per claim: the largest amplitude
within +-2 % of the frequency is at least :data:`PRESENT_FRACTION` of the
spectrum's largest peak (in :data:`BAND`), i.e. visible on a linear-amplitude
waterfall like the paper's, and at least :data:`MIN_SNR` times the median
amplitude (the noise floor).
"""

from dataclasses import dataclass, field

import numpy as np

from .errors import SimulationError

__all__ = ["ClaimResult", "Study", "PRESENT_FRACTION", "MIN_SNR", "BAND", "REL_BAND", "format_table", "initial_state"]

PRESENT_FRACTION = 0.01
MIN_SNR = 10.0
BAND = (100.0, 6000.0)  # rad/s: where the spectra are read
REL_BAND = 0.02

VERDICTS = ("reproduced", "partly", "not reproduced", "could not run")


@dataclass(frozen=True)
class ClaimResult:
    """The verdict on one claim, with what was measured."""

    claim: str
    verdict: str
    measured: str
    note: str = ""


@dataclass
class _Run:
    spectra: dict = field(default_factory=dict)
    status: str = "ok"
    detail: str = ""
    measurement: object = None


def initial_state(system, start=None):
    """The initial state of a run: None (at rest on the undeflected axis) or, for ``start="equilibrium"``,
    at rest on the static equilibrium (gravity sag) of ``system`` at t = 0."""
    if start is None:
        return None
    if start != "equilibrium":
        from .errors import ParameterError

        raise ParameterError(f"start={start!r}: expected None or 'equilibrium'")
    from .linear.linearize import static_equilibrium

    q = static_equilibrium(system)
    return np.concatenate([q, np.zeros_like(q)])


class Study:
    """Simulates a preset under overrides (cached per override set) and reads spectra.

    Parameters
    ----------
    preset : str
        Preset name (``rotorkit.preset``).
    signals : dict
        Role -> signal name, e.g. ``{"bending": "x2", "torsion": "alpha2-alpha5"}``.
    t_end : float
        Run length (s).
    window : (float, float)
        Spectral window (s).
    highpass_hz : float
        Zero-phase high-pass cut-off applied before the spectrum (Hz).
    runaway : float
        A run whose displacement exceeds this (m) is stopped and reported as a
        run-away, not read as a spectrum.
    time_limit : float
        Wall-time limit of one run (s).
    sensors : sequence, optional
        Virtual sensors (:mod:`rotorkit.sensors`) recorded in every run: a
        role may then name a sensor signal (read at the sensor's own rate),
        and each run keeps its :class:`~rotorkit.sensors.Measurement` as
        ``run.measurement`` for claims that read more than one spectrum.
    band : (float, float)
        Where spectra are read (rad/s), see :meth:`level`.
    start : str or None
        ``"equilibrium"``: start each run at rest on the static equilibrium
        (the gravity sag) instead of the undeflected axis.
    sample_rate : float
        Output rate of the states (Hz).
    """

    def __init__(self, preset, signals, *, t_end=6.0, window=(2.2, 3.8), highpass_hz=5.0, runaway=2e-3,
                 time_limit=120.0, progress=None, sensors=None, band=BAND, start=None, sample_rate=10_000.0):
        from .presets import preset_module

        self.module = preset_module(preset)
        self.signals = dict(signals)
        self.t_end, self.window, self.highpass_hz, self.runaway = t_end, window, highpass_hz, runaway
        self.time_limit = time_limit
        self.progress = progress
        self.sensors = tuple(sensors) if sensors else ()
        self.band, self.start, self.sample_rate = tuple(band), start, sample_rate
        self._runs = {}
        self.runs_done = 0

    def run(self, **overrides):
        """Spectra of every signal for ``overrides`` (a cached :class:`_Run`)."""
        from .simulate import simulate

        key = tuple(sorted(overrides.items()))
        if key in self._runs:
            return self._runs[key]
        run = _Run()
        system = self.module.build(**overrides).compile()
        options = dict(bound=self.runaway, time_limit=self.time_limit, y0=initial_state(system, self.start))
        try:
            if self.sensors:
                from .sensors import measure

                run.measurement = measure(system, (0.0, self.t_end), self.sensors, sample_rate=self.sample_rate,
                                          **options)
                result = run.measurement.result
            else:
                result = simulate(system, (0.0, self.t_end), sample_rate=self.sample_rate, **options)
        except SimulationError as err:
            first = str(err).splitlines()[0]
            run.status = "runaway" if "run-away" in first else "failed"
            run.detail = first.split(": ", 1)[-1]
        else:
            for role, name in self.signals.items():
                if run.measurement is not None and name in run.measurement:
                    run.spectra[role] = run.measurement[name].spectrum(self.window, self.highpass_hz)
                else:
                    run.spectra[role] = result.spectrum(name, self.window, self.highpass_hz)
        self._runs[key] = run
        self.runs_done += 1
        if self.progress is not None:
            self.progress(self.runs_done, overrides, run.status)
        return run

    # -- reading spectra --------------------------------------------------
    @staticmethod
    def level(spectrum, frequency, band=BAND):
        """(amplitude near ``frequency``, its share of the largest peak in ``band`` (rad/s), its ratio to the
        noise floor)."""
        f, a = spectrum.frequency, spectrum.amplitude
        band = (f >= band[0]) & (f <= band[1])
        near = band & (np.abs(f - frequency) <= REL_BAND * frequency)
        amp = float(a[near].max()) if near.any() else 0.0
        top = float(a[band].max())
        floor = float(np.median(a[band]))
        return amp, amp / top if top > 0 else 0.0, amp / floor if floor > 0 else np.inf

    @staticmethod
    def shows(spectrum, frequency, band=BAND):
        """Whether ``spectrum`` shows a component at ``frequency`` (rad/s), by the fixed rule above."""
        _, share, snr = Study.level(spectrum, frequency, band)
        return share >= PRESENT_FRACTION and snr >= MIN_SNR

    @staticmethod
    def describe(spectrum, frequency, band=BAND):
        """Short text: share of the largest peak at ``frequency``."""
        _, share, _ = Study.level(spectrum, frequency, band)
        return f"{100 * share:.2g} %"


def format_table(results):
    """The claim table as text."""
    lines = [f"{'verdict':<15s} claim", "-" * 100]
    for r in results:
        lines.append(f"{r.verdict:<15s} {r.claim}")
        lines.append(f"{'':<15s}   measured: {r.measured}")
        if r.note:
            lines.append(f"{'':<15s}   note: {r.note}")
    counts = {v: sum(r.verdict == v for r in results) for v in VERDICTS}
    lines.append("-" * 100)
    lines.append(", ".join(f"{n} {v}" for v, n in counts.items() if n))
    return "\n".join(lines)
