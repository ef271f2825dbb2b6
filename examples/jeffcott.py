"""A Jeffcott rotor from rotorkit's objects, checked against its closed forms.

    python examples/jeffcott.py

Builds a disk on an elastic support, prints the derived equations, then
compares the simulated steady unbalance whirl with
e r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2) and the gravity sag with m g / k.
"""

import numpy as np

import rotorkit as rk

m, k, c, e = 2.0, 2e4, 20.0, 1e-4  # kg, N/m, N s/m, m
wn, zeta = np.sqrt(k / m), c / (2 * np.sqrt(k * m))


def model(speed):
    return rk.Model([
        rk.Rotor(name="R", stations=(1,), speed=speed),
        rk.Disk(station=1, mass=m, radius=0.1, eccentricity=e),
        rk.ElasticSupport(station=1, stiffness=k, damping=c),
        rk.Maneuver.steady(gravity=9.81),
    ], name="jeffcott")


if __name__ == "__main__":
    print(model(wn).equations())
    system = model(wn).compile()
    print(f"\nnatural frequency sqrt(k/m) = {wn:.2f} rad/s, damping ratio {zeta:.3f}, sag m g / k = {m * 9.81 / k:.3e} m")
    for ratio in (0.5, 1.0, 2.0):
        result = rk.simulate(system.with_parameters(R_speed=ratio * wn), (0.0, 3.0))
        late = result.window(2.5, 3.0)
        sag = late["y1"].mean()
        radius = np.hypot(late["x1"], late["y1"] - sag).mean()
        expected = e * ratio**2 / np.sqrt((1 - ratio**2) ** 2 + (2 * zeta * ratio) ** 2)
        print(f"speed {ratio:.1f} wn: whirl radius {radius:.4e} m (closed form {expected:.4e}), "
              f"sag {sag:.4e} m (closed form {-m * 9.81 / k:.4e})")
