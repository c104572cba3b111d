"""docs/python.md is a tour whose every ```python block runs, in order, in one namespace, from
the source tree; its `#>` lines are what the block prints."""
import contextlib
import io
import os
import re

from conftest import CACHE, SOURCE


def blocks(text):
    return re.findall(r"^```python\n(.*?)^```$", text, flags=re.S | re.M)


def test_the_tour_in_docs_python_md_runs():
    """Catches: a tour that no longer runs (a renamed call, a changed default) or prints other
    numbers than it says."""
    with open(os.path.join(SOURCE, "docs", "python.md"), encoding="utf-8") as f:
        code = blocks(f.read())
    assert len(code) >= 8
    if CACHE:
        os.environ["PHYNJO_CACHE_DIR"] = CACHE
    os.chdir(SOURCE)
    namespace = {}
    for i, block in enumerate(code):
        expected = [l[3:] if l.startswith("#> ") else l[2:] for l in block.splitlines() if l.startswith("#>")]
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(block, f"docs/python.md block {i + 1}", "exec"), namespace)
        assert out.getvalue().splitlines() == expected, f"block {i + 1}:\n{block}"
