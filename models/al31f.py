"""AL-31F-like rub-impact dual rotor during a barrel roll (16 DOF).

Built exactly as ``shared/MODEL_NOTES.md`` states the paper's model
(bending-torsional coupling of a rub-impact dual rotor, eqs. 1-20, Table 1):

- LP rotor, stations 1..6 (masses 2, 10, 2, 2, 6, 2 kg), disks at 2 and 5
  with torsion; HP rotor, station 7 (8 kg, rigid, bending only) at
  ``speed_ratio`` times the LP speed.
- Supports k = 1e6 N/m, c = 300 N s/m at stations 1, 3, 7, 6 (the printed K
  matrix); shaft segments 1-2 (3EI/l^3), 2-3, 3-4, 4-5 (12EI/l^3), 5-6
  (3EI/l^3), c = 150 N s/m; torsion G Ip / l1 from the drive (station 1) to
  disk 2 and G Ip / (l2 + l3 + l4) from disk 2 to disk 5, c_t = 1 N m s/rad.
- Intermediate ball bearing, inner race at station 4, outer race at 7.
- Rub stator at disk 2; barrel roll from 2 s to 4 s; gravity always.

Overrides (SI floats or pint quantities): see ``DEFAULTS``. Switch effects
off with ``torsion=False``, ``rub=False``, ``maneuver=False`` (gravity
stays), ``gravity=0``.
"""

import math

import numpy as np

from rotorkit.elements import (
    BallBearing,
    Disk,
    ElasticSupport,
    LumpedMass,
    Maneuver,
    Rotor,
    RubStator,
    ShaftSegment,
)
from rotorkit.model import Model
from rotorkit.validation import ClaimResult

DESCRIPTION = "AL-31F-like rub-impact dual rotor in a barrel roll (16 DOF, Table 1 of the paper)"

#: override name -> default SI value
DEFAULTS = {
    "lp_speed": 1500.0,  # rad/s
    "speed_ratio": 1.8,
    "rub_stiffness": 8e6,  # N/m
    "friction_coefficient": 0.1,
    "rub_clearance": 1.34e-4,  # m
    "roll_rate": math.pi,  # rad/s
    "roll_radius": 3.0,  # m
    "roll_start": 2.0,  # s
    "roll_end": 4.0,  # s
    "gravity": 9.81,  # m/s^2
    "bearing_stiffness": 1.334e10,  # N/m^1.5
    "bearing_clearance": 5e-6,  # m
    "eccentricity_lp": 46.35e-6,  # m, disks 2 and 5
    "eccentricity_hp": 47.5e-6,  # m
    "support_stiffness": 1e6,  # N/m
    "support_damping": 300.0,  # N s/m
    "shaft_damping": 150.0,  # N s/m
    "torsional_damping": 1.0,  # N m s/rad
}

#: SI unit of each override, checked at the boundary
UNITS = {
    "lp_speed": "rad/s", "speed_ratio": "", "rub_stiffness": "N/m", "friction_coefficient": "",
    "rub_clearance": "m", "roll_rate": "rad/s", "roll_radius": "m", "roll_start": "s", "roll_end": "s",
    "gravity": "m/s**2", "bearing_stiffness": "N/m**1.5", "bearing_clearance": "m", "eccentricity_lp": "m",
    "eccentricity_hp": "m", "support_stiffness": "N/m", "support_damping": "N*s/m", "shaft_damping": "N*s/m",
    "torsional_damping": "N*m*s/rad",
}

#: switches: which effects the scene holds
SWITCHES = {"torsion": True, "rub": True, "maneuver": True}

E, I_AREA = 2e11, 1.178e-7
G, I_POLAR = 7.7e10, 2.356e-7
LENGTHS = (0.33, 0.33, 0.6, 0.23, 0.23)
MASSES = {1: 2.0, 3: 2.0, 4: 2.0, 6: 2.0}


