"""A rotor on a squeeze-film damper running up through its critical speed.

    python examples/sfd_runup.py [--plot runup.png]

A rigid rotor (10 kg, unbalance 20 um) sits in a squeeze-film damper
(short-bearing pi film) with a squirrel-cage centring spring; the critical
speed is sqrt(k_s / m). The rotor runs up linearly from 0.5 to 2 times the
critical speed in 2 s, once on the nonlinear damper and once on a linear
damper of the film's centred coefficient pi mu R L^3 / (2 c^3); the script
prints the peak whirl radius and the speed where it occurs. The film's
damping grows with the eccentricity (and its radial force stiffens the
support), so the nonlinear damper passes the critical speed with a smaller
peak, later, than its linearisation at the centre predicts.
"""

import argparse

import numpy as np

import rotorkit as rk
from rotorkit.elements import Disk, SpeedProfile

MASS, CAGE, UNBALANCE = 10.0, 1e6, 2e-5  # kg, N/m, m
DAMPER = dict(radius=0.05, length=0.015, clearance=2e-4, viscosity=0.01)  # m, m, m, Pa s
CRITICAL = np.sqrt(CAGE / MASS)  # rad/s
RUN = (0.0, 2.0)  # s
SPEEDS = (0.5 * CRITICAL, 2.0 * CRITICAL)  # rad/s


def model(with_damper):
    film = rk.SqueezeFilmDamper(station=1, centring_stiffness=CAGE, **DAMPER)
    support = film if with_damper else rk.ElasticSupport(station=1, stiffness=CAGE, damping=film.centred_damping())
    return rk.Model([
        rk.Rotor(name="R", stations=(1,), speed=SpeedProfile.table(times=RUN, speeds=SPEEDS)),
        Disk(station=1, mass=MASS, radius=0.1, eccentricity=UNBALANCE, torsion=False),
        support,
    ], name="sfd_runup" if with_damper else "linear_damper")


def run_up(with_damper):
    result = rk.simulate(model(with_damper).compile(), RUN, sample_rate=5000.0, rtol=1e-8, atol=1e-12)
    radius = np.hypot(result["x1"], result["y1"])
    speed = np.interp(result.t, RUN, SPEEDS)
    return result.t, speed, radius


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="save the run-up amplitude against speed to this image file")
    args = parser.parse_args()
    film = rk.SqueezeFilmDamper(station=1, **DAMPER)
    print(f"critical speed sqrt(k/m) = {CRITICAL:.1f} rad/s; damper centred damping "
          f"{film.centred_damping():.0f} N s/m (damping ratio {film.centred_damping() / (2 * np.sqrt(CAGE * MASS)):.3f})")
    curves = {}
    for label, with_damper in (("squeeze-film damper", True), ("linear damper (centred coefficient)", False)):
        t, speed, radius = run_up(with_damper)
        i = int(np.argmax(radius))
        curves[label] = (speed, radius)
        print(f"{label}: peak whirl radius {radius[i] * 1e6:.1f} um "
              f"(eps = {radius[i] / DAMPER['clearance']:.3f}) at {speed[i]:.1f} rad/s "
              f"= {speed[i] / CRITICAL:.3f} x critical")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots()
        for label, (speed, radius) in curves.items():
            ax.plot(speed, radius * 1e6, label=label)
        ax.axhline(DAMPER["clearance"] * 1e6, color="k", ls="--", lw=0.8, label="damper clearance")
        ax.set_xlabel("speed (rad/s)")
        ax.set_ylabel("whirl radius (um)")
        ax.legend()
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
