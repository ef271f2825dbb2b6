"""``rotorkit modes``: modal analysis at the scene's operating point (log decrement, whirl, shapes)."""

from .common import nonnegative_int, positive_int, save_figure
from .linear_common import add_linear_arguments, linear_scene, output_folder


def register(sub):
    p = sub.add_parser("modes", help="natural frequencies, damping, log decrement and whirl at one speed")
    add_linear_arguments(p)
    p.add_argument("--rub-engaged", action="store_true", help="linearise with the rub contact engaged along the sag")
    p.add_argument("--shapes", type=nonnegative_int, default=4, help="number of mode-shape figures to write (default 4)")
    p.add_argument("--cage-samples", type=positive_int, default=16, help="cage positions averaged (default 16)")
    p.add_argument("--modes", type=positive_int, default=8, dest="n_modes",
                   help="number of modes printed (default 8; the CSV holds all)")
    p.set_defaults(func=main)


def main(args):
    from ..linear.modes import natural_frequencies

    system, parameter = linear_scene(args)
    modes = linear_modes(system) if not hasattr(system, "rhs") else None  # a linear model: nothing compiled
    if modes is None:
        if not hasattr(system, "rhs"):
            system = system.compile(backend=args.backend)
        modes = natural_frequencies(system, rub_engaged=True if args.rub_engaged else None,
                                    cage_samples=args.cage_samples)
    out = output_folder(args, "modes")
    from ..units import display_factor

    speed = system.parameters[parameter] * display_factor(args.units)
    print(f"modes of {system.name} at {parameter} = {speed:g} {args.units}")
    print(modes.table(units=args.units, n_modes=args.n_modes))
    modes.to_csv(out / "modes.csv", units=args.units)
    for mode in range(1, min(args.shapes, len(modes)) + 1):
        save_figure(modes.plot_mode_shape(mode, units=args.units).figure, out / f"mode{mode}.png")
        save_figure(modes.plot_orbits(mode, units=args.units).figure, out / f"mode{mode}_orbits.png")
    print(f"wrote {out / 'modes.csv'} and {min(args.shapes, len(modes))} mode-shape figures to {out}")
    return 0


def linear_modes(model, t=0.0):
    """The modes :func:`~rotorkit.analysis.modes.natural_frequencies` gives for a linear model, without compiling.

    The state matrix ``[[0, I], [-M^-1 K, -M^-1 C]]`` from the cached
    matrices is the Jacobian the compiled system would give (a linear model's
    does not depend on the operating point), solved and normalised as there
    (left shapes of the mass-normalised problem), at the static deflection.
    None when a rotor's speed is a profile or a drive (their coordinates and
    speeds are the compiled system's business).
    """
    import numpy as np

    from ..linear.linear_matrices import frozen_speed_model, linear_evaluator, linear_static_deflection
    from ..linear.modal import modes_from_state_matrix
    from ..plotting.rotor import rotor_layout

    if frozen_speed_model(model, t) is not model:
        return None
    evaluator = linear_evaluator(model, t)
    if evaluator is None:
        return None
    M, C, K = evaluator.dense()
    n = M.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:] = -np.linalg.solve(M, np.hstack([K, C]))
    q = linear_static_deflection(model, t)
    modes = modes_from_state_matrix(A, tuple(model.coordinate_names), left=True, operating_point=q,
                                    sample_times=np.array([float(t)]), rub_engaged=False, speed=None)
    object.__setattr__(modes, "layout", rotor_layout(model))
    return modes
