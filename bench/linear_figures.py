"""Figures of the linear-analysis docs (docs/analysis-*.md) from the textbook two-disk rotor.

Run: ``python bench/linear_figures.py --out docs/figures/linear``

The rotor is the two-disk rotor of ``examples/two_disk_rotor.py`` (Friswell
et al., *Dynamics of Rotating Machines*, ch. 5-6: a 1.5 m steel shaft of
50 mm diameter in 6 Timoshenko elements, two disks at 0.5 m and 1.0 m,
bearings kxx = 1 MN/m, kyy = 0.8 MN/m at both ends), with its bearings as
:class:`~rotorkit.LinearBearing` and, for the responses, a bearing damping
of 100 N s/m added here (the textbook example is undamped). The stability
diagram adds a cross-coupled stiffness growing with the speed
(``kxy = -kyx``, tabulated, 0 at rest to 50 kN/m at 400 rad/s): a
destabilising fluid-film-like effect with an onset speed. Everything is
evaluated from the derived symbolic matrices (no compiled code except for
the static deflection), so the script takes well under a minute: one
derivation per model structure, then only numbers.
"""

import argparse
import os
import sys
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):  # see bench/bench_linear.py
    os.environ.setdefault(_var, "1")
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "examples"))

from rotorkit import Maneuver, Model  # noqa: E402
from rotorkit.elements import LinearBearing  # noqa: E402
from rotorkit.linear.campbell import campbell  # noqa: E402
from rotorkit.linear.critical_map import critical_speed_map  # noqa: E402
from rotorkit.linear.frf import frequency_response  # noqa: E402
from rotorkit.linear.linear_model import LinearModel, linear_model  # noqa: E402
from rotorkit.linear.static import static_deflection  # noqa: E402
from rotorkit.linear.unbalance import Unbalance, unbalance_response  # noqa: E402

KXX, KYY, DAMPING = 1e6, 0.8e6, 100.0
SPEEDS = np.linspace(0.0, 450.0, 46)  # rad/s, about 0-4300 rpm


def two_disk(bearing=None, extra=()):
    """The example's rotor with its bearings replaced by ``bearing(station)`` (default: damped LinearBearing)."""
    from two_disk_rotor import two_disk_rotor

    if bearing is None:
        def bearing(station):
            return LinearBearing(station=station, kxx=KXX, kyy=KYY, cxx=DAMPING, cyy=DAMPING)

    base = two_disk_rotor()
    kept = [e for e in base.elements if not e.grounds()]
    return Model([*kept, bearing(1), bearing(7), *extra], name="two_disk_rotor")


_START = time.perf_counter()


def save(fig, path):
    fig.savefig(path, dpi=110, bbox_inches="tight")
    print(f"wrote {path} ({time.perf_counter() - _START:.1f} s)", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/figures/linear")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    model = two_disk()
    linear = linear_model(model, speed_parameter="R_speed", speed=0.0)
    modes = linear.modes(300.0)
    print(modes.table(units="Hz").splitlines()[0])
    print("\n".join(modes.table(units="Hz").splitlines()[2:8]))
    save(modes.plot_mode_shape(1, model=model).figure, out / "mode1.png")  # the rotor drawn under the shape
    save(modes.plot_orbits(3, model=model).figure, out / "mode3_orbits.png")

    diagram = campbell(model, SPEEDS, n_modes=6, speed_parameter="R_speed")
    print(diagram.table(units="rpm"))
    save(diagram.plot(units="rpm").figure, out / "campbell.png")

    cross = two_disk(lambda s: LinearBearing.tabulated(station=s, speeds=[0.0, 400.0], kxx=[KXX, KXX],
                                                       kyy=[KYY, KYY], kxy=[0.0, 5e4], kyx=[0.0, -5e4],
                                                       cxx=[DAMPING, DAMPING], cyy=[DAMPING, DAMPING]))
    unstable = campbell(cross, SPEEDS, n_modes=6, speed_parameter="R_speed")
    print("\n".join(unstable.table(units="rpm").splitlines()[-len(unstable.onsets) - 1:]))
    save(unstable.plot_stability(units="rpm").figure, out / "stability.png")

    speeds = np.linspace(5.0, 450.0, 1000)
    response = unbalance_response(linear, [Unbalance(3, 1e-4), Unbalance(5, 1e-4, np.pi / 2)], speeds)
    top, _ = response.plot_bode("x5")
    save(top.figure, out / "bode_x5.png")
    save(response.plot_polar("x5").figure, out / "polar_x5.png")
    frf = frequency_response(linear, np.linspace(1.0, 1000.0, 1000), inputs=["x3"], outputs=["x3", "x5"],
                             speed=300.0)
    top, _ = frf.plot("x5", "x3")
    save(top.figure, out / "frf_x5_x3.png")

    # critical speed map: the shaft alone (isotropic bearings removed), supports of stiffness k at 1 and 7
    iso = linear_model(two_disk(lambda s: LinearBearing(station=s, kxx=KXX, kyy=KXX)), speed_parameter="R_speed",
                       speed=0.0)
    K = np.array(iso.stiffness)
    for station in (1, 7):
        for i in iso.station_index(station):
            K[i, i] -= KXX
    shaft = LinearModel(mass=iso.mass, damping=np.zeros_like(K), stiffness=K, gyroscopic=iso.gyroscopic,
                        coordinate_names=iso.coordinate_names, station_positions=iso.station_positions,
                        rotor_speeds=iso.rotor_speeds, speed_parameter=iso.speed_parameter)
    cmap = critical_speed_map(shaft, supports=[1, 7], stiffnesses=np.logspace(5, 9, 17), speed_range=(1.0, 1500.0),
                              n_critical=3, n_speeds=60)
    save(cmap.plot(units="rpm").figure, out / "critical_speed_map.png")

    sag = static_deflection(two_disk(extra=[Maneuver.steady(gravity=9.81)]).compile(backend="python"))
    print(sag.table().splitlines()[-3:])
    save(sag.plot().figure, out / "static.png")


if __name__ == "__main__":
    main()
