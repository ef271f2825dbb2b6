"""Every fenced Python block of the documentation runs as written.

The blocks of one page run in order, in one fresh Python process started in an empty temporary folder
(so a page may use what an earlier block of the same page defined, as a reader would). Markers in the
Markdown, as HTML comments that the rendered site does not show:

- ``<!-- snippet-setup: rotorkit run al31f --t-end 0.5 -->``: a command the page's text tells the reader
  to have run first; run (as ``python -m rotorkit.cli ...``) in the page's folder before its blocks.
- ``<!-- snippet-notebook: examples/NAME.ipynb -->``: the page's blocks run as that notebook (made from the
  page by ``docs/hooks/notebook.py``; ``tests/test_examples.py`` checks it is unchanged and executes it),
  not a second time here.
- ``<!-- snippet-skip: REASON -->`` on the line before a block: the block needs what CI cannot have (a
  batch cluster); the reason is required and the block is still compiled, so it cannot rot into
  invalid Python.

``--8<-- "FILE:SECTION"`` lines (pymdownx.snippets) are replaced by the named section of the file, as
the site build does.
"""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted((ROOT / "docs").glob("*.md")) + [ROOT / "README.md"]

_BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)
_SETUP = re.compile(r"^<!-- snippet-setup: (.+?) -->$", re.M)
_SKIP = re.compile(r"<!-- snippet-skip: (.+?) -->\s*$")
_NOTEBOOK = re.compile(r"^<!-- snippet-notebook: (\S+) -->$", re.M)
_INCLUDE = re.compile(r'^--8<-- "([^":]+):(\w+)"$', re.M)


def _section(match):
    path, name = match.groups()
    text = (ROOT / path).read_text()
    found = re.search(rf"# --8<-- \[start:{name}\]\n(.*?)# --8<-- \[end:{name}\]", text, re.S)
    if found is None:
        raise AssertionError(f"snippet include {match.group(0)!r}: no section {name!r} in {path}")
    return found.group(1)


def page_snippets(page):
    """(setup commands, [(code, skip reason or None)]) of a Markdown page."""
    text = page.read_text()
    blocks = []
    for match in _BLOCK.finditer(text):
        before = text[:match.start()].rstrip("\n").rsplit("\n", 1)[-1]
        skip = _SKIP.search(before)
        blocks.append((_INCLUDE.sub(_section, match.group(1)), skip.group(1) if skip else None))
    return _SETUP.findall(text), blocks


def _pages_with_code():
    return [p for p in PAGES if page_snippets(p)[1] and not _NOTEBOOK.search(p.read_text())]


def test_notebook_pages_have_their_notebook():
    for page in PAGES:
        for name in _NOTEBOOK.findall(page.read_text()):
            assert (ROOT / name).is_file(), f"{page.name}: {name} does not exist"


def _env():
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    return env


@pytest.mark.slow
@pytest.mark.parametrize("page", _pages_with_code(), ids=lambda p: p.name)
def test_page_code_blocks_run_as_written(page, tmp_path):
    setups, blocks = page_snippets(page)
    for command in setups:
        words = shlex.split(command)
        assert words[0] == "rotorkit", f"{page.name}: snippet-setup must be a rotorkit command, got {command!r}"
        done = subprocess.run([sys.executable, "-m", "rotorkit.cli", *words[1:]], cwd=tmp_path, env=_env(),
                              capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, f"{page.name}: setup {command!r} failed:\n{done.stderr[-3000:]}"
    code = []
    for i, (block, skip) in enumerate(blocks):
        compile(block, f"{page.name} block {i + 1}", "exec")  # even a skipped block must be valid Python
        if skip is None:
            code.append(f"# --- {page.name}, block {i + 1}\n{block}")
    script = tmp_path / "page.py"
    script.write_text("\n".join(code))
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=_env(), capture_output=True,
                          text=True, timeout=900)
    assert done.returncode == 0, f"{page.name}: a code block failed:\n{done.stderr[-4000:]}"


def test_pages_with_code_are_found():
    names = {p.name for p in _pages_with_code()}
    assert {"README.md", "theory.md", "analysis-campbell.md"} <= names


def test_includes_are_resolved_and_skips_need_a_reason(tmp_path):
    page = tmp_path / "p.md"
    page.write_text('```python\n--8<-- "docs/hooks/generated.py:jeffcott"\n```\n\n'
                    "<!-- snippet-skip: needs a SLURM cluster -->\n```python\nimport nowhere\n```\n")
    _, blocks = page_snippets(page)
    assert "def jeffcott" in blocks[0][0] and blocks[0][1] is None
    assert blocks[1] == ("import nowhere\n", "needs a SLURM cluster")
    page.write_text("<!-- snippet-skip: -->\n```python\nimport nowhere\n```\n")
    assert page_snippets(page)[1][0][1] is None  # an empty reason does not skip