def build(**overrides):
    """Build the preset with ``overrides`` of :data:`DEFAULTS` and :data:`SWITCHES`."""
    from rotorkit.errors import ParameterError

    unknown = set(overrides) - set(DEFAULTS) - set(SWITCHES)
    if unknown:
        import difflib

        name = sorted(unknown)[0]
        near = difflib.get_close_matches(name, list(DEFAULTS) + list(SWITCHES), n=3)
        hint = f"; did you mean {', '.join(near)}?" if near else ""
        raise ParameterError(
            f"al31f: unknown override {name!r}{hint} (known: {', '.join(list(DEFAULTS) + list(SWITCHES))})"
        )
    from rotorkit.units import to_si

    v = {**DEFAULTS, **SWITCHES}
    for name, value in overrides.items():
        if name in SWITCHES:
            if not isinstance(value, bool):
                raise ParameterError(f"al31f: {name}={value!r} must be True or False")
            v[name] = value
        else:
            v[name] = to_si(value, UNITS[name], f"al31f {name}")
    torsion = v["torsion"]
    l1, l2, l3, l4, l5 = LENGTHS
    elements = [
        Rotor(name="LP", stations=(1, 2, 3, 4, 5, 6), speed=v["lp_speed"]),
        Rotor(name="HP", stations=(7,), speed_ratio=v["speed_ratio"], reference="LP"),
        Disk(station=2, mass=10.0, radius=0.075, eccentricity=v["eccentricity_lp"], torsion=torsion),
        Disk(station=5, mass=6.0, radius=0.03, eccentricity=v["eccentricity_lp"], torsion=torsion),
        Disk(station=7, mass=8.0, radius=0.075, eccentricity=v["eccentricity_hp"]),
    ]
    elements += [LumpedMass(station=s, mass=m) for s, m in MASSES.items()]
    elements += [
        ElasticSupport(station=s, stiffness=v["support_stiffness"], damping=v["support_damping"])
        for s in (1, 3, 7, 6)
    ]
    segments = [(1, 2, l1, "clamped-free"), (2, 3, l2, "clamped-guided"), (3, 4, l3, "clamped-guided"),
                (4, 5, l4, "clamped-guided"), (5, 6, l5, "clamped-free")]
    for a, b, length, end in segments:
        torsional = {}
        if torsion and (a, b) == (1, 2):  # kt1 = G Ip / l1 ties disk 2 to the drive
            torsional = dict(shear_modulus=G, polar_area_moment=I_POLAR, torsional_damping=v["torsional_damping"])
        elements.append(ShaftSegment(start=a, end=b, length=length, youngs_modulus=E, area_moment=I_AREA,
                                     end_condition=end, bending_damping=v["shaft_damping"], **torsional))
    if torsion:  # kt2 = G Ip / (l2 + l3 + l4) ties disk 2 to disk 5
        elements.append(ShaftSegment(name="torsion2_5", start=2, end=5, length=l2 + l3 + l4, shear_modulus=G,
                                     polar_area_moment=I_POLAR, torsional_damping=v["torsional_damping"]))
    elements.append(BallBearing(inner_station=4, outer_station=7, contact_stiffness=v["bearing_stiffness"],
                                clearance=v["bearing_clearance"], n_balls=8, inner_race_radius=0.0401,
                                outer_race_radius=0.0639))
    if v["rub"]:
        elements.append(RubStator(station=2, clearance=v["rub_clearance"], contact_stiffness=v["rub_stiffness"],
                                  friction_coefficient=v["friction_coefficient"]))
    if v["maneuver"]:
        elements.append(Maneuver.barrel_roll(rate=v["roll_rate"], radius=v["roll_radius"], start=v["roll_start"],
                                             end=v["roll_end"], gravity=v["gravity"]))
    else:
        elements.append(Maneuver.steady(gravity=v["gravity"]))
    return Model(elements, name="al31f")

#: what ``rotorkit run al31f`` simulates and draws
OUTPUTS = {
    "t_end": 6.0,
    "orbit_station": 2,
    "clearance_parameter": "rub2_clearance",
    "bending": "x2",
    "torsion": "alpha2-alpha5",
}


# --------------------------------------------------------------------------
# The paper's claims, checked by `rotorkit validate al31f`
# --------------------------------------------------------------------------

def _orders(speed, ratio):
    high = ratio * speed
    return {"1/2 low": speed / 2, "low": speed, "5/4 low": 1.25 * speed, "3/2 low": 1.5 * speed,
            "high": high, "high - low": high - speed}


def _omega_b(study):
    """Lowest bending natural frequency, free and with the rub engaged (rad/s): computed, not assumed."""
    if not hasattr(study, "_omega_b"):
        from rotorkit.linear.modes import natural_frequencies

        system = build().compile()
        free = natural_frequencies(system).frequencies[0]
        # with the rub engaged along the sag, the pair splits: one mode stiffens
        engaged = natural_frequencies(system, rub_engaged=True).frequencies[:2].max()
        study._omega_b = (float(free), float(engaged))
    return study._omega_b


def _shows_b(study, spectrum):
    """omega_b shows if a component between the free and the rub-engaged value (+-2 %) does."""
    lo, hi = _omega_b(study)
    grid = np.linspace(min(lo, hi), max(lo, hi), 9)
    return any(study.shows(spectrum, f) for f in grid)


