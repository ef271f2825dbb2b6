"""The examples keep running (the quick ones here; all paper figures are made for docs/paper.md)."""

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run(*args, cwd):
    proc = subprocess.run([sys.executable, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def test_jeffcott_example(tmp_path):
    out = run(EXAMPLES / "jeffcott.py", cwd=tmp_path)
    assert out.count("closed form") == 6


def test_paper_figures_example(tmp_path):
    out = run(EXAMPLES / "paper_figures.py", "--figs", "7", "8", "--out", tmp_path / "figs", cwd=tmp_path)
    for name in ("fig07_load_disk2.png", "fig08_orbit_disk2.png"):
        assert (tmp_path / "figs" / name).stat().st_size > 10_000
        assert name in out


def test_first_model_notebook_executes(tmp_path, monkeypatch):
    """The example notebook runs top to bottom in a fresh kernel, and its objects render as HTML/LaTeX."""
    import os

    import nbclient
    import nbformat

    root = str(EXAMPLES.parent)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([root, os.environ.get("PYTHONPATH", "")]))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(EXAMPLES / "first_model.ipynb", as_version=4)
    nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    data = [o.get("data", {}) for o in outputs]
    assert any("text/html" in d and "support1_stiffness" in d["text/html"] for d in data)  # the model
    assert any("text/latex" in d and r"\mathbf{M}" in d["text/latex"] for d in data)  # the equations
    assert any("image/png" in d for d in data)  # the orbit
    assert (tmp_path / "jeffcott.toml").stat().st_size > 0


def test_two_disk_rotor_example(tmp_path):
    """Beam-element rotor: each whirl pair splits with speed, forward above backward (gyroscopic stiffening)."""
    out = run(EXAMPLES / "two_disk_rotor.py", "--out", tmp_path / "figs", "--max-rpm", "2000", cwd=tmp_path)
    rows = [line.split("|") for line in out.splitlines() if "|" in line and line.split("|")[0].strip().isdigit()]
    assert len(rows) == 5
    for speed, cells in rows[1:]:
        values = cells.split()
        freqs, labels = [float(v[:-1]) for v in values], [v[-1] for v in values]
        assert labels == ["B", "F"] * 3, (speed, values)
        assert all(freqs[i] < freqs[i + 1] for i in range(0, 6, 2))
    for name in ("campbell.png", "modes.png"):
        assert (tmp_path / "figs" / name).stat().st_size > 10_000


def test_al31f_intershaft_example(tmp_path):
    """The faster HP bore drags the torque-driven LP spool forward through the inter-shaft rub."""
    out = run(EXAMPLES / "al31f_intershaft.py", "--t-end", "0.2", cwd=tmp_path)
    change = float(out.split("LP speed change by the rub:")[1].split()[0])
    assert change > 1.0, out
    assert "in contact" in out and "spin1" in out


def test_sommerfeld_example(tmp_path):
    """The smaller torque is captured below the critical speed (100 rad/s), the larger passes it."""
    out = run(EXAMPLES / "sommerfeld.py", "--out", tmp_path / "figs", cwd=tmp_path)
    finals = [float(line.split("speed at 6 s")[1].split()[0]) for line in out.splitlines() if "speed at 6 s" in line]
    assert len(finals) == 2 and 90.0 < finals[0] < 100.0 and finals[1] > 200.0, out
    assert (tmp_path / "figs" / "sommerfeld.png").stat().st_size > 10_000


def test_every_example_is_run_by_a_test():
    """Each example is run by a test here or in the test file of the element it shows."""
    source = "\n".join(p.read_text() for p in Path(__file__).parent.glob("test_*.py"))
    examples = [p.name for p in EXAMPLES.iterdir() if p.suffix in (".py", ".ipynb")]
    assert examples
    assert [name for name in examples if name not in source] == []


@pytest.mark.slow
def test_rig_figures_example_clearance_check(tmp_path):
    out = run(EXAMPLES / "rig_figures.py", "--clearance", cwd=tmp_path)
    assert out.count("largest radial displacement") == 3 and "clearance of the preset: 0.15 mm" in out


def _tutorial_notebook_text():
    import importlib.util

    spec = importlib.util.spec_from_file_location("docs_notebook", EXAMPLES.parent / "docs" / "hooks" / "notebook.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.notebook_text(EXAMPLES.parent / "docs" / "tutorial.md")


def test_tutorial_notebook_is_the_docs_page():
    """examples/tutorial.ipynb is docs/tutorial.md's code, unchanged (remake: python docs/hooks/notebook.py
    docs/tutorial.md examples/tutorial.ipynb)."""
    assert (EXAMPLES / "tutorial.ipynb").read_text() == _tutorial_notebook_text()


@pytest.mark.slow
def test_tutorial_notebook_executes(tmp_path, monkeypatch):
    """The tutorial, from geometry to the model file, runs top to bottom in a fresh kernel."""
    import os

    import nbclient
    import nbformat

    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(EXAMPLES.parent), os.environ.get("PYTHONPATH", "")]))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(EXAMPLES / "tutorial.ipynb", as_version=4)
    nbclient.NotebookClient(nb, timeout=900, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"]
    assert not errors, errors
    for name in ("mode1.png", "campbell.png", "critical_speed_map.png", "bode_x8.png"):
        assert (tmp_path / name).stat().st_size > 10_000, name
    assert (tmp_path / "compressor.toml").stat().st_size > 0
