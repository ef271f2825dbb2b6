"""Rich display in Jupyter: LaTeX for elements, HTML tables for models, parameters and results.

The objects' ``_repr_latex_`` / ``_repr_html_`` methods delegate here, so a
notebook shows a model as a table and an element as its parameters with
their symbols and units. Nothing here is imported unless a notebook asks.
"""

import html
import re

__all__ = ["unit_latex", "element_latex", "model_html", "parameter_html", "result_html"]


def unit_latex(unit):
    """An SI unit string (``"N*s/m"``, ``"kg*m**2"``, ``"N/m**1.5"``) as upright LaTeX."""
    if not unit:
        return ""
    text = re.sub(r"\*\*\s*([0-9.]+)", r"^{\1}", unit).replace("*", r"\,")
    return r"\mathrm{%s}" % text


def _number(value):
    text = f"{value:.6g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        return rf"{mantissa} \times 10^{{{int(exponent)}}}"
    return text


def _text(value):
    return r"\text{%s}" % str(value).replace("_", r"\_").replace("{", "").replace("}", "")


def element_latex(element):
    """``$...$`` LaTeX of an element: type, label, structural fields and parameters with units."""
    import dataclasses

    label = element.label() if hasattr(element, "label") else type(element).__name__
    parts = [r"\textbf{%s}\ %s" % (type(element).__name__, _text(label))]
    units = getattr(element, "_units", {})
    names = getattr(element, "_latex_names", {})
    for f in dataclasses.fields(element):
        value = getattr(element, f.name)
        if f.name == "name" or value is None or f.name in units or callable(value):
            continue
        if isinstance(value, tuple) and not value:
            continue
        parts.append(r"%s = %s" % (_text(f.name), _text(value if not isinstance(value, tuple) else list(value))))
    for f, value in (element.parameters().items() if hasattr(element, "parameters") else ()):
        unit = element.unit_of(f) if hasattr(element, "unit_of") else units[f][0]
        symbol = names.get(f, _text(f))
        parts.append(rf"{symbol} = {_number(value)}\,{unit_latex(unit)}")
    return "$" + r",\quad ".join(parts) + "$"


def _table(head, rows, caption=None):
    out = ["<table>"]
    if caption:
        out.append(f"<caption>{html.escape(caption)}</caption>")
    out.append("<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>")
    for row in rows:
        out.append("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>")
    out.append("</table>")
    return "".join(out)


def parameter_html(model):
    """The model's parameters as an HTML table: name, SI value, unit, element."""
    units = model.parameter_units
    owner = {f"{e.label()}_{f}": f"{type(e).__name__} {e.label()}" for e in model.elements for f in e.parameters()}
    rows = [(name, f"{value:.6g}", units[name] or "-", owner[name]) for name, value in model.parameters.items()]
    return _table(("parameter", "value", "unit", "element"), rows)


def model_html(model):
    """A model as HTML: a summary line, its elements and its parameter table."""
    rows = []
    for e in model.elements:
        stations = ", ".join(str(s) for s in e.attached_stations())
        params = ", ".join(f"{f}={v:.4g} {u}".strip() for (f, v), u in zip(e.parameters().items(),
                                                                          e.parameter_units().values()))
        rows.append((type(e).__name__, e.label(), stations, params))
    summary = (f"<p><b>Model {html.escape(model.name)}</b>: {len(model.elements)} elements, "
               f"{len(model.coordinate_names)} coordinates ({html.escape(', '.join(model.coordinate_names))}), "
               f"effects: {html.escape(', '.join(sorted(model.effects)) or 'none')}</p>")
    return (summary + _table(("element", "label", "stations", "parameters (SI)"), rows, "elements")
            + "<details><summary>parameters</summary>" + parameter_html(model) + "</details>")


def result_html(result):
    """A result as HTML: time span, samples, signals and run statistics."""
    t = result.t
    span = f"{t[0]:.4g} - {t[-1]:.4g} s" if len(t) else "empty"
    head = (f"<p><b>Result {html.escape(str(result.name))}</b>: {span}, {len(t)} samples, "
            f"{len(result.state_names)} states</p>")
    stats = [(k, v if not isinstance(v, float) else f"{v:.4g}") for k, v in result.stats.items()
             if isinstance(v, (int, float, str))]
    names = ", ".join(result.state_names)
    return head + f"<p>signals: {html.escape(names)}</p>" + _table(("statistic", "value"), stats, "run")
