"""The Sommerfeld effect: a drive of limited torque captured at the critical speed of an unbalanced rotor.

    python examples/sommerfeld.py [--out docs/figures/drive]

A Jeffcott rotor (2 kg disk, critical speed 100 rad/s, 2 % damping,
eccentricity 1 mm) is run up from rest by a constant torque against a
viscous drag of 2e-3 N m s/rad (``Drive.constant``: the speed is a degree of
freedom). Without unbalance a torque of 0.4 N m would carry the rotor to
200 rad/s; with it, the unbalance whirl near resonance takes the torque and
the speed stays just below the critical speed. A torque of 0.8 N m passes
through. Prints the final speeds and writes ``sommerfeld.png`` (speed against
time, and whirl radius against speed) to ``--out``.
"""

import argparse
from pathlib import Path

import numpy as np

import rotorkit as rk

MASS, STIFFNESS, DAMPING, ECCENTRICITY, DRAG = 2.0, 2e4, 8.0, 1e-3, 2e-3
WN = np.sqrt(STIFFNESS / MASS)
TORQUES = (0.4, 0.8)  # N m


def model(torque):
    return rk.Model([
        rk.Rotor(name="R", stations=(1,), speed=rk.Drive.constant(torque=torque, initial_speed=0.0, drag=DRAG)),
        rk.Disk(station=1, mass=MASS, radius=0.1, eccentricity=ECCENTRICITY),
        rk.ElasticSupport(station=1, stiffness=STIFFNESS, damping=DAMPING),
    ], name="sommerfeld")


def main(out):
    system = model(TORQUES[0]).compile()
    runs = {}
    for torque in TORQUES:
        result = rk.simulate(system.with_parameters(R_speed_torque=torque), (0.0, 6.0), rtol=1e-8, atol=1e-11,
                             sample_rate=400.0)
        runs[torque] = result
        speed = result["spin1_dot"]
        print(f"torque {torque:.1f} N m: speed at 6 s {speed[-1]:6.1f} rad/s ({speed[-1] / WN:.2f} x critical "
              f"{WN:.0f} rad/s; {torque / DRAG:.0f} rad/s without unbalance), largest whirl radius "
              f"{np.hypot(result['x1'], result['y1']).max() * 1e3:.1f} mm")
    if out is None:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    for torque, result in runs.items():
        speed = result["spin1_dot"]
        left.plot(result.t, speed, label=f"T = {torque} N m")
        right.plot(speed, np.hypot(result["x1"], result["y1"]) * 1e3, label=f"T = {torque} N m")
    for ax in (left, right):
        ax.grid(alpha=0.3)
    left.axhline(WN, color="k", lw=0.8, ls="--", label="critical speed")
    right.axvline(WN, color="k", lw=0.8, ls="--")
    left.set(xlabel="time (s)", ylabel="speed (rad/s)", title="run-up with a limited torque")
    right.set(xlabel="speed (rad/s)", ylabel="whirl radius (mm)", title="whirl against speed")
    left.legend()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "sommerfeld.png", dpi=110)
    print(f"wrote {out / 'sommerfeld.png'}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None, help="folder for sommerfeld.png (no figure without it)")
    main(parser.parse_args().out)
