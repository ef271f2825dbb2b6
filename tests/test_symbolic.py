"""Per-element Lagrange derivation against sympy.physics.mechanics, and inspection."""

import numpy as np
import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

import rotorkit as rk


def two_disk_model():
    return rk.Model([
        rk.Rotor(name="R", stations=(0, 1, 2), speed=120.0),
        rk.LumpedMass(station=0, mass=1.5),
        rk.Disk(station=1, mass=4.0, radius=0.1, eccentricity=2e-3, phase=0.3, torsion=True),
        rk.Disk(station=2, mass=3.0, polar_inertia=0.02, eccentricity=1e-3, torsion=True),
        rk.ElasticSupport(station=0, stiffness=1e5, damping=20.0),
        rk.ElasticSupport(station=2, stiffness=2e5, damping=10.0),
        rk.ShaftSegment(start=0, end=1, bending_stiffness=3e5, bending_damping=5.0, torsional_stiffness=500.0,
                        torsional_damping=0.1),
        rk.ShaftSegment(start=1, end=2, bending_stiffness=4e5, torsional_stiffness=800.0),
        rk.Maneuver.steady(),
    ])


def test_matches_whole_system_lagranges_method():
    """Assemble T, V by hand for the whole system and let sympy's LagrangesMethod derive it."""
    model = two_disk_model()
    eom = model.equations()
    names = model.coordinate_names
    qf = dynamicsymbols(" ".join(names))
    t = dynamicsymbols._t
    P = {n: sp.Symbol(n, real=True) for n in model.parameters}
    q = dict(zip(names, qf))
    W = P["R_speed"]
    T = P["mass0_mass"] * (q["x0"].diff(t) ** 2 + q["y0"].diff(t) ** 2) / 2
    for s, J in ((1, P["disk1_mass"] * P["disk1_radius"] ** 2 / 2), (2, P["disk2_polar_inertia"])):
        m, e = P[f"disk{s}_mass"], P[f"disk{s}_eccentricity"]
        phi = W * t + P[f"disk{s}_phase"] + q[f"alpha{s}"]
        xg, yg = q[f"x{s}"] + e * sp.cos(phi), q[f"y{s}"] + e * sp.sin(phi)
        T += m * (xg.diff(t) ** 2 + yg.diff(t) ** 2) / 2 + J * phi.diff(t) ** 2 / 2
    V = 0
    for s, st in ((0, "support0"), (2, "support2")):
        V += P[f"{st}_stiffness"] * (q[f"x{s}"] ** 2 + q[f"y{s}"] ** 2) / 2
    for a, b, k in ((0, 1, "shaft0_1"), (1, 2, "shaft1_2")):
        V += P[f"{k}_bending_stiffness"] * ((q[f"x{a}"] - q[f"x{b}"]) ** 2 + (q[f"y{a}"] - q[f"y{b}"]) ** 2) / 2
    V += P["shaft0_1_torsional_stiffness"] * q["alpha1"] ** 2 / 2
    V += P["shaft1_2_torsional_stiffness"] * (q["alpha1"] - q["alpha2"]) ** 2 / 2
    g = P["maneuver_gravity"]
    V += g * (P["mass0_mass"] * q["y0"] + P["disk1_mass"] * q["y1"] + P["disk2_mass"] * q["y2"])
    lm = LagrangesMethod(T - V, qf)
    lm.form_lagranges_equations()
    M_ref, f_ref = lm.mass_matrix, lm.forcing
    # damping is not in L: compare with damping set to zero
    sub = {sp.Symbol(n, real=True): 0 for n in model.parameters if n.endswith("damping")}
    speeds = {qi.diff(t): sp.Symbol(f"{n}_dot", real=True) for qi, n in zip(qf, names)}
    coords = {qi: sp.Symbol(n, real=True) for qi, n in zip(qf, names)}

    def plain(expr):  # derivatives first, then the coordinates, then time
        return expr.subs(speeds).subs(coords).subs(t, eom.t)
    rng = np.random.default_rng(3)
    values = {sp.Symbol(k, real=True): v for k, v in model.parameters.items()}
    for _ in range(3):
        point = {c: rng.normal() * 1e-3 for c in eom.coordinates}
        point.update({u: rng.normal() * 1e-1 for u in eom.speeds})
        point[eom.t] = rng.uniform(0, 1)
        point.update(values)
        point.update(sub)
        for i in range(eom.n):
            ref_f = float(plain(f_ref[i]).subs(point))
            assert abs(float(eom.forcing[i].subs(point)) - ref_f) <= 1e-9 * max(1.0, abs(ref_f))
            for j in range(eom.n):
                ref_m = float(plain(M_ref[i, j]).subs(point))
                assert abs(float(eom.mass_matrix[i, j].subs(point)) - ref_m) <= 1e-12 * max(1.0, abs(ref_m))


def test_inspection_and_latex():
    eom = two_disk_model().equations()
    text = str(eom)
    assert "M[x1, alpha1]" in text and "F from maneuver" in text
    latex = eom._repr_latex_()
    assert latex.startswith("$$") and r"\mathbf{M}" in latex and r"\alpha_{1}" in latex
    assert eom.stiffness.is_symmetric() and eom.damping.is_symmetric() and eom.mass_matrix.is_symmetric()


def test_absent_effects_add_no_symbols():
    eom = rk.preset("al31f", rub=False, torsion=False, maneuver=False).equations()
    names = {s.name for s in eom.mass_matrix.free_symbols | eom.forcing.free_symbols}
    assert not any(n.startswith(("rub", "alpha")) for n in names)
    assert not any("roll" in n for n in names)
    assert eom.n == 14


def test_derives_and_compiles_a_64_dof_chain():
    """64 DOF: per-element derivation keeps this cheap (timing lives in bench/)."""
    n = 32
    elements = [rk.Rotor(name="R", stations=tuple(range(n)), speed=100.0)]
    elements += [rk.LumpedMass(station=i, mass=1.0) for i in range(n)]
    elements += [rk.ShaftSegment(start=i, end=i + 1, bending_stiffness=1e5, bending_damping=1.0) for i in range(n - 1)]
    elements += [rk.ElasticSupport(station=0, stiffness=1e5), rk.ElasticSupport(station=n - 1, stiffness=1e5)]
    system = rk.Model(elements).compile()
    assert system.n_states == 128
    y = np.zeros(128)
    y[5] = 1e-3
    dydt = system.rhs(0.0, y)
    assert dydt[64 + 5] == -2e5 * 1e-3 and dydt[64 + 4] == 1e5 * 1e-3 and dydt[64 + 6] == 1e5 * 1e-3
