"""
The friction threshold on a coarse grid
=======================================

How much friction does the reversal need? Seven friction coefficients f from 0.05 to
0.35, each a run of 5 s with the stick–slip contact (a disk of radius 1 mm, Padé law,
N = m g) from Euler angles α = β = 0.5° and ω₃ = −5 rad/s. Without enough friction the stone slides
instead of rolling and does not spin back within the run; the left panel marks those
runs with a cross. ``celtstone reproduce threshold`` bisects the boundary on a 49-point
grid; this is its seven-point sketch.
"""

import numpy as np
import pandas as pd

import celtstone as cs
from celtstone.plotting import plot_threshold
from celtstone.sweep import Sweep

body = cs.load_body("kane_levinson_1982")
frictions = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35]
results = Sweep(
    {"friction_coefficient": frictions},
    body=body,
    fixed={"initial_spin": -5.0, "contact": "hybrid"},
    t_end=5.0,
).run(workers=1)

table = pd.DataFrame(
    {
        "friction_coefficient": frictions,
        "first_reversal_time": results["first_reversal_time"].values,
        "energy_final": (results["energy_initial"] - results["energy_lost"]).values,
        "energy_rest": body.mass * body.gravity * body.shape.rest_height,
    }
)
print(table.to_string(index=False))

# %%
figure = plot_threshold(table, "Threshold sketch: Kane & Levinson, runs of 5 s")
assert np.isfinite(table["first_reversal_time"]).any()
