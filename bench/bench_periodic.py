"""Periodic response by harmonic balance: speed against time integration, Floquet cost, and the docs figure.

    PYTHONPATH=. python bench/bench_periodic.py                       # sections a and c, median of 3
    PYTHONPATH=. python bench/bench_periodic.py --sections a --repeat 5
    PYTHONPATH=. python bench/bench_periodic.py --sections figure --out docs/figures/periodic
    PYTHONPATH=. python bench/bench_periodic.py --blas-threads 2                # numpy's BLAS on 2 threads

Sections (each prints what it measured in this run, and the load average):

``a``       Jeffcott rotor with a concentric rub stator (the example of
            docs/periodic.md): a branch of about 200 points from 60 to 200
            rad/s through its fold pair (``periodic_response``, H = 3,
            stability by Hill's method included) against the compiled time
            integration (``simulate``, the C engine, rtol 1e-6) of as many
            speeds, each from rest to a settled orbit (``SETTLE_PERIODS``
            periods, the way a sweep finds them), which times ``--runs``
            speeds and scales to the branch's point count. The branch, the
            branch without stability and the ``--runs`` integrations are
            timed in turn, ``--repeat`` times, and the ratio is the median of
            the repetitions' ratios (both sides of each timed within a
            fraction of a second: the machine's speed phases, about 1.5x
            apart and seconds long, touch both alike). The ratio is the
            issue's target (a), >= 50; it also prints the ratio of the same
            branch without stability (``stability="none"``), which gives
            what the time integration gives (orbits), and error estimates. The branch runs on the compiled path
            (rotorkit/periodic/fastpath.py); the bench prints how its time
            per point splits (the continuation kernel, the per-point error
            estimate and Hill kernel, the rest in Python) and the first
            call's time (the kernels loaded from the disk cache, or compiled).
``b``       the 24-element (100-coordinate) beam rotor of bench/bench_fe.py
            with its rub stator, condensed onto the contact coordinates
            (``condense=True``): one harmonic-balance solution at a new speed
            (the frame there included) and a branch of about 100 points over
            a speed range (error estimates included, no stability), each the
            median of ``--repeat``. Targets (b): <= 20 ms and <= 5 s.
``c``       Floquet multipliers of one solution of an ``n``-coordinate chain
            rotor with a rub (``--coordinates``, default 100): Hill's method
            and the monodromy matrix. Target (c): <= 0.5 s.
``figure``  docs/periodic.md's figure: the branch of section a, with a
            run-up and a run-down in time (each speed from the previous
            speed's final state, an integer number of periods, the settled
            max radius) marked on it.
``sfd``     docs/periodic.md's squeeze-film figure: the bi-stable branch of
            the SFD-supported Jeffcott rotor of tests/test_periodic_sfd.py
            with a run-up and a run-down in time marked on it.
``doubling`` docs/periodic.md's period-doubling figure: the rubbing rotor of
            tests/test_periodic_doubling.py, its synchronous branch, the
            period-doubled branch switched onto at the doubling, and settled
            time runs (max radius).

"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path


def _blas_threads():
    """``--blas-threads N`` (default 1), set before numpy loads: the matrices here are small (<= 700), and on a
    shared machine a multi-threaded BLAS call waits for its threads (seconds per call under load)."""
    for i, arg in enumerate(sys.argv):
        if arg.startswith("--blas-threads"):
            return arg.split("=", 1)[1] if "=" in arg else sys.argv[i + 1]
    return "1"


BLAS_THREADS = _blas_threads()
for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_name] = BLAS_THREADS

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

M, K, C, E = 2.0, 2.0e4, 4.0, 2.0e-5
DELTA, KR = 1.0e-4, 2.0e4
SPEEDS = (60.0, 200.0)
#: the arclength steps of section a's branch: about 200 points, as target (a) asks (smaller steps give more points
#: at less time per point, so a higher ratio: not the branch the target names)
BRANCH_STEPS = dict(step=0.02, max_step=0.05)
SETTLE_PERIODS = 300  # zeta = 0.01, wn = 100 rad/s: the transient decays by exp(-2 pi zeta wn 300 / W): 2e-14 at 60 rad/s, 8e-5 at 200


def jeffcott_rub(speed=60.0):
    from rotorkit import Disk, ElasticSupport, Model, Rotor, RubStator

    return Model([Rotor(name="R", stations=(1,), speed=speed),
                  Disk(station=1, mass=M, radius=0.1, eccentricity=E, torsion=False),
                  ElasticSupport(station=1, stiffness=K, damping=C),
                  RubStator(station=1, clearance=DELTA, contact_stiffness=KR, friction_coefficient=0.0)],
                 name="jeffcott_rub")


def load():
    return os.getloadavg()[0]


def settled_radius(system, speed, y0=None, periods=SETTLE_PERIODS):
    """Max radius (m) over the last 4 periods of a run of ``periods`` periods at ``speed``, and the final state."""
    from rotorkit import simulate

    T = 2 * np.pi / speed
    run = simulate(system.with_parameters(R_speed=speed), (0.0, periods * T), y0=y0, rtol=1e-6, atol=1e-10,
                   sample_times=np.linspace((periods - 4) * T, periods * T, 257))
    return float(np.max(np.hypot(run.y[0], run.y[1]))), run.y[:, -1]


class _Timed:
    """Wall time spent in a function of a module (replaced by a timing wrapper while the ``with`` lasts)."""

    def __init__(self, module, name):
        self.module, self.name, self.total = module, name, 0.0

    def __enter__(self):
        self.function = function = getattr(self.module, self.name)

        def timed(*args, **kwargs):
            self.last = args, kwargs  # the last call's arguments
            t0 = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                self.total += time.perf_counter() - t0

        setattr(self.module, self.name, timed)
        return self

    def __exit__(self, *exc):
        setattr(self.module, self.name, self.function)


def section_a(repeat, runs, steps=(BRANCH_STEPS["step"], BRANCH_STEPS["max_step"])):
    from rotorkit.analysis.periodic import periodic_response
    from rotorkit.periodic import fastpath

    system = jeffcott_rub().compile(backend="c")
    t0 = time.perf_counter()
    fastpath.compile_kernels(verbose=False)  # loaded from the disk cache, or compiled (1.5 min) on a fresh one
    periodic_response(system, speeds=SPEEDS, harmonics=3, max_points=20)  # warm: Jacobian module, C builds
    warm = time.perf_counter() - t0
    settled_radius(system, 100.0, periods=10)
    # the branch, the branch without stability and the time integration of `runs` speeds in turn, `repeat` times:
    # each repetition's ratio has both sides timed within a fraction of a second, so the machine's speed phases
    # (it switches between two about 1.5x apart, for seconds at a time) touch both alike; the median of the
    # repetitions' ratios is the result
    speeds = np.linspace(*SPEEDS, runs)
    hb_times, bare_times, time_times, branch, parts, data_call = [], [], [], None, [], None
    for _ in range(repeat):
        with _Timed(fastpath, "continue_compiled") as loop, _Timed(fastpath, "point_data") as data:
            t0 = time.perf_counter()
            branch = periodic_response(system, speeds=SPEEDS, harmonics=3, step=steps[0], max_step=steps[1])
            hb_times.append(time.perf_counter() - t0)
        parts.append((loop.total, data.total))
        data_call = data.last
        t0 = time.perf_counter()
        periodic_response(system, speeds=SPEEDS, harmonics=3, step=steps[0], max_step=steps[1], stability="none")
        bare_times.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        for w in speeds:
            settled_radius(system, w)
        time_times.append((time.perf_counter() - t0) / runs)
    n = len(branch)
    ratios = [n * r / b for r, b in zip(time_times, hb_times)]
    bare_ratios = [n * r / b for r, b in zip(time_times, bare_times)]
    hb, per_run = statistics.median(hb_times), statistics.median(time_times)
    print(f"(a) Jeffcott rub branch, {n} points, folds at "
          f"{', '.join(f'{b.parameter:.2f}' for b in branch.bifurcations)} rad/s: {hb:.3f} s "
          f"({1e3 * hb / n:.1f} ms/point, stability included)")
    print(f"    time integration to a settled orbit ({SETTLE_PERIODS} periods, C engine): {per_run:.3f} s per speed, "
          f"{n} speeds {n * per_run:.1f} s")
    loop, data = (statistics.median(p[k] for p in parts) for k in (0, 1))
    problem = _problem(system)
    compiled = "compiled" if fastpath.compiled_setup(problem) is not None else "Python (numba missing?)"
    errors_only = []
    args, kwargs = data_call  # the branch's own call: its points, and the continuation's scales and accelerations
    for _ in range(repeat):
        t0 = time.perf_counter()
        fastpath.point_data(*args[:3], "none", *args[4:], **kwargs)
        errors_only.append(time.perf_counter() - t0)
    alone = statistics.median(errors_only)
    print(f"    per point ({compiled} path): continuation {1e3 * loop / n:.3f} ms, error estimate + Hill "
          f"{1e3 * data / n:.3f} ms (the error estimate alone {1e3 * alone / n:.3f} ms), the rest (start solution, "
          f"amplitude scale, fold location) {1e3 * (hb - loop - data) / n:.3f} ms; first call of the process (kernels "
          f"loaded or compiled) {warm:.1f} s")
    print(f"    without stability (stability=\"none\": the orbits and error estimates, what the time integration gives): "
          f"{statistics.median(bare_times):.3f} s, ratio {statistics.median(bare_ratios):.3g}x")
    os.environ["ROTORKIT_PERIODIC_COMPILED"] = "0"
    try:
        t0 = time.perf_counter()
        periodic_response(system, speeds=SPEEDS, harmonics=3, step=steps[0], max_step=steps[1])
        python = time.perf_counter() - t0
    finally:
        os.environ.pop("ROTORKIT_PERIODIC_COMPILED")
    print(f"    the same branch on the Python path (ROTORKIT_PERIODIC_COMPILED=0, once): {python:.3f} s, "
          f"{python / hb:.2g}x the compiled path's time")
    print(f"    ratio {statistics.median(ratios):.3g}x (target >= 50x; the median of {repeat} repetitions' ratios, "
          f"{min(ratios):.3g}x to {max(ratios):.3g}x); load {load():.1f}")


def _problem(system):
    from rotorkit.periodic.continuation import ContinuationProblem
    from rotorkit.periodic.hb import HarmonicBalance

    return ContinuationProblem(HarmonicBalance(system, speed_parameter="R_speed", harmonics=3), "R_speed")


def section_b(repeat, nodes):
    from bench_fe import fe_rotor

    from rotorkit.analysis.periodic import periodic_response, periodic_solution

    t0 = time.perf_counter()
    system = fe_rotor(nodes).compile()
    print(f"(b) {len(system.coordinate_names)}-coordinate beam rotor ({system.backend}): derive + compile "
          f"{time.perf_counter() - t0:.1f} s")
    speed = system.parameters["R_speed"]
    t0 = time.perf_counter()
    first = periodic_solution(system, harmonics=3, condense=True, stability="none")
    print(f"    first solution (Jacobian module, condensation set-up) {time.perf_counter() - t0:.1f} s; max radius "
          f"at the rub {first.max_radius(nodes // 3 + 1)[0]:.3g} m")
    from rotorkit.periodic.condensed import CondensedHarmonicBalance
    from rotorkit.periodic.hb import newton

    hb = CondensedHarmonicBalance(system, speed_parameter="R_speed", harmonics=3)
    start = first.coefficients[0][:, hb.kept].ravel()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        frame = hb.frame({"R_speed": speed * 1.01})
        # lazily, as the library's solves at a fixed parameter (periodic_solution, ContinuationProblem.solve):
        # no Jacobian at the converged point
        newton(lambda z, j: hb.residual(z, frame, j), start, tol=1e-10, scale=frame.scale, lazy_jacobian=True)
        times.append(time.perf_counter() - t0)
    print(f"    one condensed HB solution (H = 3, N = {hb.samples}, {hb.size} unknowns, from the solution at "
          f"{speed:g} rad/s, the frame at the new speed included): {1e3 * statistics.median(times):.1f} ms "
          "(target <= 20 ms)")
    branch_times, branch = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        branch = periodic_response(system, speeds=(0.5 * speed, 1.5 * speed), harmonics=3, condense=True,
                                   stability="none", step=0.03, max_step=0.03)
        branch_times.append(time.perf_counter() - t0)
    elapsed = statistics.median(branch_times)
    print(f"    branch of {len(branch)} points {0.5 * speed:g}..{1.5 * speed:g} rad/s (error estimates included): "
          f"{elapsed:.2f} s, {1e3 * elapsed / len(branch):.1f} ms/point, median of {repeat} ({branch.reason}); "
          f"load {load():.1f}")
    hundred = []
    for _ in range(repeat):  # the target's branch: 100 points from the low end of the same range
        t0 = time.perf_counter()
        branch = periodic_response(system, speeds=(0.5 * speed, 1.5 * speed), harmonics=3, condense=True,
                                   stability="none", step=0.03, max_step=0.03, max_points=100)
        hundred.append(time.perf_counter() - t0)
    print(f"    branch of {len(branch)} points {branch.parameter[0]:g}..{branch.parameter[-1]:.4g} rad/s: "
          f"{statistics.median(hundred):.2f} s, median of {repeat} (target <= 5 s; {branch.reason}); load {load():.1f}")


def chain_rotor(n_stations, clearance=3e-7):
    """A chain of disks on springs (2 coordinates per station), a rub at the middle one, unbalance at the ends."""
    from rotorkit import Disk, ElasticSupport, Model, Rotor, RubStator
    from rotorkit.elements import LinearBearing

    stations = tuple(range(1, n_stations + 1))
    elements = [Rotor(name="R", stations=stations, speed=300.0)]
    for s in stations:
        elements.append(Disk(station=s, mass=1.0, radius=0.05, eccentricity=1e-5 if s in (1, n_stations) else 0.0,
                             torsion=False))
        elements.append(ElasticSupport(station=s, stiffness=1e6, damping=50.0))
    for a, b in zip(stations, stations[1:]):
        elements.append(LinearBearing(station=a, other_station=b, kxx=2e6, kyy=2e6, cxx=10.0, cyy=10.0))
    elements.append(RubStator(station=stations[n_stations // 2], clearance=clearance, contact_stiffness=1e6,
                              friction_coefficient=0.1))
    return Model(elements, name=f"chain{n_stations}")


def section_c(repeat, coordinates, harmonics):
    from rotorkit.periodic.hb import HarmonicBalance, newton
    from rotorkit.periodic.stability import hill_multipliers, monodromy_multipliers

    system = chain_rotor(coordinates // 2).compile()
    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=harmonics)
    frame = hb.frame()
    hb.residual(np.zeros(hb.size), frame)  # warm: the Jacobian's first compilation is not timed
    t0 = time.perf_counter()
    z = newton(lambda z, j: hb.residual(z, frame, j), np.zeros(hb.size), tol=1e-10, scale=frame.scale)[0]
    solve = time.perf_counter() - t0
    hill, mono = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        mh = hill_multipliers(hb, z, frame)
        hill.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        mm = monodromy_multipliers(hb, z, frame)[0]
        mono.append(time.perf_counter() - t0)
    gap = np.max(np.min(np.abs(mh[:, None] - mm[None, :]), axis=1))
    print(f"(c) {hb.n} coordinates, H = {harmonics}, N = {hb.samples}: one HB solution {solve:.3f} s; "
          f"Floquet multipliers by Hill {statistics.median(hill):.3f} s, by the monodromy matrix "
          f"{statistics.median(mono):.3f} s (target <= 0.5 s); largest |mu| {np.max(np.abs(mm)):.6f}, "
          f"Hill-monodromy gap {gap:.1e}; load {load():.1f}")


def section_figure(out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotorkit.analysis.periodic import periodic_response

    system = jeffcott_rub().compile(backend="c")
    branch = periodic_response(system, speeds=SPEEDS, harmonics=3)
    speeds = np.arange(80.0, 160.1, 4.0)
    up, y = [], None
    for w in speeds:
        r, y = settled_radius(system, w, y0=y)
        up.append(r)
    down = []
    for w in speeds[::-1]:
        r, y = settled_radius(system, w, y0=y)
        down.append(r)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    branch.plot_response(1, ax=ax, label="harmonic balance (dashed: unstable)")
    ax.plot(speeds, 1e3 * np.array(up), "^", color="C1", label="time, run-up")
    ax.plot(speeds[::-1], 1e3 * np.array(down), "v", color="C2", mfc="none", label="time, run-down")
    ax.axhline(1e3 * DELTA, color="0.6", lw=0.8)
    ax.legend()
    ax.set_xlim(60, 200)
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "jeffcott_rub_branch.png", dpi=110)
    print(f"figure: {out / 'jeffcott_rub_branch.png'}; folds "
          f"{', '.join(f'{b.kind} {b.parameter:.2f}' for b in branch.bifurcations)}")


def _marked_runs(system, speeds, periods):
    """Settled max radii (m) of a run-up and a run-down over ``speeds`` (each from the previous final state)."""
    up, y = [], None
    for w in speeds:
        r, y = settled_radius(system, w, y0=y, periods=periods)
        up.append(r)
    down = []
    for w in speeds[::-1]:
        r, y = settled_radius(system, w, y0=y, periods=periods)
        down.append(r)
    return np.array(up), np.array(down[::-1])


def section_sfd(out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import rotorkit as rk
    from rotorkit.analysis.periodic import periodic_response

    c, critical = 2e-4, np.sqrt(1e5)
    film = rk.SqueezeFilmDamper(station=1, centring_stiffness=1e6, radius=0.05, length=0.015, clearance=c,
                                viscosity=0.004)
    system = rk.Model([rk.Rotor(name="R", stations=(1,), speed=critical),
                       rk.Disk(station=1, mass=10.0, radius=0.1, eccentricity=0.15 * c, torsion=False), film],
                      name="sfd_jeffcott").compile(backend="c")
    branch = periodic_response(system, speeds=(0.9 * critical, 1.5 * critical), harmonics=3)
    speeds = critical * np.arange(1.0, 1.401, 0.025)
    up, down = _marked_runs(system, speeds, 500)
    fig, ax = plt.subplots(figsize=(9, 4.5))
    branch.plot_response(1, ax=ax, label="harmonic balance (dashed: unstable)")
    ax.plot(speeds, 1e3 * up, "^", color="C1", label="time, run-up")
    ax.plot(speeds, 1e3 * down, "v", color="C2", mfc="none", label="time, run-down")
    ax.axhline(1e3 * c, color="0.6", lw=0.8)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)  # beside the data
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "sfd_bistable_branch.png", dpi=110)
    print(f"figure: {out / 'sfd_bistable_branch.png'}; "
          f"{', '.join(f'{b.kind} {b.parameter:.2f}' for b in branch.bifurcations)}")


def section_doubling(out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import rotorkit as rk
    from rotorkit.analysis.periodic import period_doubled_branch, periodic_response
    from rotorkit.elements import LinearBearing

    system = rk.Model([rk.Rotor(name="R", stations=(1,), speed=2990.0),
                       rk.Disk(station=1, mass=2.0, radius=0.1, eccentricity=2e-5, torsion=False),
                       LinearBearing(station=1, kxx=1.2e6, kyy=1.0e6, cxx=40.0, cyy=40.0),
                       rk.RubStator(station=1, clearance=1e-5, contact_stiffness=4e6, friction_coefficient=0.0),
                       rk.Maneuver.steady(gravity=9.81)], name="pdrub").compile(backend="c")
    branch = periodic_response(system, speeds=(2990.0, 2900.0), harmonics=10, max_step=0.02)
    doubled = period_doubled_branch(system, branch, stop=2915.0)
    speeds = np.arange(2990.0, 2914.9, -2.5)  # a run-down from the synchronous orbit at 2990 rad/s
    down, y = [], None
    for w in speeds:
        r, y = settled_radius(system, w, y0=y, periods=3000)
        down.append(r)
    down = np.array(down)
    fig, ax = plt.subplots(figsize=(9, 4.5))
    branch.plot_response(1, ax=ax, label="synchronous (nu = 1)")
    doubled.plot_response(1, ax=ax, color="C3", label="period doubled (nu = 2)")
    ax.plot(speeds, 1e3 * down, "v", color="C2", mfc="none", label="time, run-down")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)  # beside the data
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "period_doubling_branch.png", dpi=110)
    print(f"figure: {out / 'period_doubling_branch.png'}; "
          f"{', '.join(f'{b.kind} {b.parameter:.2f}' for b in branch.bifurcations)}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sections", nargs="+", default=["a", "b", "c"],
                        choices=("a", "b", "c", "figure", "sfd", "doubling"))
    parser.add_argument("--nodes", type=int, default=25, help="beam nodes of the section b rotor (4 coordinates each)")
    parser.add_argument("--repeat", type=int, default=3, help="repetitions per timing (median; default 3)")
    parser.add_argument("--runs", type=int, default=10, help="time-integrated speeds timed in section a")
    parser.add_argument("--branch-steps", type=float, nargs=2, metavar=("STEP", "MAX_STEP"),
                        default=(BRANCH_STEPS["step"], BRANCH_STEPS["max_step"]),
                        help="section a's arclength steps (default 0.02 0.05: about 200 points; 0.012 0.03 gives "
                             "the 314-point branch of the earlier figures in docs/periodic.md)")
    parser.add_argument("--coordinates", type=int, default=100, help="size of the section c rotor")
    parser.add_argument("--harmonics", type=int, default=3, help="H of the section c solution")
    parser.add_argument("--out", default=str(ROOT / "docs" / "figures" / "periodic"))
    parser.add_argument("--blas-threads", default="1", help="BLAS threads (set before numpy loads; default 1)")
    args = parser.parse_args()
    print(f"load average {load():.1f} on {os.cpu_count()} cores; BLAS threads {BLAS_THREADS}")
    if "a" in args.sections:
        section_a(args.repeat, args.runs, tuple(args.branch_steps))
    if "b" in args.sections:
        sys.path.insert(0, str(ROOT / "bench"))
        section_b(args.repeat, args.nodes)
    if "c" in args.sections:
        section_c(args.repeat, args.coordinates, args.harmonics)
    if "figure" in args.sections:
        section_figure(Path(args.out))
    if "sfd" in args.sections:
        section_sfd(Path(args.out))
    if "doubling" in args.sections:
        section_doubling(Path(args.out))


if __name__ == "__main__":
    main()
