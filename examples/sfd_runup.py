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

With ``--bistable FILE`` it also draws the bi-stable response of a lightly
damped damper (viscosity 4 mPa s, unbalance 0.15 c): the steady circular
orbits from the closed-form pi-film forces (three between about 1.20 and
1.26 times the critical speed, the middle one unstable) and a slow run-up
and run-down, which follow the large and the small orbit and jump between
them at the folds.
"""

import argparse
import math

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


def circular_orbits(speed, viscosity, unbalance):
    """Eccentricity ratios of the steady centred circular orbits (closed-form pi-film forces, San Andres)."""
    from scipy.optimize import brentq

    c, R, L = DAMPER["clearance"], DAMPER["radius"], DAMPER["length"]

    def balance(eps):
        K = viscosity * R * L**3 * speed / c**2
        radial, tangential = -K * 2 * eps**2 / (1 - eps**2) ** 2, -K * math.pi * eps / (2 * (1 - eps**2) ** 1.5)
        return ((CAGE - MASS * speed**2) * eps * c - radial) ** 2 + tangential**2 - (MASS * unbalance * speed**2) ** 2

    grid = np.linspace(1e-6, 0.99, 2000)
    g = [balance(e) for e in grid]
    return [brentq(balance, grid[i], grid[i + 1]) for i in range(len(grid) - 1) if g[i] * g[i + 1] < 0]


def bistable_figure(path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    viscosity, unbalance, span = 0.004, 0.15 * DAMPER["clearance"], (1.0, 1.4)
    fig, ax = plt.subplots()
    ratios = np.linspace(0.8, 1.6, 321)
    points = [(r, e) for r in ratios for e in circular_orbits(r * CRITICAL, viscosity, unbalance)]
    ax.plot(*zip(*points), "k.", ms=2, label="steady circular orbits (closed form)")
    for start, end, label in ((span[0], span[1], "run-up"), (span[1], span[0], "run-down")):
        film = rk.SqueezeFilmDamper(station=1, centring_stiffness=CAGE, **{**DAMPER, "viscosity": viscosity})
        profile = SpeedProfile.table(times=(0.0, 3.0), speeds=(start * CRITICAL, end * CRITICAL))
        m = rk.Model([rk.Rotor(name="R", stations=(1,), speed=profile),
                      Disk(station=1, mass=MASS, radius=0.1, eccentricity=unbalance, torsion=False), film])
        result = rk.simulate(m.compile(), (0.0, 3.0), sample_rate=5000.0, rtol=1e-8, atol=1e-12)
        settled = result.t > 0.3  # past the start from rest
        speed = np.interp(result.t[settled], (0.0, 3.0), (start, end))
        radius = np.hypot(result["x1"][settled], result["y1"][settled])
        ax.plot(speed, radius / DAMPER["clearance"], lw=0.8, label=label)
    ax.set_xlabel("speed / critical speed sqrt(k_s / m)")
    ax.set_ylabel("eccentricity ratio")
    ax.legend(loc="upper right")
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="save the run-up amplitude against speed to this image file")
    parser.add_argument("--bistable", help="save the bi-stable response (closed form, run-up, run-down) to this file")
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
    if args.bistable:
        bistable_figure(args.bistable)
