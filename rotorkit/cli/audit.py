"""``rotorkit audit``: the API 617 lateral checks of a scene and their self-contained HTML report."""

from .common import add_scene_arguments

HINT = "expected MIN:MAX, rad/s unless a unit is given, e.g. '8000:10500 rpm' or '840:1100'"


def register(sub):
    p = sub.add_parser("audit", help="API 617 checks (critical map, unbalance response, Level I stability, "
                                     "shear and moment) and an HTML report")
    add_scene_arguments(p)
    p.add_argument("--operating", required=True, metavar="MIN:MAX",
                   help="operating range: minimum operating and maximum continuous speed, " + HINT)
    p.add_argument("--out", help="output folder (default rotorkit-out/<scene>): report.html and CSV files")
    p.add_argument("--trip", help="trip speed (default 105 %% of the maximum continuous speed), e.g. '11000 rpm'")
    p.add_argument("--qa", help="anticipated cross-coupling Q_A, N/m unless a unit is given (or give --power ...)")
    p.add_argument("--power", help="Wachel Q_A: rated power per impeller, comma-separated, e.g. '1.5 MW,1.5 MW'")
    p.add_argument("--impeller-diameter", help="Wachel Q_A: impeller diameters, comma-separated (m or with unit)")
    p.add_argument("--restrictive-width", help="Wachel Q_A: smaller of diffuser and impeller discharge width, "
                                               "comma-separated (m or with unit)")
    p.add_argument("--density-ratio", default="1", help="Wachel Q_A: discharge / suction gas density per impeller, "
                                                       "comma-separated (default 1)")
    p.add_argument("--stage-factor", default="3", help="Wachel B_c: 3 centrifugal (default), 1.5 axial")
    p.add_argument("--unbalance-multiple", type=float, default=None,
                   help="multiple of the residual unbalance U_r = 6350 W/N g mm applied (default 2, as API 617 asks)")
    p.add_argument("--probes", help="vibration probe stations, comma-separated (default: the bearing stations)")
    p.add_argument("--clearance", action="append", default=[], metavar="STATION=CLEARANCE",
                   help="a close clearance (seal): station and minimum diametral running clearance, m unless a unit "
                        "is given, e.g. '6=0.4 mm'; repeat for each")
    p.add_argument("--stations", help="stations of the applied cross-coupling, comma-separated (default mid-span)")
    p.add_argument("--speed-parameter", help="rotor speed swept, e.g. R_speed (default: the first rotor's)")
    p.set_defaults(func=main)


def parse_operating(text):
    """``"MIN:MAX"`` -> ``(min, max)`` in rad/s; a unit on either bound applies to both."""
    from ..errors import ParameterError
    from .linear_common import speed_bounds

    parts = str(text).split(":")
    if len(parts) != 2:
        raise ParameterError(f"--operating {text!r}: {HINT}")
    low, high = speed_bounds(parts, "--operating", text, HINT, "the two bounds")
    if not 0 < low <= high:
        raise ParameterError(f"--operating {text!r}: expected 0 < MIN <= MAX")
    return low, high


def _list(text):
    return [v.strip() for v in str(text).split(",") if v.strip()]


def _number_or_text(text):
    try:
        return float(text)
    except ValueError:
        return text


def parse_clearances(items):
    """``["6=0.4 mm", ...]`` -> ``{"6": "0.4 mm", ...}`` (values as numbers where they are numbers)."""
    from ..errors import ParameterError

    out = {}
    for item in items:
        station, sep, value = str(item).partition("=")
        if not sep or not station.strip() or not value.strip():
            raise ParameterError(f"--clearance {item!r}: expected STATION=CLEARANCE, e.g. '6=0.4 mm'")
        out[station.strip()] = _number_or_text(value.strip())
    return out


def main(args):
    from ..audit.run import api617_audit
    from ..errors import ParameterError
    from .common import load_preset
    from .linear_common import output_folder

    operating = parse_operating(args.operating)
    wachel = None
    if args.power is not None or args.impeller_diameter is not None or args.restrictive_width is not None:
        missing = [n for n, v in (("--power", args.power), ("--impeller-diameter", args.impeller_diameter),
                                  ("--restrictive-width", args.restrictive_width)) if v is None]
        if missing:
            raise ParameterError(f"Wachel Q_A needs --power, --impeller-diameter and --restrictive-width: "
                                 f"{', '.join(missing)} missing")
        wachel = {"power": [_number_or_text(v) for v in _list(args.power)],
                  "impeller_diameter": [_number_or_text(v) for v in _list(args.impeller_diameter)],
                  "restrictive_width": [_number_or_text(v) for v in _list(args.restrictive_width)],
                  "density_ratio": [_number_or_text(v) for v in _list(args.density_ratio)],
                  "stage_factor": _number_or_text(args.stage_factor)}
    if (args.qa is None) == (wachel is None):
        raise ParameterError("give the anticipated cross-coupling: --qa Q_A (e.g. '1.5 MN/m'), or the Wachel inputs "
                             "--power, --impeller-diameter, --restrictive-width (and --density-ratio)")
    clearances = parse_clearances(args.clearance) or None
    _, model, _ = load_preset(args)
    audit = api617_audit(model, operating, q_a=None if args.qa is None else _number_or_text(args.qa), wachel=wachel,
                         trip_speed=None if args.trip is None else _number_or_text(args.trip),
                         cross_coupling_stations=None if args.stations is None else _list(args.stations),
                         speed_parameter=args.speed_parameter, unbalance_multiple=args.unbalance_multiple,
                         probes=None if args.probes is None else _list(args.probes), close_clearances=clearances)
    out = output_folder(args, "audit")
    audit.write_csv(out)
    path = audit.write_report(out / "report.html")
    for check, value, requirement, passed in audit.summary():
        print(f"{'pass' if passed else 'FAIL':>4}  {check}: {value} (requirement {requirement})")
    print(f"API 617 audit: {'PASS' if audit.passed else 'FAIL'}; wrote {path.name} and CSV files to {out}")
    return 0
