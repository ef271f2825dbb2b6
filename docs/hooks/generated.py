"""MkDocs hook: pages whose content rotorkit itself generates at build time (so they cannot drift).

A page asks for generated content with an HTML comment on its own line:

- ``<!-- generated: equations jeffcott -->``: the LaTeX of the Jeffcott
  rotor's derived equations (the model below);
- ``<!-- generated: equations al31f -->``: the same for the AL-31F preset;
- ``<!-- generated: cli -->``: ``rotorkit <command> --help`` of every command;
- ``<!-- generated: gallery -->``: every example in ``examples/`` with its
  description and the command that runs it.
"""

import ast
import contextlib
import io
import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_MARKER = re.compile(r"^<!-- generated: (\w+)(?: (\w+))? -->$", re.MULTILINE)


# --8<-- [start:jeffcott]
def jeffcott():
    """A Jeffcott rotor: one unbalanced disk on an elastic, damped support, under gravity."""
    import rotorkit as rk

    return rk.Model([
        rk.Rotor(name="R", stations=(1,), speed=300.0),                   # rad/s
        rk.Disk(station=1, mass=5.0, radius=0.1, eccentricity=1e-5),       # kg, m, m
        rk.ElasticSupport(station=1, stiffness=5e5, damping=50.0),         # N/m, N s/m
        rk.Maneuver.steady(),                                              # gravity
    ], name="jeffcott")
# --8<-- [end:jeffcott]


def _model(name):
    import rotorkit as rk

    return jeffcott() if name == "jeffcott" else rk.preset(name)


def _equations(name):
    model = _model(name)
    eom = model.equations()
    return (f"*Generated from `{name}` ({len(model.coordinate_names)} coordinates, effects: "
            f"{', '.join(sorted(model.effects))}) by `model.equations().latex()` when this site was built.*\n\n"
            "$$\n" + eom.latex() + "\n$$\n")


def _cli():
    from rotorkit.cli import COMMANDS, build_parser

    os.environ["COLUMNS"] = "100"  # argparse wraps help text to the terminal width
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    out = []
    for module in COMMANDS:
        for name, command in sub.choices.items():
            if command.get_default("func").__module__.endswith(f".{module}"):
                out.append(f"### `rotorkit {name}`\n\n```text\n{command.format_help().rstrip()}\n```\n")
    return "\n".join(out)


def _gallery():
    out = []
    for path in sorted((ROOT / "examples").iterdir()):
        if path.suffix == ".py":
            doc = ast.get_docstring(ast.parse(path.read_text())) or ""
            command = f"python examples/{path.name}"
        elif path.suffix == ".ipynb":
            import json

            cells = json.loads(path.read_text())["cells"]
            doc = "".join(cells[0]["source"]).lstrip("# ") if cells and cells[0]["cell_type"] == "markdown" else ""
            command = f"jupyter lab examples/{path.name}"
        else:
            continue
        title, _, rest = doc.partition("\n")
        out.append(f"## `{path.name}`\n\n**{title.strip()}**\n\n{rest.strip()}\n\nRun it: `{command}` "
                   f"(run in CI by `tests/test_examples.py`).\n")
    return "\n".join(out)


def on_page_markdown(markdown, page, config, files):
    if "<!-- generated:" not in markdown:
        return markdown
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))

    def replace(match):
        kind, arg = match.groups()
        with contextlib.redirect_stdout(io.StringIO()):
            if kind == "equations":
                return _equations(arg)
            if kind == "cli":
                return _cli()
            if kind == "gallery":
                return _gallery()
        raise ValueError(f"{page.file.src_path}: unknown generated block {match.group(0)!r}")

    return _MARKER.sub(replace, markdown)
