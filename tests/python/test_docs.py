"""The examples of docs/python.md run as they are written (from the source folder, the shared
CAD data where the docs say it is) and print what their comments say."""

import contextlib
import io
import os
import re

from conftest import SHARED_DATA, SOURCE_DIR


def test_the_examples_run(tmp_path):
    text = (SOURCE_DIR / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 7
    namespace = {}
    printed = io.StringIO()
    before = os.getcwd()
    os.chdir(SOURCE_DIR)
    try:
        with contextlib.redirect_stdout(printed):
            for block in blocks:
                exec(compile(block.replace("<data>", str(SHARED_DATA)), "docs/python.md",
                             "exec"), namespace)
    finally:
        os.chdir(before)
    lines = printed.getvalue().splitlines()
    assert lines[0] == "STEP AP214 mm 1"
    assert "40.0 converged True" in lines
    assert any(line.startswith("-40.0") and line.endswith("penetrating surfaces_meet hull")
               for line in lines)
    assert 0.07 < namespace["rep"].summary[("A", "bracket")]["deepest_penetration"] < 0.09
    assert namespace["files"] == [os.path.join(namespace["out"], "demo.csv")]
    assert os.path.getsize(namespace["files"][0]) > 0
