"""The audit report: one self-contained HTML file (figures as base64 PNG, inline CSS, no network).

:func:`write_report` writes the pass/fail summary, the inputs and the
rotorkit version, the model drawn, the static analysis (journal loads,
deflection, shear force and bending moment), the undamped critical speed
map with the bearing curves, the unbalance response of each mode with its
placement, amplification factor and separation margin, the amplitudes at
the vibration probes and the close clearances, and the Level I stability.
Figures are drawn on :class:`matplotlib.figure.Figure` objects of their
own (pyplot's state is not touched).
"""

from __future__ import annotations

import base64
import datetime
import html
import math

__all__ = ["write_report", "report_html"]

_RPM = 30.0 / math.pi

_CSS = """
body { font-family: sans-serif; margin: 2em auto; max-width: 60em; color: #222; background: #fff; }
h1 { border-bottom: 2px solid #444; } h2 { border-bottom: 1px solid #aaa; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.6em 0; } td, th { border: 1px solid #bbb; padding: 0.25em 0.6em; }
th { background: #eee; text-align: left; } .pass { background: #d8f0d8; } .fail { background: #f6d0d0; }
.verdict { font-size: 1.4em; font-weight: bold; padding: 0.3em 0.8em; display: inline-block; }
img { max-width: 100%; } .note { color: #555; font-size: 0.9em; }
"""


def _figure(width=7.0, height=3.6, rows=1):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    return fig, fig.subplots(rows, 1, sharex=rows > 1)


def _img(fig, alt):
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    return f'<img alt="{html.escape(alt)}" src="data:image/png;base64,{data}">'


def _table(header, rows, flags=None):
    out = ["<table>", "<tr>" + "".join(f"<th>{html.escape(str(h))}</th>" for h in header) + "</tr>"]
    for i, row in enumerate(rows):
        cls = "" if flags is None or flags[i] is None else f' class="{"pass" if flags[i] else "fail"}"'
        out.append(f"<tr{cls}>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def _rotor_figure(audit):
    from ..plotting.rotor import draw_rotor, rotor_layout

    layout = rotor_layout(audit.model)
    fig, ax = _figure(7.0, 2.2)
    draw_rotor(ax, layout, bottom=-1.0, top=1.0)
    z = list(layout.positions.values())
    ax.set_xlim(min(z) - 0.05 * layout.span, max(z) + 0.05 * layout.span)
    ax.set_ylim(-1.3, 1.1)
    ax.set_xlabel("axial position (m)")
    ax.set_yticks([])
    ax.set_title(f"{audit.model.name}: shaft, disks and bearings", fontsize=9)
    return fig


def _static_figures(audit):
    fig, ax = _figure(7.0, 3.0)
    audit.static.plot(ax=ax)
    fig2, axes = _figure(7.0, 4.6, rows=2)
    audit.shear_moment.plot(axes=axes)
    return fig, fig2


def _map_figure(audit):
    fig, ax = _figure(7.5, 4.6)
    audit.critical_map.plot(ax=ax, units="rpm")
    low, high = audit.operating
    ax.axhspan(low * _RPM, high * _RPM, color="tab:green", alpha=0.15, label="operating range")
    return fig


def _mode_figure(audit, check):
    fig, ax = _figure(7.0, 3.2)
    ax.plot(check.speeds * _RPM, check.response * 1e6, color="C0", label=f"station {check.probe}")
    af = check.amplification
    low, high = audit.operating
    ax.axvspan(low * _RPM, high * _RPM, color="tab:green", alpha=0.15, label="operating range")
    if af.factor > 0:
        ax.axhline(af.peak / math.sqrt(2) * 1e6, color="0.5", lw=0.8, ls=":", label="peak / sqrt(2)")
        for v in (af.lower, af.upper):
            if math.isfinite(v):
                ax.axvline(v * _RPM, color="0.5", lw=0.8, ls="--")
    ax.set_xlabel("speed (rpm)")
    ax.set_ylabel("major semi-axis (um)")
    ax.set_title(f"mode {check.mode}: API 617 unbalance response", fontsize=9)
    ax.legend(fontsize=8)
    return fig


def _amplitude_figure(audit, check):
    a = check.amplitude
    rows = 2 if a.clearances else 1
    fig, axes = _figure(7.0, 3.0 * rows, rows=rows)
    axes = list(axes) if rows > 1 else [axes]
    rpm = check.speeds * _RPM
    low, high = audit.operating
    for ax in axes:
        ax.axvspan(low * _RPM, high * _RPM, color="tab:green", alpha=0.15, label="operating range")
    for i, p in enumerate(a.probes):
        axes[0].plot(rpm, check.amplitudes[p] * 1e6, color=f"C{i}", label=f"probe st. {p}")
    axes[0].hlines(a.vibration_limit * 1e6, low * _RPM, high * _RPM, color="k", ls="--", lw=1.0,
                   label="A_vl (operating range)")
    axes[0].set_ylabel("pk-pk (um)")
    axes[0].set_title(f"mode {check.mode}: amplitude at the probes", fontsize=9)
    axes[0].legend(fontsize=8)
    if a.clearances:
        upto = check.speeds <= audit.trip_speed * (1 + 1e-12)
        axes[1].axvline(audit.trip_speed * _RPM, color="0.4", lw=0.8, ls=":", label="trip speed")
        for i, c in enumerate(a.clearances):
            line, = axes[1].plot(rpm[upto], a.scale_factor * check.amplitudes[c.station][upto] * 1e6, color=f"C{i}",
                                 label=f"st. {c.station} x S_cc")
            axes[1].axhline(c.limit * 1e6, color=line.get_color(), ls="--", lw=1.0)
        axes[1].set_ylabel("scaled pk-pk (um)")
        axes[1].set_title(f"close clearances (S_cc = {a.scale_factor:.3g}; dashed: 75 % of the clearance)",
                          fontsize=9)
        axes[1].legend(fontsize=8)
    axes[-1].set_xlabel("speed (rpm)")
    return fig


def _stability_figure(audit):
    fig, ax = _figure(7.0, 3.4)
    audit.stability.plot(ax=ax)
    return fig


def _fmt(v, digits=4):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.{digits}g}"


