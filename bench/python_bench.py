"""What the Python module adds to a run (`make bench`): the chimney under El
Centro through rocking.simulate, against the time the run itself takes inside
the library (the summary's wall_s, measured in C++ around rocking::simulate,
its set-up included). The difference is everything the call adds: building
the model, the handler that keeps Ctrl-C alive, the summary into a dict, the
history's columns into NumPy arrays and the events into dicts. Interleaved
repeats, medians reported. Then how soon Ctrl-C stops an IDA of 3000 runs
(tests/python/test_ida.py checks only that it does).

    PYTHONPATH=build/python python3 bench/python_bench.py [--repeats N] [--records DIR]
"""
import argparse
import os
import pathlib
import signal
import threading
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

# Ctrl-C one second into an IDA of 3000 runs (3 variants x 1000 levels).
levels = [0.01 * k for k in range(1, 1001)]
timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
start = time.monotonic()
timer.start()
try:
    rocking.ida(scene, [record], levels=levels, threads=2)
    print("Ctrl-C did not stop the IDA: it ran to its end")
except KeyboardInterrupt:
    print(f"Ctrl-C 1 s into a 3000-run IDA: the call returned {time.monotonic() - start - 1.0:.2f} s after the signal")
timer.cancel()
