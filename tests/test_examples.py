"""The examples keep running (the quick ones here; all paper figures are made for docs/paper.md)."""

import subprocess
import sys
from pathlib import Path

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
