"""The AL-31F dual rotor with an inter-shaft rub and a torque-driven LP spool (a variant of the preset).

    python examples/al31f_intershaft.py [--t-end 0.3]

Takes the elements of ``rotorkit.preset("al31f")`` (the preset itself is not
changed) and replaces its two rotors: the LP spool is turned by a turbine
torque balancing its drag at 1500 rad/s (``Drive.constant``: the LP speed is
a degree of freedom), the HP spool turns at a constant 2700 rad/s (its own
rotor, no longer geared to the LP). An ``IntershaftRub`` joins LP disk 5 and
HP station 7. The HP bore turns faster than the LP disk (2700 x 0.0304 m/s
against 1500 x 0.03 m/s at the surfaces): once they touch, the friction
drags the LP spool forward, and the LP speed rises above the 1500 rad/s its
turbine holds. The run prints the LP speed, the inter-shaft contact and the
energy balance.
"""

import argparse

import numpy as np

import rotorkit as rk
from rotorkit.analysis.energy import energy_balance

LP_SPEED, HP_SPEED = 1500.0, 2700.0  # rad/s
DRAG = 2e-3  # N m s/rad: the LP spool's aerodynamic drag, balanced by the turbine torque at LP_SPEED
CLEARANCE = 4.0e-4  # m, inter-shaft gap between LP disk 5 and the HP bore at station 7 (their relative whirl
#                     without the rub reaches 0.4-0.5 mm)


def variant():
    """The preset's elements with a driven LP, a constant-speed HP and an inter-shaft rub."""
    base = rk.preset("al31f", maneuver=False)
    kept = [e for e in base.elements if not isinstance(e, rk.Rotor)]
    lp = next(e for e in base.elements if isinstance(e, rk.Rotor) and e.name == "LP")
    drive = rk.Drive.constant(torque=DRAG * LP_SPEED, initial_speed=LP_SPEED, drag=DRAG, polar_inertia=0.05)
    rotors = [rk.Rotor(name="LP", stations=lp.stations, speed=drive),
              rk.Rotor(name="HP", stations=(7,), speed=HP_SPEED)]
    rub = rk.IntershaftRub(inner_station=5, outer_station=7, clearance=CLEARANCE, contact_stiffness=1e7,
                           friction_coefficient=0.1, contact_radius=0.03)
    return rk.Model(rotors + kept + [rub], name="al31f_intershaft")


def main(t_end):
    model = variant()
    print(f"{model!r}\ncoordinates: {', '.join(model.coordinate_names)}")
    system = model.compile()
    result = rk.simulate(system, (0.0, t_end), sample_rate=20_000.0, rtol=1e-7, atol=1e-11)
    speed = LP_SPEED + result["spin1_dot"]
    gap = np.hypot(result["x5"] - result["x7"], result["y5"] - result["y7"])
    contact = gap > CLEARANCE
    balance = energy_balance(model, result)
    print(f"LP speed: {speed[0]:.2f} rad/s at the start, {speed.min():.2f} .. {speed.max():.2f} rad/s over the run, "
          f"{speed[-1]:.2f} rad/s at t = {t_end:g} s")
    print(f"inter-shaft gap: largest {gap.max() * 1e6:.1f} um against a clearance of {CLEARANCE * 1e6:.1f} um; "
          f"in contact {100 * contact.mean():.1f} % of the samples")
    print(f"work of the inter-shaft rub on the model: {balance.work['intershaftrub5_7'][-1]:.4f} J; "
          f"energy balance relative residual {balance.relative_residual:.1e}")
    print(f"LP speed change by the rub: {speed[-1] - speed[0]:+.2f} rad/s")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=0.3, help="simulated time (s)")
    main(parser.parse_args().t_end)
