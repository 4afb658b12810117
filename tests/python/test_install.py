"""`cmake --install` puts the module into Debian's dist-packages layout, where it imports with
no build tree in sight."""

import os
import pathlib
import subprocess
import sys

import pytest

from conftest import BINARY_DIR


def test_the_installed_module_imports_and_measures(tmp_path):
    cmake = os.environ.get("CMAKE_COMMAND", "cmake")
    site = os.environ.get("EXTREMAL_PYTHON_INSTALL_DIR")
    if not site:
        pytest.fail("EXTREMAL_PYTHON_INSTALL_DIR is not set (ctest sets it)")
    assert site.endswith("dist-packages")
    prefix = tmp_path / "prefix"
    p = subprocess.run([cmake, "--install", str(BINARY_DIR), "--component", "python",
                        "--prefix", str(prefix)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    package = prefix / site / "extremal"
    names = sorted(f.name for f in package.iterdir())
    assert len(names) == 3 and names[0] == "__init__.py" and names[2] == "batch.py"
    assert names[1].startswith("_core.cpython-") and names[1].endswith(".so")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(prefix / site)
    script = ("import extremal, extremal.batch\n"
              "print(extremal.__file__)\n"
              "r = extremal.distance(extremal.sphere(1), extremal.sphere(2), pose_b=(5, 0, 0))\n"
              "print(r.distance)\n")
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env,
                       cwd=tmp_path, timeout=120)
    assert p.returncode == 0, p.stderr
    where, d = p.stdout.split()
    assert pathlib.Path(where).resolve() == (package / "__init__.py").resolve()
    assert float(d) == 2.0
