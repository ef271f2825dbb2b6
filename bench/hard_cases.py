"""Hard cases: the AL-31F preset and a Jeffcott rotor with a rub stator at the edges
of their envelope, each run checked for solver success, finite states, run-away and
the energy balance (:mod:`rotorkit.analysis.energy`).

Run the full matrix (full spans, 0-6 s and a 30 s run; several minutes)::

    python bench/hard_cases.py                      # prints a Markdown table
    python bench/hard_cases.py --only al31f:kr_1e9 jeffcott:mu_0.3
    python bench/hard_cases.py --ci                 # the short windows tests/test_hard_cases.py runs
    python bench/hard_cases.py --markdown out.md    # also write the table to a file

The same matrix, over short windows, is ``tests/test_hard_cases.py`` (which imports
this file). The measured table and what it means are in ``docs/envelope.md``.

Checks and verdicts
-------------------
- ``ok``: the solver succeeded, all states are finite, the rub disk stayed within
  ``RUNAWAY_RADIUS`` (1 mm, 7.5 clearances) and the energy balance closes:
  ``relative_residual <= BALANCE_FACTOR * rtol * max(1, flow / scale)`` with the
  quadrature error of the balance at least 10 times below that (else the check is
  inconclusive: raise the sample rate). ``relative_residual`` is the largest energy
  error along the run against the energy of the motion (the mechanical energy
  scale, which does not grow with run length); the allowance grows with the energy
  that passed through the drive, damping and loads (``flow``), since the solver's
  error accumulates as energy is carried in and out.
- ``run-away``: the rub disk went past ``RUNAWAY_RADIUS`` (dry-friction backward
  whirl at high friction, the documented physics of the model). Expected for the
  cases marked so; the states must still be finite wherever the solver returned
  them and the energy balance must still close on them, up to the time the disk
  passes ``BALANCE_RADIUS`` (10 mm; the table says "up to t = ..."). At full span
  such a run grows without bound until the solver gives up (``SimulationError``):
  the verdict names the time and amplitude of the run-away and the solver's message.
- ``FAIL``: anything else (unexpected run-away, solver failure, non-finite state,
  balance not closing): a finding to report.

Tolerances: ``rtol`` with ``atol = 1e-6 * rtol`` (displacements are ~1e-4 m, so the
default ``atol = 1e-9`` would dominate the error at high speed; see docs/envelope.md).
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import rotorkit as rk
from rotorkit.analysis.energy import energy_balance
from rotorkit.convergence import check_convergence

#: rub-disk radius (m) beyond which a run is a run-away (7.5 AL-31F clearances)
RUNAWAY_RADIUS = 1e-3
#: relative energy residual allowed, per unit of rtol
BALANCE_FACTOR = 10.0
#: the quadrature error must stay this many times below the allowed residual
QUADRATURE_MARGIN = 10.0
#: default tolerances and sampling of the checked runs
RTOL = 1e-6
FULL_SAMPLE_RATE = 100_000.0
CI_SAMPLE_RATE = 200_000.0
#: sample rate of a prefix run that only brings the state to the start of a window
PREFIX_SAMPLE_RATE = 1_000.0
#: in a run-away the energy balance is checked until the rub disk passes this radius (m): beyond,
#: the contact laws are far outside their validity (the Hertzian bearing stiffens without bound
#: and makes the problem stiff), the energy grows by orders of magnitude and overflows at last
BALANCE_RADIUS = 1e-2
#: wall-time limit per run (s) passed to simulate
TIME_LIMIT = 120.0

#: the Jeffcott rotor with a rub stator: disk 2 of the AL-31F preset on its own
JEFFCOTT_DEFAULTS = {
    "lp_speed": 1500.0,  # rad/s
    "disk_mass": 10.0,  # kg
    "disk_radius": 0.075,  # m
    "eccentricity": 46.35e-6,  # m
    "support_stiffness": 1e6,  # N/m: wn = 316 rad/s
    "support_damping": 2000.0,  # N s/m: zeta = 0.32 (a squeeze-film-damped support)
    "rub_stiffness": 8e6,  # N/m
    "friction_coefficient": 0.1,
    "rub_clearance": 1.34e-4,  # m: gravity sag 98 um + unbalance whirl 48 um reach it
    "gravity": 9.81,  # m/s^2
}


def jeffcott_rub(**overrides):
    """A Jeffcott rotor (one disk at station 2 on an isotropic support) with a rub stator and gravity.

    Overrides: the keys of :data:`JEFFCOTT_DEFAULTS` (SI floats).
    """
    unknown = set(overrides) - set(JEFFCOTT_DEFAULTS)
    if unknown:
        raise ValueError(f"jeffcott_rub: unknown overrides {sorted(unknown)}; known: {sorted(JEFFCOTT_DEFAULTS)}")
    v = {**JEFFCOTT_DEFAULTS, **overrides}
    return rk.Model([
        rk.Rotor(name="LP", stations=(2,), speed=v["lp_speed"]),
        rk.Disk(station=2, mass=v["disk_mass"], radius=v["disk_radius"], eccentricity=v["eccentricity"]),
        rk.ElasticSupport(station=2, stiffness=v["support_stiffness"], damping=v["support_damping"]),
        rk.RubStator(station=2, clearance=v["rub_clearance"], contact_stiffness=v["rub_stiffness"],
                     friction_coefficient=v["friction_coefficient"]),
        rk.Maneuver.steady(gravity=v["gravity"]),
    ], name="jeffcott_rub")


BUILDERS = {"al31f": lambda **o: rk.preset("al31f", **o), "jeffcott": jeffcott_rub}


@dataclass(frozen=True)
class Case:
    """One hard case: a model, overrides, the full span and a short window for CI."""

    model: str
    name: str
    overrides: dict = field(default_factory=dict)
    span: tuple = (0.0, 6.0)
    ci_window: tuple = (0.0, 0.2)
    expect: str = "ok"  # or "run-away", or "unconverged" (succeeds, balance closes, trajectory not converged)
    converge: bool = False  # also run rotorkit.convergence.check_convergence (costs the reference run)
    method: str = "DOP853"
    why: str = ""
    full: bool = True  # part of the full-span matrix (False: a CI-only window)
    sample_rate: float = FULL_SAMPLE_RATE  # Hz, full span
    ci_sample_rate: float = CI_SAMPLE_RATE  # Hz, CI window

    @property
    def key(self):
        return f"{self.model}:{self.name}"


def _matrix(model):
    """The hard cases of one model (``"al31f"`` or ``"jeffcott"``)."""
    al31f = model == "al31f"
    cases = [
        Case(model, "default", {}, why="reference point; the rest start puts the disk at r2 = 0 exactly"),
        Case(model, "kr_0", {"rub_stiffness": 0.0}, why="rub element present, no stiffness"),
        Case(model, "kr_5e5", {"rub_stiffness": 5e5}, why="soft contact"),
        Case(model, "kr_2e7", {"rub_stiffness": 2e7}, why="stiff contact"),
        Case(model, "kr_1e8", {"rub_stiffness": 1e8}, why="very stiff contact"),
        Case(model, "kr_1e9", {"rub_stiffness": 1e9}, sample_rate=400_000.0,
             why="very stiff contact, contact frequency ~1e4 rad/s; short grazes need 400 kHz samples "
                 "for the balance's quadrature"),
        Case(model, "kr_1e9_radau", {"rub_stiffness": 1e9}, span=(0.0, 1.0), ci_window=(0.0, 0.05),
             method="Radau", sample_rate=400_000.0, ci_sample_rate=400_000.0,
             why="the same with scipy's implicit Radau (analytic Jacobian), for comparison"),
        Case(model, "mu_0", {"friction_coefficient": 0.0}, why="frictionless: the rub is conservative"),
    ]
    if al31f:
        cases[0] = Case(model, "default", {}, converge=True,
                        why="reference point; the rest start puts the disk at r2 = 0 exactly")
        cases += [
            Case(model, f"kr_1e{k}", {"rub_stiffness": 10.0 ** k}, span=(0.0, 1.0), expect="unconverged",
                 converge=True, sample_rate=400_000.0, ci_sample_rate=400_000.0,
                 why=f"extremely stiff contact (1e{k} N/m): every step succeeds, but the trajectory is not "
                     "converged: against a run at 100 times tighter tolerances it differs by about its own "
                     "amplitude within 0.2 s (the convergence check says so)")
            for k in (10, 11, 12)
        ]
    if al31f:
        cases += [
            Case(model, "mu_0.3", {"friction_coefficient": 0.3}, ci_window=(2.0, 2.15), expect="run-away",
                 why="high friction: dry-friction whirl within 0.1 s after the roll starts (model notes)"),
            Case(model, "mu_0.5", {"friction_coefficient": 0.5}, ci_window=(0.0, 0.3), expect="run-away",
                 why="very high friction: dry-friction backward whirl already in the start-up"),
        ]
    else:
        cases += [
            Case(model, "mu_0.3", {"friction_coefficient": 0.3},
                 why="high friction; a light graze (r - delta << r) keeps the friction force small"),
            Case(model, "mu_0.5", {"friction_coefficient": 0.5}, why="very high friction, light graze"),
            Case(model, "clearance_0_mu_0.3", {"rub_clearance": 0.0, "friction_coefficient": 0.3},
                 ci_window=(0.0, 1.0), ci_sample_rate=20_000.0, expect="run-away",
                 why="permanent contact above the closed-form threshold mu k_r > c sqrt((k + k_r)/m) "
                     "(mu_crit = 0.237): backward whirl grows at Re(s) = 26.1 1/s, without bound"),
            Case(model, "clearance_0_mu_0.5", {"rub_clearance": 0.0, "friction_coefficient": 0.5},
                 span=(0.0, 8.0), ci_window=(0.0, 8.0), sample_rate=50_000.0, ci_sample_rate=50_000.0,
                 expect="run-away",
                 why="the same at Re(s) = 107 1/s: the states overflow near 7 s, the solver must stop "
                     "with an explained SimulationError"),
        ]
    cases += [
        Case(model, "speed_500", {"lp_speed": 500.0}, why="low speed"),
        Case(model, "speed_3000", {"lp_speed": 3000.0}, why="twice the nominal speed"),
        Case(model, "speed_5000", {"lp_speed": 5000.0}, sample_rate=400_000.0, ci_sample_rate=400_000.0,
             why="3.3 times the nominal speed; the ball onsets of the bearing need 400 kHz samples for the "
                 "balance's quadrature"),
        Case(model, "clearance_0", {"rub_clearance": 0.0},
             why="permanent contact, started at r2 = 0 = clearance (contact_ratio(0, 0))"),
        Case(model, "clearance_1m", {"rub_clearance": 1.0}, why="never in contact"),
    ]
    if al31f:
        cases += [
            Case(model, "eccentricity_0", {"eccentricity_lp": 0.0, "eccentricity_hp": 0.0},
                 why="no unbalance: gravity and manoeuvre only"),
            Case(model, "bearing_clearance_0", {"bearing_clearance": 0.0},
                 why="intermediate bearing with zero gap"),
            Case(model, "roll_window", {}, ci_window=(1.9, 2.1), full=False,
                 why="across the roll's start (a time event) at the nominal point (CI only: the "
                     "full-span default run crosses it)"),
            Case(model, "long_30s", {}, span=(0.0, 30.0), ci_window=(29.9, 30.0),
                 why="a 30 s run: no drift, no step-size collapse (CI: the last 0.1 s checked after a "
                     "29.9 s prefix run)"),
        ]
    else:
        cases += [
            Case(model, "eccentricity_0", {"eccentricity": 0.0}, why="no unbalance: gravity only"),
            Case(model, "long_30s", {}, span=(0.0, 30.0), ci_window=(0.0, 30.0), ci_sample_rate=50_000.0,
                 why="a 30 s run: no drift, no step-size collapse"),
        ]
    return cases


CASES = _matrix("al31f") + _matrix("jeffcott")


def case(key):
    """The case named ``model:name``."""
    for c in CASES:
        if c.key == key:
            return c
    raise KeyError(f"no hard case {key!r}; cases: {', '.join(c.key for c in CASES)}")


_MODELS = {}


def build(c):
    """(model, system) of a case (cached: all cases of a model share one structure)."""
    key = (c.model, tuple(sorted(c.overrides.items())))
    if key not in _MODELS:
        model = BUILDERS[c.model](**c.overrides)
        _MODELS[key] = (model, model.compile())
    return _MODELS[key]


@dataclass
class Outcome:
    """What one checked run did."""

    case: Case
    window: tuple
    rtol: float
    sample_rate: float
    engine: str = ""
    method: str = ""
    success: bool = False
    message: str = ""
    t_reached: float = math.nan
    wall: float = math.nan
    nfev: int = 0
    finite: bool = True
    max_r2: float = math.nan
    max_x2: float = math.nan
    runaway_time: float | None = None
    relative_residual: float = math.nan
    relative_quadrature: float = math.nan
    balance_error: str = ""
    samples: int = 0
    balance_until: float | None = None  # the balance covers the samples up to here (run-away overflow)
    convergence: object = None  # rotorkit.convergence.Convergence when the case asks for the check
    flow_ratio: float = 1.0  # energy that passed through all power channels / the mechanical energy scale

    @property
    def tolerance(self):
        """Allowed relative residual: BALANCE_FACTOR rtol per mechanical energy scale of energy passed through."""
        return BALANCE_FACTOR * self.rtol * max(1.0, self.flow_ratio)

    @property
    def runaway(self):
        return self.runaway_time is not None

    @property
    def balance_ok(self):
        return (np.isfinite(self.relative_residual) and self.relative_residual <= self.tolerance
                and self.relative_quadrature * QUADRATURE_MARGIN <= self.tolerance)

    @property
    def verdict(self):
        """``ok``, ``run-away (expected) ...`` or ``FAIL: ...`` with the reason."""
        problems = []
        if not self.finite:
            problems.append("non-finite states")
        if self.case.expect == "unconverged":  # a documented limit: the balance is information, not a check
            pass
        elif self.balance_error:
            problems.append(f"energy balance not computed: {self.balance_error}")
        elif not np.isfinite(self.relative_residual) or self.relative_residual > self.tolerance:
            problems.append(f"energy residual {self.relative_residual:.1e} > {self.tolerance:.1e} allowed")
        elif self.relative_quadrature * QUADRATURE_MARGIN > self.tolerance:
            problems.append(f"balance inconclusive: quadrature error {self.relative_quadrature:.1e} "
                            "(raise the sample rate)")
        if self.runaway:
            what = (f"run-away: r2 > {RUNAWAY_RADIUS * 1e3:g} mm at t = {self.runaway_time:.3f} s, "
                    f"max {self.max_r2:.2g} m")
            if not self.success:
                what += f"; solver stopped at t = {self.t_reached:.3f} s: {_short(self.message)}"
            if self.case.expect != "run-away":
                problems.append("unexpected " + what)
            elif problems:
                return "FAIL: " + "; ".join(problems) + " [" + what + "]"
            else:
                return "expected " + what
        elif self.case.expect == "run-away" and self.success:
            problems.append("expected a run-away, none happened")
        if not self.success and not self.runaway:
            problems.append(f"solver failed at t = {self.t_reached:.4g} s: {_short(self.message)}")
        if self.case.converge and self.success:
            conv = self.convergence
            if self.case.expect == "unconverged" and conv.converged:
                problems.append(f"expected the convergence check to fail: {conv.message}")
            elif self.case.expect != "unconverged" and not conv.converged:
                problems.append(f"unexpected: {conv.message}")
            elif not problems:
                return ("expected: " if not conv.converged else "ok; ") + conv.message
        return "FAIL: " + "; ".join(problems) if problems else "ok"

    @property
    def passed(self):
        return not self.verdict.startswith("FAIL")


def _short(message):
    """A solver message without the repeated 'model: integration failed at t = ... (segment ...):'."""
    text = re.sub(r"^.*integration failed at t = \S+ s \(segment [^)]*\): ", "", message)
    return re.sub(r" at t=[0-9.e+-]+\.?$", "", text)


def run(c, window=None, *, rtol=RTOL, sample_rate=None, time_limit=TIME_LIMIT, engine="auto", method=None,
        contact_events=False):
    """Run case ``c`` over ``window`` (default: its full span) and check it.

    ``contact_events=True`` restarts the integration at every contact onset
    and loss (``simulate(..., contact_events=True)``).

    A window that starts after 0 is reached by a prefix run from rest (sampled at
    ``PREFIX_SAMPLE_RATE``, checked for success and run-away only); the checked run
    continues from its final state. Starting windows at a time event (the roll at
    2 s) makes this the same integration as one run, which restarts there anyway.
    """
    window = tuple(window or c.span)
    method = method or c.method
    if sample_rate is None:
        sample_rate = c.sample_rate if window == tuple(c.span) else c.ci_sample_rate
    model, system = build(c)
    out = Outcome(case=c, window=window, rtol=rtol, sample_rate=sample_rate, method=method)
    options = dict(method=method, rtol=rtol, atol=1e-6 * rtol, engine=engine, time_limit=time_limit,
                   check_convergence=False)  # checked below where the case asks for it
    if contact_events:
        options["contact_events"] = True
    y0, wall, nfev = None, 0.0, 0
    result = None
    if window[0] > 0.0:
        try:
            pre = rk.simulate(system, (0.0, window[0]), sample_rate=PREFIX_SAMPLE_RATE, bound=None, **options)
        except rk.SimulationError as err:
            pre, out.message, out.t_reached = err.partial, str(err).splitlines()[0], err.time
        wall, nfev = pre.stats["wall_time"], pre.stats["nfev"]
        _inspect(out, pre)
        if out.message:  # the prefix failed: report it as the run
            out.engine, out.wall, out.nfev, out.samples = pre.stats["engine"], wall, nfev, pre.t.size
            out.balance_error = "prefix run failed"
            return out
        y0 = pre.y[:, -1].copy()
    try:
        result = rk.simulate(system, window, y0=y0, sample_rate=sample_rate, bound=None, **options)
        out.success, out.message, out.t_reached = True, "success", window[1]
    except rk.SimulationError as err:
        result, out.message, out.t_reached = err.partial, str(err).splitlines()[0], err.time
    if c.converge and out.success:
        out.convergence = check_convergence(system, result, y0=y0, engine=engine, bound=None,
                                            time_limit=time_limit)
    out.engine = result.stats["engine"]
    out.wall = wall + result.stats["wall_time"]
    out.nfev = nfev + result.stats["nfev"]
    out.samples = result.t.size
    _inspect(out, result)
    if result.t.size >= 2 and out.finite:
        # a run-away: check the balance while the amplitude means something (BALANCE_RADIUS)
        beyond = np.flatnonzero(np.hypot(result["x2"], result["y2"]) > BALANCE_RADIUS)
        if beyond.size:
            out.balance_until = float(result.t[max(beyond[0], 1)])
            result = result.window(result.t[0], out.balance_until)
        try:
            balance = energy_balance(model, result)
            out.relative_residual = balance.relative_residual
            out.relative_quadrature = balance.relative_quadrature_error
            out.flow_ratio = balance.flow / balance.scale if balance.scale > 0 else 1.0
        except rk.RotorkitError as err:
            out.balance_error = str(err)
    elif not out.finite:
        out.balance_error = "non-finite states"
    else:
        out.balance_error = "fewer than 2 samples"
    return out


def _inspect(out, result):
    """Finite states, |x2| and |r2| extremes and the run-away time, accumulated into ``out``."""
    if result.t.size == 0:
        return
    out.finite = out.finite and bool(np.all(np.isfinite(result.y)))
    x2, y2 = result["x2"], result["y2"]
    r2 = np.hypot(x2, y2)
    out.max_x2 = float(np.nanmax([out.max_x2, np.nanmax(np.abs(x2))]))
    out.max_r2 = float(np.nanmax([out.max_r2, np.nanmax(r2)]))
    if out.runaway_time is None and np.any(r2 > RUNAWAY_RADIUS):
        out.runaway_time = float(result.t[np.argmax(r2 > RUNAWAY_RADIUS)])


def format_table(outcomes):
    """The outcomes as a Markdown table."""
    head = ("| case | window (s) | engine / method | success | wall (s) | nfev | max \\|x2\\| (m) | "
            "energy rel. residual / allowed (quadrature) | verdict |")
    lines = [head, "| --- | --- | --- | --- | ---: | ---: | ---: | --- | --- |"]
    for o in outcomes:
        success = "yes" if o.success else f"no (t = {o.t_reached:.4g} s)"
        if o.balance_error:
            energy = o.balance_error
        else:
            energy = f"{o.relative_residual:.1e} / {o.tolerance:.0e} ({o.relative_quadrature:.0e})"
            if o.balance_until is not None:
                energy += f" up to t = {o.balance_until:.3g} s"
        cells = [o.case.key, f"{o.window[0]:g}-{o.window[1]:g}", f"{o.engine} / {o.method}", success,
                 f"{o.wall:.2f}", f"{o.nfev:,}", f"{o.max_x2:.3g}", energy, o.verdict]
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", help="cases as model:name (default: all)")
    parser.add_argument("--model", choices=sorted(BUILDERS), help="only the cases of one model")
    parser.add_argument("--ci", action="store_true", help="the short CI windows instead of the full spans")
    parser.add_argument("--rtol", type=float, default=RTOL)
    parser.add_argument("--sample-rate", type=float, default=None, help="Hz (default: 100 kHz full, 200 kHz CI)")
    parser.add_argument("--time-limit", type=float, default=TIME_LIMIT, help="wall-time limit per run (s)")
    parser.add_argument("--markdown", type=Path, help="also write the table to this file")
    args = parser.parse_args(argv)
    cases = [case(k) for k in args.only] if args.only else [c for c in CASES if c.full or args.ci]
    if args.model:
        cases = [c for c in cases if c.model == args.model]
    print(f"rotorkit {rk.__version__}, numpy {np.__version__}; rtol = {args.rtol:g}, atol = 1e-6 rtol; "
          f"balance tolerance {BALANCE_FACTOR:g} rtol per energy scale passed through; run-away radius {RUNAWAY_RADIUS * 1e3:g} mm", flush=True)
    outcomes = []
    start = time.perf_counter()
    for c in cases:
        window = c.ci_window if args.ci else c.span
        o = run(c, window, rtol=args.rtol, sample_rate=args.sample_rate, time_limit=args.time_limit)
        outcomes.append(o)
        energy = o.balance_error or f"{o.relative_residual:.1e} (quad {o.relative_quadrature:.0e})"
        if o.balance_until is not None and not o.balance_error:
            energy += f" up to t = {o.balance_until:.4g} s"
        print(f"{c.key:30s} {o.engine}/{o.method} success={o.success} wall={o.wall:.2f}s nfev={o.nfev:,} "
              f"max|x2|={o.max_x2:.3g} energy={energy} -> {o.verdict}", flush=True)
    table = format_table(outcomes)
    print()
    print(table)
    print(f"\n{sum(o.passed for o in outcomes)}/{len(outcomes)} passed; total {time.perf_counter() - start:.0f} s")
    if args.markdown:
        args.markdown.write_text(table + "\n")
    return 0 if all(o.passed for o in outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
