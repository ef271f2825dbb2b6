"""``rotorkit stiffness``: time scales of a scene and the integration method that fits."""

from .common import add_scene_arguments, load_preset, positive_float


def register(sub):
    st = sub.add_parser("stiffness", help="time scales of a scene and the integration method that fits")
    add_scene_arguments(st)
    st.add_argument("--t-end", type=positive_float, default=0.5, help="length of the trial run whose states are scanned (s)")
    st.set_defaults(func=main)


def main(args):
    from ..analysis.stiffness import stiffness_report
    from ..simulate import simulate

    _, model, _ = load_preset(args)
    system = model.compile()
    trial = simulate(system, (0.0, args.t_end), sample_rate=1000.0)
    report = stiffness_report(system, trial)
    print(f"fastest time scale {report.fastest_time_scale:.3g} s, slowest {report.slowest_time_scale:.3g} s, "
          f"stiffness ratio {report.ratio:.3g} (states at rest and along 0-{args.t_end:g} s)")
    print(f"suggested method: {report.suggested_method}: {report.reason}")
    return 0
