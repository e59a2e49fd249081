"""Writes data/scenes/towers/tower_N.toml: the Christchurch chimney's height,
mass and mean stiffness spread evenly over N lumped masses (issue 20's towers),
with the chimney's base, contact, damping and dampers. The same spreading as
tests/spread_nodes.hpp: heights i H / N, masses M / N, every element the mean
second moment.

    python3 scripts/make_towers.py [N ...]      (default: 8 16 32 64 128)
"""
import pathlib
import sys

here = pathlib.Path(__file__).resolve().parent.parent
height, masses = 33.05, [78600.0, 60800.0, 53800.0, 31000.0]
second_moments = [9.84, 4.03, 3.45, 3.01]
counts = [int(n) for n in sys.argv[1:]] or [8, 16, 32, 64, 128]
out = here / "data" / "scenes" / "towers"
out.mkdir(parents=True, exist_ok=True)


def numbers(values):
    return "[" + ", ".join(repr(v) for v in values) + "]"


for n in counts:
    mass, inertia = sum(masses) / n, sum(second_moments) / len(second_moments)
    text = f'''# Written by scripts/make_towers.py: do not edit, rerun it.
[scene]
name = "tower, {n} nodes"
description = """\\
The Christchurch chimney's height ({height} m), mass and mean stiffness spread evenly \\
over {n} lumped masses, with its base, contact, damping and dampers. Shaken by the \\
chimney's one-sine pulse (0.35 g, 0.6 s) unless a record is chosen; more nodes \\
show more of the bending, at a higher cost of computing."""

[structure]
half_width = 3.3
heights = {numbers([height * (i + 1) / n for i in range(n)])}
masses = {numbers([mass] * n)}
base_mass = 62400.0
second_moments = {numbers([inertia] * n)}
youngs_modulus = 20.0e9
damping_ratio = 0.035

[contact]
rocking = true
restitution = 0.94
theta_dot_min = 0.0015

[damper]
enabled = true
stiffness = 1.0e7
post_yield_ratio = 0.06
theta_y = 2.8e-3
alpha = 1.0
beta = 0.0
n = 1.0

[excitation]
kind = "pulse"
pulse = "one-sine"
amplitude_g = 0.35
period = 0.6
duration = 8.0
'''
    (out / f"tower_{n}.toml").write_text(text)
    print(f"wrote {out / f'tower_{n}.toml'}")
