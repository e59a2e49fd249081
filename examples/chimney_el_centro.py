"""The Christchurch chimney under El Centro 1940 (N-S), with and without its
dampers: top drift and rocking angle against time, as in the paper's Fig. 4.

    python3 examples/chimney_el_centro.py [--records DIR] [--out DIR]
"""
import argparse
import os
import pathlib

import matplotlib

matplotlib.use("Agg")  # draws to files: no display needed
import matplotlib.pyplot as plt

import rocking

here = pathlib.Path(__file__).resolve().parent
parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--records", default=os.environ.get("ROCKING_RECORDS", here.parent.parent / "shared/data/records"))
parser.add_argument("--out", default="out/examples")
args = parser.parse_args()

record = rocking.Record.load(pathlib.Path(args.records) / "elcentro_1940_ns.at2")
chimney = rocking.Scene.default()
runs = {
    "with dampers": rocking.simulate(chimney, record),
    "no damper": rocking.simulate(chimney.copy().set("damper.enabled", False), record),
}

fig, (top, tilt) = plt.subplots(2, 1, sharex=True, figsize=(7, 5), constrained_layout=True)
for label, run in runs.items():
    h = run.history
    top.plot(h["t"], 100 * h["delta_t"], lw=0.9, label=label)
    tilt.plot(h["t"], h["theta_over_alpha"], lw=0.9, label=label)
    print(f"{label:13s} peak delta_t {100 * run.peaks['delta_t']:.3f} %, theta/alpha_cg "
          f"{run.peaks['theta_over_alpha']:.3f}, {run.summary['counts']['uplifts']} uplifts")
top.set_ylabel(r"top drift $\delta_t$ [%]")
tilt.set_ylabel(r"$\theta / \alpha_{cg}$")
tilt.set_xlabel("t [s]")
top.legend(frameon=False)
top.set_title(f"{chimney.name} under {record.name}")
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "chimney_el_centro.png", dpi=150)
print(f"wrote {out / 'chimney_el_centro.png'}")
