"""Runs an example of examples/ as a user runs it, for CTest. Examples that
read the records (--records) need them at $ROCKING_RECORDS or
../shared/data/records: missing, this fails under CI=true and otherwise exits
77, which CTest reports as skipped."""
import os
import pathlib
import runpy
import sys

from conftest import records_dir

example, *args = sys.argv[1:]
if "--records" in open(example).read():
    folder = records_dir()
    if not folder.is_dir():
        print(f"SKIPPED: {example}: the records folder {folder} is missing (set ROCKING_RECORDS)", file=sys.stderr)
        sys.exit(1 if os.environ.get("CI") == "true" else 77)
    args = ["--records", str(folder), *args]
sys.argv = [example, *args]
runpy.run_path(example, run_name="__main__")
