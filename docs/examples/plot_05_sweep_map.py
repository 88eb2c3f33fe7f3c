"""
A small sweep map
=================

A sweep runs every combination of its axes in compiled batches. Here 4 × 4 points:
friction coefficient f in [0.05, 0.35] against the initial spin ω₃ in [−6, −3] rad/s,
each a run of 2 s of the stick–slip contact (disk of radius 1 mm, Padé law, N = m g),
held in memory (``run()`` without a store; give a path to write Zarr). The map shows
the spin at the end of each run [rad/s]: positive where the stone has already turned
back.
"""

import numpy as np

from celtstone.plotting.maps import plot_field_map
from celtstone.sweep import Sweep

sweep = Sweep(
    {
        "friction_coefficient": np.linspace(0.05, 0.35, 4),
        "initial_spin": np.linspace(-6.0, -3.0, 4),
    },
    t_end=2.0,
)
print(f"{sweep.size} points, dimensions {sweep.dims}")
results = sweep.run(workers=1)
print(results["spin_final"].round(2).to_pandas())

# %%
figure = plot_field_map(results, "spin_final")
