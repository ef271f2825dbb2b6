"""``rotorkit unbalance``: steady unbalance response (Bode, polar, orbit ellipse) over a speed range."""

import math

from ..errors import ParameterError
from .common import save_figure
from .linear_common import add_linear_arguments, linear_scene, output_folder, parse_speeds


def register(sub):
    p = sub.add_parser("unbalance", help="steady unbalance response over speed: Bode, polar and CSV")
    add_linear_arguments(p, speeds=True)
    p.add_argument("--unbalance", action="append", default=[], metavar="STATION:KG_M[:DEG]",
                   help="an unbalance at a station, kg m unless a unit is given, and its angle, degrees unless "
                        "a unit is given, e.g. 2:1e-5:90 or '2:100 g*mm:1.2 rad'; repeat for several "
                        "(default: each disk's mass x eccentricity at its phase)")
    p.add_argument("--station", action="append", default=[], help="station whose response is written (default all)")
    p.set_defaults(func=main)


def _parse(text):
    from ..errors import UnitError
    from ..units import parse_quantity, to_si

    parts = text.split(":")
    hint = "expected STATION:KG_M[:DEG] (a unit may be given: '2:100 g*mm:90' or '2:1e-5:1.2 rad')"
    if len(parts) not in (2, 3) or not parts[0].strip():
        raise ParameterError(f"--unbalance {text!r}: {hint}")
    try:
        magnitude = to_si(parts[1].strip(), "kg*m", f"--unbalance {text!r}: magnitude")
        angle = 0.0
        if len(parts) > 2:
            value = parse_quantity(parts[2].strip(), f"--unbalance {text!r}: angle")
            angle = math.radians(value) if isinstance(value, float) else to_si(parts[2].strip(), "rad",
                                                                               f"--unbalance {text!r}: angle")
    except UnitError:
        raise
    except ValueError:
        raise ParameterError(f"--unbalance {text!r}: {hint}") from None
    return parts[0].strip(), magnitude, angle


def _disk_unbalances(system):
    from ..elements import Disk

    values = system.parameters
    out = []
    for e in getattr(system, "model", system).elements:
        if isinstance(e, Disk):
            label = e.label()
            u = values[f"{label}_mass"] * values[f"{label}_eccentricity"]
            if u > 0:
                out.append((str(e.station), u, values[f"{label}_phase"]))
    return out


def main(args):
    from ..linear.linear_model import linear_model
    from ..linear.unbalance import unbalance_response

    items = [_parse(u) for u in args.unbalance]  # the options are checked before deriving
    given = parse_speeds(args.speeds, None) if args.speeds is not None else None
    system, parameter = linear_scene(args)  # a linear model is not compiled
    items = items or _disk_unbalances(system)
    if not items:
        raise ParameterError("no unbalance: the scene's disks have zero eccentricity; give --unbalance STATION:KG_M")
    speeds = given if given is not None else parse_speeds(None, system.parameters[parameter])
    model = linear_model(system, speed_parameter=parameter)
    response = unbalance_response(model, items, speeds)
    out = output_folder(args, "unbalance")
    from ..units import display_factor

    factor = display_factor(args.units)
    stations = args.station or list(model.stations)
    print(f"unbalance response ({response.method} solve), {len(speeds)} speeds; peaks per station:")
    print(f"{'rotor':>6}  {'station':>7}  {'peak major semi-axis (um)':>26}  {f'at {parameter} ({args.units})':>26}  whirl")
    for rotor in response.components:
        for s in stations:
            o = response.orbit(s, rotor)
            i = int(o.major.argmax())
            print(f"{rotor:>6}  {s:>7}  {o.major[i] * 1e6:>26.5g}  {speeds[i] * factor:>26.6g}  {o.direction[i]}")
            response.to_csv(out / f"unbalance_{rotor}_{s}.csv", rotor, station=s)
            top, _ = response.plot_bode(f"x{s}", rotor=rotor, units=args.units)
            save_figure(top.figure, out / f"bode_{rotor}_x{s}.png")
            save_figure(response.plot_polar(f"x{s}", rotor=rotor, units=args.units).figure,
                        out / f"polar_{rotor}_x{s}.png")
    print(f"wrote CSV, Bode and polar figures to {out}")
    return 0
