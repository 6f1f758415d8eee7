"""The README's Python examples run as printed (in a scratch folder), and say what they print."""
import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)


def test_the_readme_has_python_examples():
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_python_example_runs_as_printed(tmp_path, index):
    script = tmp_path / "example.py"
    script.write_text(BLOCKS[index])
    prepare = re.search(r"# (wearjoint build-fmu --out \S+)", BLOCKS[index])   # a command the example says it needs
    if prepare:
        done = subprocess.run([sys.executable, "-m", "wearjoint.cli", *prepare.group(1).split()[1:]], cwd=tmp_path,
                              capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, done.stderr[-3000:]
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
