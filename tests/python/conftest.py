"""Shared fixtures of the Python module's tests.

ctest (tests/python/CMakeLists.txt) runs them with Debian's interpreter and sets
PYTHONPATH=build/python, EXTREMAL_CLI (the `extremal` command), EXTREMAL_SHARED_DATA (the real
CAD files, ../shared/data as the C++ tests find them) and EXTREMAL_SOURCE_DIR. By hand:
    PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/python
finds the same places from this file's own."""

import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("EXTREMAL_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
BINARY_DIR = pathlib.Path(os.environ.get("EXTREMAL_BINARY_DIR", SOURCE_DIR / "build"))
CLI = pathlib.Path(os.environ.get("EXTREMAL_CLI", BINARY_DIR / "cli" / "extremal"))
SHARED_DATA = pathlib.Path(os.environ.get("EXTREMAL_SHARED_DATA",
                                          SOURCE_DIR.parent / "shared" / "data"))


@pytest.fixture(scope="session")
def shared_data():
    if not SHARED_DATA.is_dir():
        pytest.fail(f"the shared CAD data is not at {SHARED_DATA} (EXTREMAL_SHARED_DATA)")
    return SHARED_DATA


@pytest.fixture(scope="session")
def cli():
    """Runs the `extremal` command; returns (exit code, stdout, stderr)."""
    if not CLI.is_file():
        pytest.fail(f"the extremal command is not at {CLI} (EXTREMAL_CLI)")

    def run(*args):
        p = subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True,
                           timeout=600)
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    """`extremal ... --json` parsed (the command must succeed)."""

    def run(*args):
        code, out, err = cli(*args, "--json")
        assert code == 0, err
        return json.loads(out)

    return run


def write_scene(path, scene):
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(scene, indent=1))
    return path
