"""A Markdown page of the docs as a Jupyter notebook: text cells and its Python blocks as code cells.

    python docs/hooks/notebook.py docs/tutorial.md examples/tutorial.ipynb

writes the notebook; ``tests/test_examples.py`` checks that the notebook on disk is the one this makes of
the page (so they cannot drift apart) and executes it. Other fenced blocks (``bash``, output) stay in the
text cells; HTML comments are dropped.
"""

import json
import re
import sys
from pathlib import Path

_FENCE = re.compile(r"^```python\n(.*?)^```\n?", re.S | re.M)
_COMMENT = re.compile(r"^<!--.*?-->\n?", re.S | re.M)


def _markdown(text):
    text = re.sub(r"\n{3,}", "\n\n", _COMMENT.sub("", text)).strip("\n")
    return {"cell_type": "markdown", "metadata": {}, "source": text.splitlines(keepends=True)} if text else None


def page_to_notebook(page):
    """The notebook (a dict in nbformat 4) of a Markdown page."""
    text = Path(page).read_text()
    cells, last = [], 0
    for match in _FENCE.finditer(text):
        cells.append(_markdown(text[last:match.start()]))
        cells.append({"cell_type": "code", "execution_count": None, "metadata": {}, "outputs": [],
                      "source": match.group(1).rstrip("\n").splitlines(keepends=True)})
        last = match.end()
    cells.append(_markdown(text[last:]))
    return {
        "cells": [c for c in cells if c is not None],
        "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
                     "language_info": {"name": "python"}},
        "nbformat": 4,
        "nbformat_minor": 4,
    }


def notebook_text(page):
    """The notebook file's text (stable: sorted keys, one-space indent, final newline)."""
    return json.dumps(page_to_notebook(page), indent=1, sort_keys=True, ensure_ascii=False) + "\n"


if __name__ == "__main__":
    source, target = sys.argv[1:3]
    Path(target).write_text(notebook_text(source))
    print("wrote", target)
