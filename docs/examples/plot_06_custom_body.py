"""
A body of your own: a TOML file and an implicit polynomial
==========================================================

A body is a mass [kg], a central inertia tensor [kg m²] in body axes and a convex
surface [m]. Here it is written as a TOML file (the format of the shipped bodies,
``docs/bodies.md``) into a temporary directory and loaded by path, and then the same
inertia is given an egg-shaped surface, the implicit polynomial
x²/a² + y²/b² + z²/c² + 0.3 z³/c³ + 0.1 z⁴/c⁴ = 1 (a, b, c = 0.20, 0.03, 0.02 m).
Both roll for 3 s from Euler angles α = β = 0.5° and ω₃ = −5 rad/s.
"""

import tempfile
from pathlib import Path

from matplotlib.figure import Figure

import celtstone as cs

TOML = """
title = "A rattleback of my own"

[body]
mass = 1.0
inertia = [[2.0e-4, -2.0e-5, 0.0], [-2.0e-5, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]

[shape]
kind = "ellipsoid"
semi_axes = [0.20, 0.03, 0.02]
com_offset = 0.01
"""

with tempfile.TemporaryDirectory() as folder:
    path = Path(folder) / "my_rattleback.toml"
    path.write_text(TOML, encoding="utf-8")
    ellipsoid_body = cs.load_body(path)
print(ellipsoid_body.name, ellipsoid_body.mass, "kg,", ellipsoid_body.shape)

# %%
# The egg: coefficients c in m^−(i+j+k) of the terms c x^i y^j z^k.
egg = cs.ImplicitPolynomial(
    terms=[
        (25.0, 2, 0, 0),
        (1111.111, 0, 2, 0),
        (2500.0, 0, 0, 2),
        (37500.0, 0, 0, 3),
        (625000.0, 0, 0, 4),
    ],
    com_offset=0.01,
)
egg_body = cs.Body(name="egg", mass=ellipsoid_body.mass, inertia=ellipsoid_body.inertia, shape=egg)

state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
runs = {
    "ellipsoid (TOML file)": cs.simulate(cs.RollingModel(), ellipsoid_body, state, 3.0),
    "egg (implicit polynomial)": cs.simulate(cs.RollingModel(), egg_body, state, 3.0),
}

# %%
figure = Figure(figsize=(7.0, 3.6), layout="constrained")
axes = figure.add_subplot()
for label, run in runs.items():
    axes.plot(run.dataset["time"], run.dataset["spin"], label=label)
axes.set_xlabel("time [s]")
axes.set_ylabel("spin ω · n [rad/s]")
axes.legend()
axes.grid(alpha=0.3)