def _list(study, spectrum, orders, names):
    return ", ".join(f"{n} {study.describe(spectrum, orders[n])}" for n in names)


def _verdict(hits, total):
    return "reproduced" if hits == total else ("partly" if hits else "not reproduced")


def _skip(run, claim):
    return ClaimResult(claim, "could not run", f"{run.status}: {run.detail}")


def _read(study, claim, speed=None, **overrides):
    """(orders, bending spectrum, torsion spectrum) of a run, or the ClaimResult saying why it was not read."""
    run = study.run(**overrides)
    if run.status != "ok":
        return _skip(run, claim)
    orders = _orders(speed if speed is not None else DEFAULTS["lp_speed"], DEFAULTS["speed_ratio"])
    return orders, run.spectra["bending"], run.spectra["torsion"]


def claim_no_rub(study):
    claim = "Without rub, bending holds omega_low and omega_high; torsion holds omega_high - omega_low"
    read = _read(study, claim, rub=False)
    if isinstance(read, ClaimResult):
        return read
    o, b, t = read
    hits = [study.shows(b, o["low"]), study.shows(b, o["high"]), study.shows(t, o["high - low"])]
    return ClaimResult(claim, _verdict(sum(hits), 3),
                       f"bending: {_list(study, b, o, ['low', 'high'])}; torsion: high - low "
                       f"{study.describe(t, o['high - low'])} (share of the largest peak)")


def claim_kr_2e6(study):
    claim = "k_r = 2e6 N/m: bending shows no 1/2 omega_low, torsion shows omega_low"
    read = _read(study, claim, rub_stiffness=2e6)
    if isinstance(read, ClaimResult):
        return read
    o, b, t = read
    hits = [not study.shows(b, o["1/2 low"]), study.shows(t, o["low"])]
    return ClaimResult(claim, _verdict(sum(hits), 2),
                       f"bending 1/2 low {study.describe(b, o['1/2 low'])}; torsion low {study.describe(t, o['low'])}")


def claim_kr_8e6_bending(study):
    claim = "k_r = 8e6 N/m: bending shows 1/2 omega_low and omega_b"
    read = _read(study, claim, rub_stiffness=8e6)
    if isinstance(read, ClaimResult):
        return read
    o, b, t = read
    lo, hi = _omega_b(study)
    hits = [study.shows(b, o["1/2 low"]), _shows_b(study, b)]
    return ClaimResult(claim, _verdict(sum(hits), 2),
                       f"1/2 low {study.describe(b, o['1/2 low'])}; omega_b ({lo:.0f}-{hi:.0f} rad/s) "
                       f"{'shows' if hits[1] else 'absent'}")


def claim_kr_8e6_torsion(study):
    claim = "k_r = 8e6 N/m: torsion shows 1/2, 5/4, 3/2 omega_low plus omega_low and omega_high"
    read = _read(study, claim, rub_stiffness=8e6)
    if isinstance(read, ClaimResult):
        return read
    o, b, t = read
    names = ["1/2 low", "5/4 low", "3/2 low", "low", "high"]
    hits = [study.shows(t, o[n]) for n in names]
    missing = [n for n, h in zip(names, hits) if not h]
    return ClaimResult(claim, _verdict(sum(hits), len(names)), _list(study, t, o, names)
                       + (f"; below the threshold: {', '.join(missing)}" if missing else ""))


def claim_kr_14e6(study):
    claim = "k_r = 1.4e7 N/m: omega_b is gone from bending, 1/2 omega_low remains"
    read = _read(study, claim, rub_stiffness=1.4e7)
    if isinstance(read, ClaimResult):
        return read
    o, b, t = read
    hits = [not _shows_b(study, b), study.shows(b, o["1/2 low"])]
    return ClaimResult(claim, _verdict(sum(hits), 2),
                       f"omega_b {'shows' if not hits[0] else 'absent'}; 1/2 low {study.describe(b, o['1/2 low'])}")


KR_SWEEP = tuple(np.linspace(5e5, 2e7, 40))


