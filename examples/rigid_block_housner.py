"""A rigid block released from a tilt theta0 = alpha / 2 with no ground
motion: the time to its first impact against Housner's (1963) closed form.
The block's energy gives (1/2) J_p th'^2 = m g R (cos(alpha - theta0) -
cos(alpha - theta)), so the fall to theta = 0 takes
    t = (1/p) int_0^theta0 dth / sqrt(2 (cos(alpha - theta0) - cos(alpha - th))),
p^2 = m g R / J_p; linearised (small alpha), t = (1/p) arccosh(1 / (1 - theta0 / alpha)).
Exits 1 if the simulated impact misses the exact time by more than 1e-6 s.

    python3 examples/rigid_block_housner.py [--out DIR]
"""
import argparse
import pathlib
import sys

import numpy as np

import rocking

here = pathlib.Path(__file__).resolve().parent
parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--out", default="out/examples")
args = parser.parse_args()

block = rocking.Scene.load(here.parent / "data" / "scenes" / "rigid_block.toml")
geometry = rocking.modal(block)  # a rigid block: mass, J_p, R, p, alpha_cg, ...
alpha, p = geometry["alpha_cg"], geometry["p"]
theta0 = 0.5 * alpha
block.set("excitation.kind", "none").set("excitation.duration", 3.0).set("initial.theta", theta0)
run = rocking.simulate(block, rtol=1e-10, atol=1e-13)
impact = next(e["t"] for e in run.events if e["kind"] == "impact")

# theta = theta0 - s^2 takes the 1/sqrt singularity at theta0 out of the integral.
s, w = np.polynomial.legendre.leggauss(64)
s = 0.5 * np.sqrt(theta0) * (s + 1)
w = 0.5 * np.sqrt(theta0) * w
drop = np.cos(alpha - theta0) - np.cos(alpha - theta0 + s**2)
exact = np.sum(w * 2 * s / np.sqrt(2 * drop)) / p
linear = np.arccosh(1 / (1 - theta0 / alpha)) / p

print(f"{block.name}: alpha_cg {alpha:.4f} rad, p {p:.4f} rad/s, released from theta0 = alpha/2")
print(f"  first impact, simulated       {impact:.9f} s")
print(f"  Housner, exact (quadrature)   {exact:.9f} s  (difference {impact - exact:.1e} s)")
print(f"  Housner, linearised           {linear:.9f} s")
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)
(out / "rigid_block_housner.txt").write_text(f"simulated {impact!r}\nexact {exact!r}\nlinearised {linear!r}\n")
sys.exit(0 if abs(impact - exact) < 1e-6 else 1)
