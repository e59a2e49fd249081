"""Shared fixtures of the Python module's tests (run by `make test` through
CTest, which sets PYTHONPATH to build/python and ROCKING_BIN to the program).

The records are found at $ROCKING_RECORDS or ../shared/data/records beside the
checkout; a test that needs them fails under CI=true when they are missing
and is skipped, saying so, otherwise."""
import json
import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("ROCKING_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SCENES = SOURCE / "data" / "scenes"


def read_history(path):
    """history.csv's column names (units dropped) and its rows as text fields."""
    lines = path.read_text().splitlines()
    names = [h.split(" [")[0] for h in lines[0].split(",")]
    rows = [line.split(",") for line in lines[1:] if line]
    return names, rows


def program_and_module(cli, tmp_path, scene_file):
    """`rocking simulate` on the scene file (its summary.json, and history.csv's
    names and rows) and rocking.simulate on the same file, for comparison."""
    import rocking

    out = tmp_path / "cli"
    r = cli.run("simulate", scene_file, "--out", out)
    assert r.returncode == 0, r.stderr
    expected = json.loads((out / "summary.json").read_text())
    names, rows = read_history(out / "history.csv")
    return expected, names, rows, rocking.simulate(rocking.Scene.load(str(scene_file)))


def records_dir():
    env = os.environ.get("ROCKING_RECORDS")
    return pathlib.Path(env) if env else SOURCE.parent / "shared" / "data" / "records"


@pytest.fixture
def records():
    folder = records_dir()
    if not folder.is_dir():
        message = f"the records folder {folder} is missing (set ROCKING_RECORDS)"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        print(f"\nSKIPPED: {message}")
        pytest.skip(message)
    return folder


@pytest.fixture
def elcentro(records):
    return records / "elcentro_1940_ns.at2"


class Cli:
    """The `rocking` program, as a user runs it."""

    def __init__(self):
        self.bin = os.environ.get("ROCKING_BIN", str(SOURCE / "build" / "bin" / "rocking"))

    def run(self, *args):
        return subprocess.run([self.bin, "-q", *map(str, args)], capture_output=True, text=True)

    def json(self, *args):
        r = self.run(*args)
        assert r.returncode == 0, r.stderr
        return json.loads(r.stdout)

    def error(self, *args):
        """The one-line message of an input error (exit 2)."""
        r = self.run(*args)
        assert r.returncode == 2, (args, r.returncode, r.stderr)
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1, r.stderr
        prefix = "rocking: error: "
        assert lines[0].startswith(prefix), lines[0]
        return lines[0][len(prefix):]


@pytest.fixture
def cli():
    return Cli()