def claim_kr_bifurcations(study):
    claim = ("k_r cascade 5e5-2e7 N/m: bending gains 1/2 omega_low and omega_b above ~5.5e6 N/m; "
             "omega_b disappears above ~1.15e7 N/m")
    o = _orders(DEFAULTS["lp_speed"], DEFAULTS["speed_ratio"])
    half, band_b, bad = [], [], []
    for kr in KR_SWEEP:
        run = study.run(rub_stiffness=float(kr))
        if run.status != "ok":
            bad.append(f"{kr:.3g} ({run.status})")
            continue
        b = run.spectra["bending"]
        half.append((kr, study.shows(b, o["1/2 low"])))
        band_b.append((kr, _shows_b(study, b)))
    onset = next((kr for kr, s in half if s), None)
    with_b = [kr for kr, s in band_b if s]
    loss = max(with_b) if with_b else None
    near = lambda value, target: value is not None and abs(value - target) <= 0.3 * target  # noqa: E731
    hits = [near(onset, 5.5e6), near(loss, 1.15e7)]
    measured = (f"first k_r with 1/2 low in bending: {onset:.3g} N/m" if onset else "1/2 low never shows") + "; " + (
        f"last k_r with omega_b: {loss:.3g} N/m" if loss else "omega_b never shows")
    if bad:
        measured += f"; not read: {', '.join(bad)}"
    return ClaimResult(claim, _verdict(sum(hits), 2), measured,
                       "a bifurcation point counts as reproduced within +-30 % of the paper's value")


MU_SWEEP = (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3)


def claim_friction(study):
    claim = "The friction coefficient (0-0.3) changes torsion far more than bending"
    spectra, bad = [], []
    for mu in MU_SWEEP:
        run = study.run(friction_coefficient=mu)
        if run.status != "ok":
            bad.append(f"mu={mu:g} ({run.status}: {run.detail})")
            continue
        spectra.append((mu, run.spectra["bending"].amplitude, run.spectra["torsion"].amplitude))
    if len(spectra) < 2:
        return ClaimResult(claim, "could not run", "; ".join(bad))
    base = spectra[0]
    change = lambda i: float(np.mean([np.linalg.norm(s[i] - base[i]) / np.linalg.norm(base[i])  # noqa: E731
                                      for s in spectra[1:]]))
    bend, tors = change(1), change(2)
    verdict = "reproduced" if tors >= 2 * bend else ("partly" if tors > bend else "not reproduced")
    measured = (f"mean relative change of the spectrum from mu = {base[0]:g}: torsion {tors:.3g}, "
                f"bending {bend:.3g} (ratio {tors / bend:.3g})")
    if bad:
        measured += f"; not read: {'; '.join(bad)}"
    return ClaimResult(claim, verdict, measured, "'far more' is read as at least twice the relative change")


SPEED_SWEEP = tuple(range(500, 3001, 125))


def claim_speed_region(study):
    claim = ("LP speed 500-3000 rad/s: bending shows fault frequencies (1/2 omega_low) only in the intermediate "
             "region 1140-1740 rad/s; torsion shows rub features (omega_low) at every speed")
    showing, torsion_all, bad = [], True, []
    for w in SPEED_SWEEP:
        run = study.run(lp_speed=float(w))
        if run.status != "ok":
            bad.append(f"{w} ({run.status})")
            continue
        o = _orders(float(w), DEFAULTS["speed_ratio"])
        if study.shows(run.spectra["bending"], o["1/2 low"]):
            showing.append(w)
        torsion_all &= study.shows(run.spectra["torsion"], o["low"])
    inside = [w for w in showing if 1140 - 125 <= w <= 1740 + 125]
    outside = [w for w in showing if w not in inside]
    hits = [bool(inside) and not outside, torsion_all]
    measured = (f"bending shows 1/2 low at {showing or 'no speed'} rad/s"
                + (f" (outside the region: {outside})" if outside else "")
                + f"; torsion shows omega_low at every speed: {torsion_all}")
    if bad:
        measured += f"; not read: {', '.join(bad)}"
    return ClaimResult(claim, _verdict(sum(hits), 2), measured, "region edges get one sweep step (125 rad/s) of slack")


def claim_speed_1800(study):
    claim = "omega_low = 1800 rad/s (Fig. 16): bending shows no fault frequency (1/2 omega_low), torsion shows omega_low"
    read = _read(study, claim, speed=1800.0, lp_speed=1800.0)
    if isinstance(read, ClaimResult):
        return read
    o, b, t = read
    hits = [not study.shows(b, o["1/2 low"]), study.shows(t, o["low"])]
    return ClaimResult(claim, _verdict(sum(hits), 2),
                       f"bending 1/2 low {study.describe(b, o['1/2 low'])}; torsion low {study.describe(t, o['low'])}")


#: the claims `rotorkit validate al31f` checks, in the paper's order
CLAIMS = (claim_no_rub, claim_kr_2e6, claim_kr_8e6_bending, claim_kr_8e6_torsion, claim_kr_14e6,
          claim_kr_bifurcations, claim_friction, claim_speed_region, claim_speed_1800)
