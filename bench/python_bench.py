"""What the Python module adds to a run (`make bench`): the chimney under El
Centro through rocking.simulate, against the time the run itself takes inside
the library (the summary's wall_s, measured in C++ around rocking::simulate,
its set-up included). The difference is everything the call adds: building
the model, the handler that keeps Ctrl-C alive, the summary into a dict, the
history's columns into NumPy arrays and the events into dicts. Interleaved
repeats, medians reported.

    PYTHONPATH=build/python python3 bench/python_bench.py [--repeats N] [--records DIR]
"""
import argparse
import os
import pathlib
import statistics
import time

import rocking

here = pathlib.Path(__file__).resolve().parent
parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--repeats", type=int, default=41)
parser.add_argument("--records", default=os.environ.get("ROCKING_RECORDS", here.parent.parent / "shared/data/records"))
args = parser.parse_args()

scene = rocking.Scene.default()
record = rocking.Record.load(pathlib.Path(args.records) / "elcentro_1940_ns.at2")
rows = {}
for history in (True, False):
    rocking.simulate(scene, record, history=history)  # warm caches
    calls, cores = [], []
    for _ in range(args.repeats):
        start = time.perf_counter()
        result = rocking.simulate(scene, record, history=history)
        calls.append(time.perf_counter() - start)
        cores.append(result.summary["wall_s"])
    ratios = [c / r - 1 for c, r in zip(calls, cores)]
    rows[history] = (statistics.median(calls), statistics.median(cores), statistics.median(ratios),
                     len(result.history.get("t", [])))

print(f"chimney under El Centro (rocking.simulate, default tolerances), {args.repeats} repeats, medians")
print(f"{'history':>9} {'rows':>6} {'call [ms]':>10} {'run [ms]':>9} {'overhead':>9}")
for history, (call, core, ratio, n) in rows.items():
    print(f"{'kept' if history else 'none':>9} {n:>6} {1e3 * call:>10.3f} {1e3 * core:>9.3f} {100 * ratio:>8.2f}%")
