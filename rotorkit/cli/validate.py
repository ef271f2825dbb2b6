"""``rotorkit validate``: check a preset's claims from simulated spectra."""

import sys
from pathlib import Path

from ..errors import ParameterError


def register(sub):
    va = sub.add_parser("validate", help="check the paper's claims from simulated spectra and print the table")
    va.add_argument("preset", help="preset name, e.g. al31f (see 'rotorkit list')")
    va.add_argument("--out", help="also write claims.txt here")
    va.set_defaults(func=main)


def main(args):
    from ..presets import preset_module
    from ..validation import Study, format_table

    if args.out is not None:  # before the study's runs: a file, a device or '' is refused now
        from ..files import check_output_folder

        check_output_folder(args.out, ours=False)
    module = preset_module(args.preset)
    claims = getattr(module, "CLAIMS", ())
    if not claims:
        raise ParameterError(f"preset {args.preset!r} defines no CLAIMS to validate")
    outputs = getattr(module, "OUTPUTS", {})
    options = dict(getattr(module, "STUDY", {}))  # a preset's own study settings (sensors, window, band, ...)
    signals = options.pop("signals", None) or {"bending": outputs["bending"], "torsion": outputs["torsion"]}

    def progress(done, overrides, status):
        text = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in overrides.items())
        print(f"  run {done}: {text or 'defaults'}: {status}", file=sys.stderr, flush=True)

    study = Study(args.preset, signals, t_end=outputs.get("t_end", 6.0), progress=progress, **options)
    results = [claim(study) for claim in claims]
    table = format_table(results)
    print(table)
    if args.out is not None:
        from ..files import atomic_write_text

        out = Path(args.out)
        atomic_write_text(out / "claims.txt", table + "\n")
        print(f"wrote {out / 'claims.txt'}")
    return 0
