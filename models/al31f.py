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
