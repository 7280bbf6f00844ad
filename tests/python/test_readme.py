"""The README's Python example runs as written (from the repository's root, as its paths expect)."""

import os
import re
import subprocess
import sys

from conftest import DATA, REPO


def readme_example():
    text = (REPO / "README.md").read_text()
    section = text[text.index("### Python: `import lidarscout`"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_readme_example_runs():
    code = readme_example().replace("../shared/data", str(DATA))
    done = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, env=os.environ,
                          check=False)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "1 1012412 3089"
    assert lines[-1].startswith("refused: ") and "no tile touches" in lines[-1]
