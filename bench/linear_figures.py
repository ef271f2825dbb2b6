"""Figures of the linear-analysis docs (docs/analysis-*.md) from a beam rotor and the AL-31F preset.

Run: ``python bench/linear_figures.py --out docs/figures/linear``

The beam rotor is the 400-coordinate one of ``bench/bench_linear.py``
(steel shaft of 99 Euler-Bernoulli elements, two disks, two bearings);
the textbook two-disk rotor of issue 8 will replace it once it exists.
It lives in bench/ beside the model it draws: it takes minutes (a
400-coordinate rotor, a 61-speed Campbell diagram, the critical speed map),
too long for the examples that CI runs.
"""

import argparse
import os
import sys
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):  # see bench/bench_linear.py
    os.environ.setdefault(_var, "1")
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))  # bench_linear.py beside this file

from bench_linear import beam_rotor  # noqa: E402

from rotorkit.analysis.campbell import campbell  # noqa: E402
from rotorkit.analysis.critical_map import critical_speed_map  # noqa: E402
from rotorkit.analysis.frf import frequency_response  # noqa: E402
from rotorkit.analysis.unbalance import Unbalance, unbalance_response  # noqa: E402


def save(fig, path):
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/figures/linear")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    model = beam_rotor()
    modes = model.modes(2000.0, n_modes=6)
    print(modes.table(units="Hz"))
    save(modes.plot_mode_shape(1).figure, out / "mode1.png")
    save(modes.plot_orbits(2).figure, out / "mode2_orbits.png")
    diagram = campbell(model, np.linspace(0.0, 3000.0, 61), n_modes=6)
    print(diagram.table())
    save(diagram.plot(units="rad/s").figure, out / "campbell.png")
    save(diagram.plot_stability().figure, out / "stability.png")
    r = unbalance_response(model, [Unbalance(31, 1e-4), Unbalance(71, 1e-4, 1.5)], np.linspace(10.0, 3000.0, 1000))
    top, _ = r.plot_bode("x31")
    save(top.figure, out / "bode_x31.png")
    save(r.plot_polar("x31").figure, out / "polar_x31.png")
    frf = frequency_response(model, np.linspace(1.0, 3000.0, 1000), inputs=["x31"], outputs=["x31", "x71"],
                             speed=1500.0)
    top, _ = frf.plot("x71", "x31")
    save(top.figure, out / "frf_x71_x31.png")
    bare = beam_rotor()
    K = np.array(bare.stiffness)
    for node in (5, 94):  # remove the bearings: the map adds its own support stiffness
        for i in (4 * node, 4 * node + 1):
            K[i, i] -= 1e7
    from rotorkit.analysis.linear_model import LinearModel

    shaft = LinearModel(mass=bare.mass, damping=np.zeros_like(K), stiffness=K, gyroscopic=bare.gyroscopic,
                        coordinate_names=bare.coordinate_names)
    cmap = critical_speed_map(shaft, supports=[6, 95], stiffnesses=np.logspace(5, 9, 5), speed_range=(1.0, 4000.0),
                              n_critical=2, n_speeds=20)
    save(cmap.plot(units="rad/s").figure, out / "critical_speed_map.png")


if __name__ == "__main__":
    main()
