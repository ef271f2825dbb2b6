"""Gyroscopics of the finite-element rotor under changing speed, and the energy they do not change.

- Changing speed: a spinning section carries ``T_g = I_p Omega(t) thx' thy``;
  Lagrange's equations give ``I_d thx'' + I_p Omega thy' + I_p Omega' thy``
  and ``I_d thy'' - I_p Omega thx'``. The ``I_p Omega'`` term is checked on a
  disk (hand derivation) and, for beam elements plus a disk, the whole
  element-by-element derivation equals sympy's ``LagrangesMethod`` applied
  to the model's total energies under a speed profile.
- Energy: gyroscopic forces ``-G q'`` with ``G`` skew do no work, so an
  undamped, unforced FE rotor at constant speed keeps its energy
  ``h = 1/2 q'^T M q' + 1/2 q^T K q`` (the Jacobi integral of its
  Lagrangian) to integration tolerance, while gyroscopics move energy from
  one bending plane to the other.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from rotorkit import Disk, Model, Rotor, simulate
from rotorkit.elements import BeamSegment, LinearBearing, Material, SpeedProfile
from helpers import Clamp  # noqa: E402

STEEL = Material.steel()


def ramp():
    return SpeedProfile.expression(lambda t, w0, a: w0 + a * t, parameters={"w0": 100.0, "a": 400.0})


def numeric(eom, model, expr, **at):
    """``expr`` with the parameter values of ``model`` and the given symbol values."""
    values = {p: model.parameters[str(p)] for p in eom.parameters}
    values.update({sp.Symbol(k, real=True): v for k, v in at.items()})
    return float(sp.sympify(expr).subs(values))


def test_disk_moment_of_angular_acceleration_is_ip_omega_dot():
    """Overhung disk on a (near-massless) cantilever: d f_thx / d thy = -I_p Omega', d f_thy / d thx = 0."""
    massless = Material(density=1e-9, youngs_modulus=STEEL.youngs_modulus, shear_modulus=STEEL.shear_modulus)
    disk = Disk.from_geometry(station=2, width=0.03, outer_diameter=0.25, material=STEEL)
    model = Model([Rotor(name="R", stations=(1, 2), speed=ramp()), Clamp(station=1, stiffness=1e12), disk,
                   BeamSegment(start=1, end=2, length=0.3, outer_diameter=0.02, material=massless)])
    eom = model.equations()
    names = [str(q) for q in eom.coordinates]
    f_thx, f_thy = eom.forcing[names.index("thx2")], eom.forcing[names.index("thy2")]
    thx, thy = eom.coordinates[names.index("thx2")], eom.coordinates[names.index("thy2")]
    ip, accel = disk.polar_inertia, 400.0
    # the beam's own share is rho I_p of a 1e-9 kg/m^3 shaft: negligible
    assert abs(numeric(eom, model, sp.diff(f_thx, thy), t=0.3) + ip * accel) < 1e-9 * ip * accel
    assert abs(numeric(eom, model, sp.diff(f_thy, thx), t=0.3)) < 1e-9 * ip * accel
    # and the gyroscopic coupling at the speed of that instant, Omega(0.3) = 220 rad/s
    thx_dot = eom.speeds[names.index("thx2")]
    speed = 100.0 + 400.0 * 0.3
    assert abs(numeric(eom, model, sp.diff(f_thy, thx_dot), t=0.3) - ip * speed) < 1e-9 * ip * speed


def test_beam_under_speed_profile_equals_whole_system_lagranges_method():
    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

    model = Model([Rotor(name="R", stations=(1, 2), speed=ramp()),
                   BeamSegment(start=1, end=2, length=0.6, outer_diameter=0.04, material=STEEL, elements=1),
                   Disk.from_geometry(station=2, width=0.02, outer_diameter=0.2, material=STEEL),
                   LinearBearing(station=1, kxx=1e6, kyy=8e5), LinearBearing(station=2, kxx=1e6, kyy=8e5)])
    eom = model.equations()
    assert eom.t in eom.kinetic.free_symbols  # the spin speed changes
    # numbers for the geometry and material (exact rationals: the comparison stays exact), symbols for the speed
    numbers = {p: sp.nsimplify(model.parameters[str(p)], rational=True) for p in eom.parameters
               if not str(p).startswith("R_speed")}
    qt = [dynamicsymbols(str(q)) for q in eom.coordinates]
    to_t = {**dict(zip(eom.coordinates, qt)), **{u: sp.diff(q, dynamicsymbols._t) for u, q in zip(eom.speeds, qt)}}
    lagrangian = (eom.kinetic - eom.potential).xreplace(numbers).subs(eom.t, dynamicsymbols._t).subs(to_t)
    lm = LagrangesMethod(lagrangian, qt)
    lm.form_lagranges_equations()
    back = {v: k for k, v in to_t.items()}
    mass = lm.mass_matrix.subs(back)
    forcing = lm.forcing.subs(back).subs(dynamicsymbols._t, eom.t)
    assert (mass - eom.mass_matrix.xreplace(numbers)).applyfunc(sp.expand) == sp.zeros(eom.n, eom.n)
    assert (forcing - eom.forcing.xreplace(numbers)).applyfunc(sp.expand) == sp.zeros(eom.n, 1)


def fe_rotor(speed):
    return Model([Rotor(name="R", stations=(1, 2, 3), speed=speed),
                  BeamSegment(start=1, end=2, length=0.3, outer_diameter=0.03, material=STEEL),
                  BeamSegment(start=2, end=3, length=0.3, outer_diameter=0.03, material=STEEL),
                  Disk.from_geometry(station=2, width=0.03, outer_diameter=0.3, material=STEEL),
                  LinearBearing(station=1, kxx=2e6, kyy=1e6), LinearBearing(station=3, kxx=2e6, kyy=1e6)])


def test_gyroscopic_forces_do_no_work():
    eom = fe_rotor(2000.0).equations()
    G = -sp.Matrix(eom.forcing).jacobian(eom.speeds)  # undamped: all of it is gyroscopic
    assert G.T == -G
    assert any(v != 0 for v in G)
    u = sp.Matrix(eom.speeds)
    assert sp.expand((u.T * G * u)[0]) == 0


def test_undamped_gyroscopic_fe_rotor_conserves_energy():
    model = fe_rotor(3000.0)
    eom = model.equations()
    system = model.compile(backend="python")
    # the Jacobi integral of L = T - V: h = q' dT/dq' - T + V (the T linear in q', N q, drops out)
    T, V = eom.kinetic, eom.potential
    h = (sum((u * sp.diff(T, u) for u in eom.speeds), sp.S.Zero) - T + V).subs(eom.t, 0.0)  # e = 0: no t
    args = list(eom.coordinates) + list(eom.speeds) + list(eom.parameters)
    h_of = sp.lambdify(args, h)
    values = [model.parameters[str(p)] for p in eom.parameters]
    y0 = system.initial_state(thy2_dot=2.0, x2=1e-4)  # a conical swing in the x-z plane
    result = simulate(system, (0.0, 0.05), y0=y0, rtol=1e-12, atol=1e-15, sample_rate=20_000.0)
    states = [result[n] for n in system.coordinate_names] + [result[f"{n}_dot"] for n in system.coordinate_names]
    energy = h_of(*states, *values)
    assert np.ptp(energy) < 1e-8 * energy[0]
    # gyroscopics move the motion into the other plane (so the test is not trivially planar)
    assert np.max(np.abs(result["thx2"])) > 0.2 * np.max(np.abs(result["thy2"]))
