"""A parametric study in a loop: the damper plates' thickness against the
chimney's peak rocking angle under El Centro (a thicker plate is stiffer and
stronger: k x tau^3, yield displacement x 1/tau).

    python3 examples/damper_thickness.py [--records DIR] [--out DIR]
"""
import argparse
import os
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import rocking

here = pathlib.Path(__file__).resolve().parent
parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--records", default=os.environ.get("ROCKING_RECORDS", here.parent.parent / "shared/data/records"))
parser.add_argument("--out", default="out/examples")
args = parser.parse_args()

record = rocking.Record.load(pathlib.Path(args.records) / "elcentro_1940_ns.at2")
scene = rocking.Scene.default()
thickness = np.linspace(0.5, 2.0, 7)
peaks = []
for tau in thickness:
    run = rocking.simulate(scene.set("damper.thickness", float(tau)), record, history=False)
    peaks.append(run.peaks["theta_over_alpha"])
    print(f"thickness x{tau:.2f}: peak theta/alpha_cg {peaks[-1]:.4f}")
free = rocking.simulate(scene.set("damper.enabled", False), record, history=False).peaks["theta_over_alpha"]
print(f"no damper:       peak theta/alpha_cg {free:.4f}")

fig, ax = plt.subplots(figsize=(5, 3.5), constrained_layout=True)
ax.plot(thickness, peaks, "o-", label="with dampers")
ax.axhline(free, ls="--", color="0.4", label="no damper")
ax.set_ylim(0.95 * min(peaks), 1.05 * max(free, max(peaks)))  # the no-damper line clear of the frame
ax.set_xlabel("damper thickness / the paper's")
ax.set_ylabel(r"peak $\theta / \alpha_{cg}$")
ax.legend(frameon=False)
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "damper_thickness.png", dpi=150)
print(f"wrote {out / 'damper_thickness.png'}")