def _vibration_limit_text(audit):
    """``A_vl`` of the audit as text (um)."""
    return f"{audit.modes[0].amplitude.vibration_limit * 1e6:.3g} um" if audit.modes else "no mode in range"


def report_html(audit):
    """The report of an :class:`~rotorkit.audit.run.Api617Audit` as one HTML string."""
    verdict = audit.passed
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>API 617 audit: {html.escape(audit.model.name)}</title>", f"<style>{_CSS}</style></head><body>",
             f"<h1>API 617 lateral analysis audit: {html.escape(audit.model.name)}</h1>",
             f'<p class="note">rotorkit {html.escape(audit.version)}, written '
             f'{datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}. '
             "Checks after API Standard 617, 8th edition (2014), 4.8, and API RP 684 (2005).</p>"]
    parts.append("<h2>Summary</h2>")
    parts.append(f'<p class="verdict {"pass" if verdict else "fail"}">{"PASS" if verdict else "FAIL"}</p>')
    rows = audit.summary()
    parts.append(_table(["check", "value", "requirement", "result"],
                        [(a, b, c, "pass" if d else "fail") for a, b, c, d in rows], [r[3] for r in rows]))
    parts.append("<h2>Inputs</h2>")
    parts.append(_table(["input", "value"], list(audit.inputs.items())))
    parts.append("<h2>Model</h2>")
    model = audit.model
    parts.append(f"<p>{len(model.coordinate_names)} coordinates, {len(model.stations)} stations, "
                 f"{len(model.elements)} elements.</p>")
    parts.append(_img(_rotor_figure(audit), "the rotor"))
    parts.append(_table(["element", "type"], [(e.label(), type(e).__name__) for e in model.elements]))
    parts.append("<h2>Static analysis</h2>")
    def reaction(label):
        station = audit.bearings[label]
        forces = audit.static.reactions.get(label, {})
        return math.hypot(forces.get(f"x{station}", 0.0), forces.get(f"y{station}", 0.0))

    parts.append(_table(["bearing", "station", "journal static load (kg)", "reaction (N)"],
                        [(k, audit.bearings[k], f"{v:.4g}", f"{reaction(k):.4g}")
                         for k, v in audit.journal_loads.items()]))
    deflection, diagrams = _static_figures(audit)
    z, m = audit.shear_moment.max_moment()
    parts.append(_img(deflection, "static deflection"))
    parts.append(f"<p>Largest bending moment {m:.4g} N m at {z:.4g} m. Shear force and bending moment "
                 "(M = EI w'', positive sagging; V = dM/dz):</p>")
    parts.append(_img(diagrams, "shear force and bending moment"))
    parts.append("<h2>Undamped critical speed map</h2>")
    parts.append("<p>Rotor without its bearings on supports of stiffness k at the bearing stations; the bearings' "
                 "direct stiffness against speed drawn over it (a crossing is a critical speed on that "
                 "bearing). Shaded: the operating range.</p>")
    parts.append(_img(_map_figure(audit), "critical speed map"))
    parts.append("<h2>Unbalance response</h2>")
    multiple = audit.inputs.get("unbalance", "")
    parts.append(f"<p>Unbalance applied: {html.escape(multiple)}. U_r = 6350 W / N g mm is the residual unbalance "
                 f"(W in kg, N = {audit.operating[1] * _RPM:.6g} rpm, the maximum continuous speed, held at 25000 rpm "
                 "above it); the analysis applies twice it. Placement from each mode shape (API 617's figure of "
                 "typical mode shapes and their unbalance locations): the shape is cut at its sign changes into "
                 "lobes, lobes under 30 % of the largest dropped; one unbalance at each lobe's largest "
                 "displacement, at 0 or 180 deg with the sign of the lobe (in phase or out of phase). W is the sum "
                 "of the journal loads for the only lobe between the bearings (mid-span), the nearest journal's "
                 "load for each of several lobes, and the mass outboard of the bearing for a lobe on an overhung "
                 "end (a disk outboard of the bearing). Amplification factor AF = N_c1 / (N_2 - N_1) from the "
                 "half-power points; required separation margin min(16, 17 (1 - 1 / (AF - 1.5))) % below and "
                 "min(26, 10 + 17 (1 - 1 / (AF - 1.5))) % above the operating range, none when AF &lt; 2.5 "
                 "(4.8.2.10).</p>")
    rows, flags = [], []
    for c in audit.modes:
        a = c.amplification
        unb = "; ".join(f"st. {u.station}: {u.magnitude * 1e6:.4g} g mm at {math.degrees(u.angle):.0f} deg"
                        for u in c.unbalances)
        rows.append((c.mode, f"{a.critical_speed * _RPM:.0f}", unb, c.probe, f"{a.factor:.3g}",
                     f"{_fmt(a.lower * _RPM, 5)} / {_fmt(a.upper * _RPM, 5)}", f"{c.margin:.1f}",
                     f"{c.required:.1f}", "pass" if c.margin_passed else "fail"))
        flags.append(c.margin_passed)
    parts.append(_table(["mode", "peak (rpm)", "unbalance", "largest response at", "AF", "N1 / N2 (rpm)",
                         "margin (%)", "required (%)", "result"], rows, flags))
    if not audit.modes:
        parts.append("<p>No forward critical speed below 125 % of the trip speed.</p>")
    for c in audit.modes:
        parts.append(f"<p>Mode {c.mode} placement: {html.escape(c.placement.rule)}.</p>")
        parts.append(_img(_mode_figure(audit, c), f"unbalance response of mode {c.mode}"))
    parts.append("<h2>Amplitudes at the probes and close clearances</h2>")
    parts.append("<p>With each mode's unbalance applied: the peak-to-peak amplitude at the vibration probes within "
                 "the operating range, A_max, must be below A_vl = 25.4 sqrt(12000 / N_mc) um (at most 25.4 um; "
                 f"here {_vibration_limit_text(audit)}); the peak-to-peak amplitude at each close clearance from zero "
                 "to the trip speed, multiplied by S_cc = A_vl / A_max (held within "
                 f"{html.escape(audit.inputs.get('scale factor bounds', ''))}), must be below 75 % of the minimum "
                 "design diametral running clearance (API 617 8th ed. 4.8.2.10 and 4.8.2.11). Amplitudes on the "
                 "orbit's major axis (the largest a probe of any orientation reads).</p>")
    rows, flags = [], []
    for c in audit.modes:
        a = c.amplitude
        rows.append((c.mode, "probes " + ", ".join(a.probes), f"A_max = {a.max_amplitude * 1e6:.3g} um at st. "
                     f"{a.probe}, {a.speed * _RPM:.0f} rpm", f"< A_vl = {a.vibration_limit * 1e6:.3g} um",
                     "pass" if a.probes_passed else "fail"))
        flags.append(a.probes_passed)
        for k in a.clearances:
            rows.append((c.mode, f"clearance st. {k.station} ({k.clearance * 1e6:.4g} um)",
                         f"{k.amplitude * 1e6:.3g} um at {k.speed * _RPM:.0f} rpm (S_cc = {a.scale_factor:.3g})",
                         f"< {k.limit * 1e6:.4g} um", "pass" if k.passed else "fail"))
            flags.append(k.passed)
    parts.append(_table(["mode", "where", "amplitude (pk-pk)", "limit", "result"], rows, flags))
    if audit.modes and not audit.modes[0].amplitude.clearances:
        parts.append('<p class="note">No close clearance given: the clearance check was not run '
                     "(give close_clearances, or --clearance STATION=VALUE).</p>")
    for c in audit.modes:
        parts.append(_img(_amplitude_figure(audit, c), f"amplitudes of mode {c.mode}"))
    s = audit.stability
    parts.append("<h2>Level I stability</h2>")
    where = html.escape(", ".join(s.stations))
    parts.append(f"<p>Cross-coupled stiffness Q (F_x = -Q y, F_y = Q x) at station(s) {where}"
                 f", rotor at {s.speed * _RPM:.6g} rpm; log decrement of the first forward mode from Q = 0 to "
                 "10 Q_A; Q_0 where it reaches zero. Level II is required when Q_0 / Q_A &lt; 2 or the log "
                 "decrement at Q_A is below 0.1 (the critical speed ratio / gas density chart is not "
                 "evaluated).</p>")
    if audit.wachel is not None:
        parts.append("<p>Q_A = sum of q_A = B_c C P / (D_c H_c N) (rho_d / rho_s) per impeller: "
                     + ", ".join(f"{q:.4g} N/m" for q in audit.wachel) + ".</p>")
    parts.append(_table(["Q_A (N/m)", "log decrement at Q_A", "Q_0 (N/m)", "Q_0 / Q_A",
                         "frequency at Q = 0 (rpm)", "result"],
                        [(f"{s.q_a:.4g}", f"{s.log_decrement_a:.4g}", _fmt(s.q_0), _fmt(s.q_ratio, 3),
                          f"{s.frequencies[0] * _RPM:.0f}", "pass" if s.passed else "Level II required")],
                        [s.passed]))
    parts.append(_img(_stability_figure(audit), "log decrement against cross-coupling"))
    parts.append('<p class="note">Not checked here: the Level I region chart (critical speed ratio against gas '
                 "density), Level II analysis, the minimum and maximum bearing clearance cases (run the audit once "
                 "per bearing table).</p>")
    parts.append("</body></html>")
    return "\n".join(parts)


def write_report(audit, path):
    """Write the report of ``audit`` to ``path`` (HTML, UTF-8, atomically); the path."""
    from pathlib import Path

    from ..files import atomic_write_bytes

    path = Path(path)
    atomic_write_bytes(path, report_html(audit).encode("utf-8"))
    return path
