"""The README's Python example runs as written (its cells in order, from a
folder where data/ is the bundled data; plotting where matplotlib is)."""
import os
import re
import subprocess
import sys

from conftest import DATA, SOURCE


def test_readme_python_cells_run(tmp_path):
    readme = (SOURCE / "README.md").read_text()
    section = readme[readme.index("## Python"):]
    section = section[:section.index("\n## ", 1)]
    cells = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(cells) >= 4
    (tmp_path / "data").symlink_to(DATA)
    env = dict(os.environ, MPLBACKEND="Agg")
    r = subprocess.run([sys.executable, "-c", "\n".join(cells)], cwd=tmp_path, env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "calibration.yaml").read_text().startswith("# Calibration written by")
