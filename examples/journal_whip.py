"""A rigid rotor on short journal bearings running up through its oil-whip threshold.

    python examples/journal_whip.py [--plot whip.png]

Half of a symmetric rigid rotor (50 kg) on one short plain journal bearing
(pi film) under gravity. The linear stability analysis (``campbell`` with
``relinearize=True``: the equilibrium moves with the speed) gives the speed
where the half-speed whirl becomes unstable; a run-up from 0.8 to 1.15 times
that speed in 1 s, then held there, shows the whirl about the moving
equilibrium dying out below it and, once above, growing into a whip orbit
of large eccentricity at a whirl frequency near half the speed.
"""

import argparse

import numpy as np

import rotorkit as rk
from rotorkit.linear.linearize import static_equilibrium
from rotorkit.linear.campbell import campbell
from rotorkit.elements import LumpedMass, SpeedProfile

MASS, GRAVITY = 50.0, 9.81  # kg, m/s^2
BEARING = dict(station=1, radius=0.025, length=0.02, clearance=5e-5, viscosity=0.02)  # m, m, m, Pa s
RAMP, END = (0.0, 1.0), 2.0  # s: run-up, then held at the final speed


def model(speed):
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=speed), LumpedMass(station=1, mass=MASS),
                     rk.JournalBearing(**BEARING), rk.Maneuver.steady(gravity=GRAVITY)], name="journal_whip")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="save the speed and the horizontal motion against time to this image file")
    args = parser.parse_args()
    linear = campbell(model(1000.0).compile(), np.linspace(600.0, 1800.0, 7), n_modes=2, relinearize=True)
    onset = linear.onsets[0]
    print(f"whip threshold from the linear stability analysis: {onset.speed:.1f} rad/s, whirl at "
          f"{onset.frequency:.1f} rad/s = {onset.frequency / onset.speed:.3f} x speed")
    speeds = (0.8 * onset.speed, 1.15 * onset.speed)
    system = model(SpeedProfile.table(times=RAMP, speeds=speeds)).compile()
    start = static_equilibrium(system)
    result = rk.simulate(system, (0.0, END), y0=[start[0] + 2e-6, start[1], 0.0, 0.0], sample_rate=20000.0,
                         rtol=1e-8, atol=1e-13)
    speed = np.interp(result.t, RAMP, speeds)
    for lo, hi in ((0.1, 0.3), (0.6, 0.8), (1.0, 1.2), (1.8, 2.0)):
        window = result.window(lo, hi)
        print(f"{lo:.1f}-{hi:.1f} s, speed {np.interp(lo, RAMP, speeds) / onset.speed:.2f}-"
              f"{np.interp(hi, RAMP, speeds) / onset.speed:.2f} x threshold: x swings by +-"
              f"{np.ptp(window['x1']) / 2 * 1e6:.3g} um, eccentricity ratio up to "
              f"{np.hypot(window['x1'], window['y1']).max() / BEARING['clearance']:.3f}")
    spectrum = result.window(END - 0.3, END).spectrum("x1", highpass=5.0)  # Hz: drops the static position
    whirl = spectrum.frequency[np.argmax(spectrum.amplitude)]
    print(f"last 0.3 s: dominant whirl {whirl:.0f} rad/s = {whirl / speeds[1]:.2f} x speed")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (top, bottom) = plt.subplots(2, 1, sharex=True)
        top.plot(result.t, speed / onset.speed)
        top.axhline(1.0, color="k", ls="--", lw=0.8, label="threshold (linear analysis)")
        top.set_ylabel("speed / threshold")
        top.legend()
        bottom.plot(result.t, result["x1"] / BEARING["clearance"], lw=0.5)
        bottom.set_xlabel("time (s)")
        bottom.set_ylabel("x / clearance")
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
