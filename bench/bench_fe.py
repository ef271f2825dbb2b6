"""Beam finite-element rotors: the full model against hand-written compiled code, cold derive + compile, codegen paths.

    PYTHONPATH=. python bench/bench_fe.py                      # all sections, 25-node rotor, median of 3
    PYTHONPATH=. python bench/bench_fe.py --nodes 25 --repeat 5 --sections run
    PYTHONPATH=. python bench/bench_fe.py --sections cold --cold-nodes 25 100
    PYTHONPATH=. python bench/bench_fe.py --sections codegen --codegen-nodes 4 6 8 10 13
    PYTHONPATH=. python bench/bench_fe.py --sections reduced --modes 20          # (b); --modes 4 8 20 32
    PYTHONPATH=. python bench/bench_fe.py --sections solve --solve-nodes 10 25 50 100

The rotor (issue 14, benchmark 5): a uniform 50 mm steel shaft of 1.5 m in
``nodes - 1`` Timoshenko elements (4 coordinates per node), two disks with
unbalance at a third and two thirds of the length, two damped bearings at the
ends, a rub stator around the first disk, spinning at 300 rad/s.

Sections (each prints ratios measured in this run, and the load average):

``run``     1 s at rtol 1e-6, atol 1e-9 from rest. (a) the generated
            right-hand side and a hand-written compiled one (the same M, K,
            C + gyroscopic matrices evaluated numerically, M^-1 precomputed,
            dense loops; unbalance and contact law written by hand) each in
            the same compiled Dormand-Prince loop (``integrate``), medians;
            also the whole ``simulate()`` call. The hand-written right-hand
            side is checked against rotorkit's before timing.
``cold``    (c) derive + generate + numba compile of a rotor in a fresh
            process with empty caches, per size (wall and the process's
            CPU time: on a loaded machine the CPU time is the better guide).
``reduced`` (b) the full model against its Craig-Bampton reduction (``rotorkit.reduce``,
            ``--modes`` interior modes plus the physical coordinates of the
            rub and unbalance stations), each 1 s at rtol 1e-6 in the same
            compiled loop, medians: the speed ratio, and the spectral error
            of the rub station's response (defined in ``spectral_error``).
``codegen`` unrolled (numba, and C with the c back end) against structured
            (numba) code generation by size: generate + compile time and one
            right-hand side inside the loop; the ``auto`` threshold
            (``rotorkit.codegen.STRUCTURED_FROM``) comes from this
            table.
``solve``   the structured code's two ways of applying ``M0^-1`` in the
            right-hand side (dense product, band solve) by size; the
            ``auto`` rule (``rotorkit.codegen.structured.band_pays``) comes
            from this table.

Times are wall-clock on a shared machine: quote the command, the load
average printed, and compare ratios measured in one run.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SPEED = 300.0
CLEARANCE = 1.0e-5


def fe_rotor(nodes, rub=True, name=None):
    """The benchmark rotor: ``nodes`` beam nodes (4 coordinates each)."""
    from rotorkit import ElasticSupport, Model, Rotor, RubStator
    from rotorkit.elements import BeamSegment, Disk, Material

    steel = Material.steel()
    stations = tuple(range(1, nodes + 1))
    length = 1.5 / (nodes - 1)
    elements = [Rotor(name="R", stations=stations, speed=SPEED)]
    elements += [BeamSegment(start=s, end=s + 1, length=length, outer_diameter=0.05, material=steel)
                 for s in stations[:-1]]
    disks = (stations[nodes // 3], stations[2 * nodes // 3])
    for s, phase in zip(disks, (0.0, 1.0)):
        elements.append(Disk.from_geometry(station=s, width=0.07, inner_diameter=0.05, outer_diameter=0.28,
                                           material=steel, eccentricity=2e-4, phase=phase))
    elements += [ElasticSupport(station=s, stiffness=1e6, damping=200.0) for s in (stations[0], stations[-1])]
    if rub:
        elements.append(RubStator(station=disks[0], clearance=CLEARANCE, contact_stiffness=2e6,
                                  friction_coefficient=0.1))
    return Model(elements, name=name or f"fe{nodes}")


def load():
    return os.getloadavg()[0]


def median_time(fn, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), max(times), out


# ---------------------------------------------------------------- hand-written reference
def handwritten(model):
    """(core, p, check) of the hand-written compiled right-hand side of ``model`` (its own matrices)."""
    import numba
    import sympy as sp

    eom = model.equations()
    n = eom.n
    values = {sp.Symbol(k, real=True): v for k, v in model.parameters.items()}
    num = lambda e: float(sp.sympify(e).xreplace(values))  # noqa: E731
    M, K, C = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    for A, mat in ((M, eom.mass_matrix), (K, eom.stiffness), (C, eom.damping)):
        for (i, j), v in mat.todok().items():
            A[i, j] = num(v)
    # gyroscopic (and any other linear velocity/displacement) terms of every force but the rub's
    u_index = {u: k for k, u in enumerate(eom.speeds)}
    q_index = {q: k for k, q in enumerate(eom.coordinates)}
    for label, vec in eom.forces.items():
        if label.startswith("rub"):
            continue
        for (i, _), v in vec.todok().items():
            for s in v.free_symbols:
                if s in u_index:
                    C[i, u_index[s]] -= num(sp.diff(v, s))
                elif s in q_index:
                    K[i, q_index[s]] -= num(sp.diff(v, s))
    minv = np.linalg.inv(M)
    names = model.coordinate_names
    p = model.parameters
    disks = [e for e in model.elements if type(e).__name__ == "Disk"]
    unb = np.array([[names.index(f"x{d.station}"), names.index(f"y{d.station}"),
                     p[f"{d.label()}_mass"] * p[f"{d.label()}_eccentricity"], p[f"{d.label()}_phase"]]
                    for d in disks])
    rub = next(e for e in model.elements if type(e).__name__ == "RubStator")
    ix, iy = names.index(f"x{rub.station}"), names.index(f"y{rub.station}")
    kr, delta, mu = (p[f"{rub.label()}_{f}"] for f in ("contact_stiffness", "clearance", "friction_coefficient"))
    omega = p["R_speed"]
    packed = np.concatenate([minv.ravel(), K.ravel(), C.ravel(), unb.ravel()])
    n_unb = len(disks)

    @numba.njit(cache=False)
    def core(t, y, p, dydt):
        nn = n * n
        minv_, k_, c_ = p[:nn].reshape((n, n)), p[nn:2 * nn].reshape((n, n)), p[2 * nn:3 * nn].reshape((n, n))
        f = -(np.dot(k_, y[:n]) + np.dot(c_, y[n:]))  # BLAS matrix-vector products
        for d in range(n_unb):
            base = 3 * nn + 4 * d
            a = p[base + 2] * omega * omega
            ph = omega * t + p[base + 3]
            f[int(p[base])] += a * np.cos(ph)
            f[int(p[base + 1])] += a * np.sin(ph)
        x, yy = y[ix], y[iy]
        r = np.sqrt(x * x + yy * yy)
        if r > delta:
            g = kr * (r - delta) / r
            f[ix] -= g * (x - mu * yy)
            f[iy] -= g * (mu * x + yy)
        dydt[:n] = y[n:]
        dydt[n:] = np.dot(minv_, f)

    return core, packed


def section_run(args):
    import rotorkit as rk
    from rotorkit.engines.rk_numba import integrate

    model = fe_rotor(args.nodes)
    system = model.compile(backend="numba")
    n = len(model.coordinate_names)
    core, packed = handwritten(model)
    rng = np.random.default_rng(0)
    for _ in range(5):  # same equations: the hand-written right-hand side against rotorkit's
        y = rng.normal(size=2 * n) * np.r_[np.full(n, 3e-5), np.full(n, 1e-2)]
        t = float(rng.uniform(0, 1))
        ref = system.rhs(t, y)
        hw = np.empty(2 * n)
        core(t, y, packed, hw)
        err = np.abs(hw - ref).max() / np.abs(ref).max()
        assert err < 1e-9, f"hand-written right-hand side differs from rotorkit's by {err:.2e}"
    t_eval = np.linspace(0.0, 1.0, 10_001)
    y0 = np.zeros(2 * n)
    p_gen = system.within(0.0, 1.0).prepared_parameters

    def run(c, p):
        sol = integrate(c, 0.0, 1.0, y0, p, t_eval, rtol=1e-6, atol=1e-9)
        assert sol.success, sol.message
        return sol

    run(system.core, p_gen), run(core, packed)  # compile the loop for both
    rows = {}
    for label, fn in (("generated", lambda: run(system.core, p_gen)), ("hand-written", lambda: run(core, packed)),
                      ("simulate()", lambda: rk.simulate(system, (0.0, 1.0), rtol=1e-6, atol=1e-9))):
        rows[label] = median_time(fn, args.repeat)
    gen, hand = rows["generated"][3], rows["hand-written"][3]
    diff = np.abs(gen.y - hand.y).max() / np.abs(hand.y).max()
    radius = np.hypot(hand.y[model.coordinate_names.index(f"x{model.elements[-1].station}")],
                      hand.y[model.coordinate_names.index(f"y{model.elements[-1].station}")])
    contact = radius > CLEARANCE
    print(f"\n(a) {args.nodes}-node rotor ({n} coordinates, {system._module.CODEGEN} code), 1 s, rtol 1e-6, "
          f"median of {args.repeat} (load {load():.1f}); in contact {contact.mean():.0%} of the samples, "
          f"largest radius {radius.max() / CLEARANCE:.1f} x the clearance")
    for label, (med, lo, hi, sol) in rows.items():
        nfev = sol.nfev if hasattr(sol, "nfev") else sol.stats["nfev"]
        print(f"   {label:13s} {med:7.3f} s  (min {lo:.3f}, max {hi:.3f})  {nfev:9d} evaluations  "
              f"{med / nfev * 1e6:6.2f} us per evaluation+step")
    print(f"   ratio generated / hand-written: {rows['generated'][0] / rows['hand-written'][0]:.2f} (target <= 1.5); "
          f"simulate() / hand-written: {rows['simulate()'][0] / rows['hand-written'][0]:.2f}; "
          f"largest state difference {diff:.1e} of the largest state")


# ---------------------------------------------------------------- (b) reduced model
BAND = (0.0, 3000.0)  # rad/s: 10 x the running speed
STEADY = 0.5  # s: the spectra use t >= STEADY


def spectral_error(t, x_ref, x, band=BAND, start=STEADY):
    """Spectral error of a signal ``x`` against ``x_ref`` (same samples ``t``).

    ``max_w |A(w) - A_ref(w)| / max_w A_ref(w)`` over ``w`` in ``band``
    (rad/s), ``A`` the Hann-windowed amplitude spectrum of the samples with
    ``t >= start`` (the steady part): the largest difference of the amplitude
    spectra in the band of interest relative to the reference's peak there.
    """
    from rotorkit.analysis import amplitude_spectrum

    keep = t >= start
    ref = amplitude_spectrum(t[keep], x_ref[keep])
    got = amplitude_spectrum(t[keep], x[keep])
    inside = (ref.frequency >= band[0]) & (ref.frequency <= band[1])
    return float(np.abs(got.amplitude[inside] - ref.amplitude[inside]).max() / ref.amplitude[inside].max())


def section_reduced(args):
    import rotorkit as rk
    from rotorkit.engines.rk_numba import integrate

    model = fe_rotor(args.nodes)
    system = model.compile(backend="numba", codegen="structured")
    n = len(model.coordinate_names)
    t_eval = np.linspace(0.0, 1.0, 10_001)

    def run(sys_):
        p = sys_.within(0.0, 1.0).prepared_parameters
        y0 = np.zeros(sys_.n_states)
        sol = integrate(sys_.core, 0.0, 1.0, y0, p, t_eval, rtol=1e-6, atol=1e-9)
        assert sol.success, sol.message
        return sol

    rub = next(e for e in model.elements if type(e).__name__ == "RubStator").station
    ix = model.coordinate_names.index(f"x{rub}")
    run(system)  # compile the loop
    full = median_time(lambda: run(system), args.repeat)
    x_full = full[3].y[ix]
    print(f"\n(b) {args.nodes}-node rotor ({n} coordinates) against rk.reduce(system, modes=m), 1 s, rtol 1e-6, "
          f"median of {args.repeat} (reduced: of {max(args.repeat, 7)}; load {load():.1f}); largest |x{rub}| {np.abs(x_full).max():.3g} m")
    print(f"   full model: {full[0]:.3f} s (min {full[1]:.3f}, max {full[2]:.3f}), {full[3].nfev} evaluations, "
          f"{full[0] / full[3].nfev * 1e6:.2f} us per evaluation+step")
    print(f"   spectral error: x{rub} (rub station), t >= {STEADY:g} s, band {BAND[0]:g}-{BAND[1]:g} rad/s, relative "
          "to the peak (target <= 1e-3); speed ratio full / reduced (target >= 20 at 20 modes)")
    print(f"   {'modes':>5s} {'coords':>6s} {'reduce ms':>9s} {'run s':>7s} {'evaluations':>11s} {'ratio':>6s} "
          f"{'spectral err':>12s} {'FRF estimate':>12s} {'1st dropped rad/s':>17s}")
    for modes in args.modes:
        t0 = time.perf_counter()
        reduced = rk.reduce(system, modes=modes)
        t_reduce = time.perf_counter() - t0
        run(reduced)
        med, _, _, sol = median_time(lambda r=reduced: run(r), max(args.repeat, 7))  # short runs: more repeats
        x_red = (reduced.basis @ sol.y[: reduced.basis.shape[1]])[ix]
        err = spectral_error(t_eval, x_full, x_red)
        estimate = reduced.error_estimate(band=BAND)
        print(f"   {modes:5d} {reduced.n_states // 2:6d} {t_reduce * 1e3:9.1f} {med:7.3f} {sol.nfev:11d} "
              f"{full[0] / med:6.1f} {err:12.2e} {estimate.frf_error:12.2e} {estimate.first_dropped_frequency:17.0f}",
              flush=True)
    print(f"   boundary (physical): {', '.join(reduced.boundary)}; reduce: first call loads or compiles the "
          "reduced code, later calls build the basis only")


# ---------------------------------------------------------------- cold start
COLD = """
import os, sys, time
sys.path.insert(0, {bench!r})
t0, c0 = time.perf_counter(), time.process_time()
from bench_fe import fe_rotor
model = fe_rotor({nodes})
model.equations()
t1, c1 = time.perf_counter(), time.process_time()
model.compile(backend="numba")
t2, c2 = time.perf_counter(), time.process_time()
print(t1 - t0, t2 - t1, c1 - c0, c2 - c1)
"""


def section_cold(args):
    print(f"\n(c) cold derive + compile in a fresh process, empty rotorkit and numba caches (load {load():.1f})")
    print(f"   {'nodes':>5s} {'coords':>6s} {'derive s':>9s} {'generate+compile s':>19s} {'total s':>8s} "
          f"{'total CPU s':>11s}  target")
    for nodes in args.cold_nodes:
        env = dict(os.environ, ROTORKIT_CACHE_DIR=tempfile.mkdtemp(prefix="rk-bench-fe-"), ROTORKIT_QUIET="1",
                   PYTHONPATH=str(ROOT))
        out = subprocess.run([sys.executable, "-c", COLD.format(bench=str(ROOT / "bench"), nodes=nodes)], env=env,
                             capture_output=True, text=True, check=True).stdout.split()
        derive, comp, cpu = float(out[-4]), float(out[-3]), float(out[-2]) + float(out[-1])
        target = {25: "< 15 s", 100: "< 60 s"}.get(nodes, "")
        print(f"   {nodes:5d} {4 * nodes:6d} {derive:9.2f} {comp:19.2f} {derive + comp:8.2f} {cpu:11.2f}  {target}",
              flush=True)


# ---------------------------------------------------------------- codegen paths
def section_codegen(args):
    from rotorkit import available_backends
    from rotorkit.engines import rk_c, rk_numba

    cases = [("numba", "unrolled"), ("numba", "structured")]
    if "c" in available_backends():
        cases.append(("c", "unrolled"))
    print(f"\ncodegen paths by size (fresh cache; load {load():.1f}): generate + compile, and the cost of one "
          "right-hand side in the compiled loop (rotor without rub, 0.05 s)")
    labels = [f"{mode[:5]}/{backend}" for backend, mode in cases]
    print(f"   {'nodes':>5s} {'coords':>6s} " + " ".join(f"{label + ' s':>15s}" for label in labels) + " "
          + " ".join(f"{label + ' us':>16s}" for label in labels))
    os.environ["ROTORKIT_CACHE_DIR"] = tempfile.mkdtemp(prefix="rk-bench-fe-")
    for nodes in args.codegen_nodes:
        model = fe_rotor(nodes, rub=False, name=f"cg{nodes}")
        model.equations()
        row = []
        for backend, mode in cases:
            t0 = time.perf_counter()
            system = model.compile(backend=backend, codegen=mode)
            row.append(time.perf_counter() - t0)
        for backend, mode in cases:
            system = model.compile(backend=backend, codegen=mode)
            integrate, core = ((rk_c.integrate, system.core.address) if backend == "c"
                               else (rk_numba.integrate, system.core))
            y0 = np.zeros(system.n_states)
            p = system.within(0.0, 0.05).prepared_parameters
            integrate(core, 0.0, 0.01, y0, p, np.array([0.01]))
            med, _, _, sol = median_time(lambda: integrate(core, 0.0, 0.05, y0, p, np.array([0.05])), args.repeat)
            row.append(med / sol.nfev * 1e6)
        k = len(cases)
        print(f"   {nodes:5d} {4 * nodes:6d} " + " ".join(f"{v:15.2f}" for v in row[:k]) + " "
              + " ".join(f"{v:16.2f}" for v in row[k:]), flush=True)


# ---------------------------------------------------------------- M0^-1: dense product or band solve
def section_solve(args):
    from rotorkit.codegen import cache
    from rotorkit.codegen.structured import band_pays, generate_structured, mass_band, split_equations
    from rotorkit.engines.rk_numba import CORE_SIGNATURE, integrate
    from rotorkit.system import System

    print(f"\nM0^-1 in the structured right-hand side: dense product against band solve (load {load():.1f}); one "
          "evaluation inside the compiled loop, rotor with rub, 0.02 s from an offset start, median of "
          f"{args.repeat}")
    print(f"   {'nodes':>5s} {'coords':>6s} {'bandwidth':>9s} {'dense us':>9s} {'band us':>8s} {'band/dense':>10s}  auto")
    os.environ.setdefault("ROTORKIT_CACHE_DIR", tempfile.mkdtemp(prefix="rk-bench-fe-"))
    for nodes in args.solve_nodes:
        model = fe_rotor(nodes, name=f"solve{nodes}")
        eom = model.equations()
        _, width = mass_band(split_equations(eom))
        systems = []
        for solve in ("dense", "band"):
            key = f"{model.structure_key}_bench_{solve}"
            module = cache.store(key, generate_structured(eom, key, solve=solve).source)
            core = cache.jit(module, "rhs", error_model="numpy")
            core.compile(CORE_SIGNATURE.args)
            systems.append(System(model, module, "numba", core))
        y0 = systems[0].initial_state(**{f"x{model.elements[-1].station}": 2 * CLEARANCE})
        a, b = (s.rhs(0.01, y0) for s in systems)
        assert np.abs(a - b).max() <= 1e-12 * np.abs(a).max(), "band and dense right-hand sides differ"
        row = []
        for system in systems:
            p = system.within(0.0, 0.02).prepared_parameters
            integrate(system.core, 0.0, 0.002, y0, p, np.array([0.002]))
            med, _, _, sol = median_time(lambda: integrate(system.core, 0.0, 0.02, y0, p, np.array([0.02])),
                                         args.repeat)
            row.append(med / sol.nfev * 1e6)
        n = len(model.coordinate_names)
        auto = "band" if band_pays(n, width) else "dense"
        print(f"   {nodes:5d} {n:6d} {width:9d} {row[0]:9.2f} {row[1]:8.2f} {row[1] / row[0]:10.2f}  {auto}",
              flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, default=25, help="rotor size of the run section (default 25)")
    parser.add_argument("--repeat", type=int, default=3, help="repetitions per timing (median; default 3)")
    parser.add_argument("--sections", nargs="+", default=["run", "cold"],
                        choices=["run", "cold", "codegen", "reduced", "solve"])
    parser.add_argument("--modes", type=int, nargs="+", default=[20],
                        help="interior modes of the reduced section (default 20)")
    parser.add_argument("--cold-nodes", type=int, nargs="+", default=[25, 100])
    parser.add_argument("--codegen-nodes", type=int, nargs="+", default=[4, 6, 8, 10, 13])
    parser.add_argument("--solve-nodes", type=int, nargs="+", default=[10, 25, 50, 100])
    args = parser.parse_args(argv)
    os.environ.setdefault("ROTORKIT_CACHE_DIR", tempfile.mkdtemp(prefix="rk-bench-fe-"))
    print(f"bench_fe: {os.uname().nodename}, {os.cpu_count()} cores, load average {os.getloadavg()}")
    for section in args.sections:
        {"run": section_run, "cold": section_cold, "codegen": section_codegen,
         "reduced": section_reduced, "solve": section_solve}[section](args)


if __name__ == "__main__":
    main()
