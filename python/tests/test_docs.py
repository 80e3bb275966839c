"""Every Python code block of README.md and docs/PYTHON.md runs as written (issue 44: the
README's dataset block needed group= and named variables nobody defined). The blocks of one
file run in order in one namespace, in a fresh folder where `tests` leads to the repository's
own tests/ (the paths the blocks name), so that what they write stays out of the repository."""

import re
import warnings

import pytest

from conftest import REPO

BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


@pytest.mark.parametrize("document", ["README.md", "docs/PYTHON.md"])
def test_every_python_block_runs_as_written(document, tmp_path, monkeypatch):
    blocks = BLOCK.findall((REPO / document).read_text())
    assert blocks, f"{document} has no Python block"
    (tmp_path / "tests").symlink_to(REPO / "tests")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    with warnings.catch_warnings():
        # Takes the corpus holds on purpose that do not compile are warned about.
        warnings.simplefilter("ignore")
        for number, block in enumerate(blocks, 1):
            try:
                exec(compile(block, f"{document} block {number}", "exec"), namespace)
            except Exception as error:
                raise AssertionError(f"{document}, Python block {number} fails:\n{block}") from error
