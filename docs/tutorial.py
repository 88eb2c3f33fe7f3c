# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#       jupytext_version: 1.19.6
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Tutorial: the rattleback, from a first spin to a sweep
#
# A **rattleback** (Celt stone) is a convex rigid body, often a half-ellipsoid, on a
# horizontal plane. Its principal axes of inertia are turned against the axes of its
# curved surface, and that misalignment couples spin and rocking: spun one way it
# spins on; spun the other ("wrong") way it starts to rock, stops spinning and spins
# back. Energy conservation does not forbid it: the contact force acts at a point off
# the vertical through the centre of mass, so it has a moment about the vertical whose
# sign follows the rocking, and the misalignment turns rocking into spin.
#
# This notebook walks through it with `celtstone` in SI units (m, kg, s, rad, J):
#
# 1. a body and why one sense of spin is unstable;
# 2. a run that rolls without sliding;
# 3. a run that slides, with dry friction at the contact, and its energy budget;
# 4. a small sweep over friction and spin.
#
# Each run is a few seconds of simulated time. The first run of each model compiles
# its kernels (a minute or two, once; cached afterwards).

# %%
# %matplotlib inline
import numpy as np

import celtstone as cs
from celtstone.plotting import plot_energy_budget
from celtstone.plotting.maps import plot_field_map
from celtstone.sweep import Sweep

# %% [markdown]
# ## 1. A body, and the stability of steady spin
#
# Kane & Levinson's (1982) rattleback: 1 kg, an ellipsoid of semi-axes
# 0.20 × 0.03 × 0.02 m, the centre of mass 1 cm below the centre, and a product of
# inertia I₁₂ = −2e-5 kg m² that turns the principal axes by a few degrees.

# %%
body = cs.load_body("kane_levinson_1982")
print(body.mass, "kg")
print(np.asarray(body.inertia), "kg m²")
print(body.shape)

# %% [markdown]
# Linearising the rolling model about steady spin at rate s [rad/s] gives eigenvalues
# whose positive real parts are growth rates [1/s] of the rocking. One sense of spin
# has a growth rate more than ten times the other's: spun that way the stone rocks at
# once.

# %%
stability = cs.spin_stability(body, np.linspace(-10.0, 10.0, 101))
print("preferred sense of spin:", stability.preferred_direction)
print(f"largest growth rate for s < 0: {stability.max_growth_rate_negative:.2f} 1/s")
print(f"largest growth rate for s > 0: {stability.max_growth_rate_positive:.2f} 1/s")

# %% [markdown]
# ## 2. Rolling without sliding
#
# Start tilted by two Euler angles α = β = 0.5° and spinning at ω₃ = −5 rad/s, the
# unstable sense. The contact point does not slip, so energy is conserved: the spin
# turns into rocking and back into spin of the other sense.

# %%
state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
rolling = cs.simulate(cs.RollingModel(), body, state, t_end=4.0)
summary = rolling.summary()
print("first reversal [s]:", summary["first_reversal_time"])
print("spin at the start and the end [rad/s]:", summary["spin_initial"], summary["spin_final"])
print("relative energy drift:", summary["max_relative_energy_drift"])

# %% [markdown]
# `rolling.dataset` is an xarray `Dataset` of every variable against time;
# `rolling.plot()` draws the main ones.

# %%
rolling.plot()

# %% [markdown]
# ## 3. Rolling with sliding, and where the energy goes
#
# A real contact slides and pivots. The sliding model applies dry friction of
# coefficient f on a small contact disk of radius ε (Zhuravlev's Padé form of the
# Coulomb–Contensou law), here f = 0.35 and ε = 1 mm, loaded with the true normal force N
# (`friction_load="dynamic"`). The paper loads it, as a first approximation, with the
# weight m g; while the stone rocks N falls below m g, so that friction can exceed
# Coulomb's bound f N, and `celtstone` warns when it does. Friction does work W ≥ 0, so
# the energy E falls: E(0) − E(t) = W(t), and the residual of that budget is the
# integrator's error.

# %%
sliding_model = cs.SlidingModel(
    friction_coefficient=0.35, contact_radius=1e-3, friction_load="dynamic"
)
sliding = cs.simulate(sliding_model, body, state, t_end=4.0)
s = sliding.summary()
print("first reversal [s]:", s["first_reversal_time"])
print(f"energy: {s['energy_initial']:.5f} J -> {s['energy_final']:.5f} J")
print(f"friction work W: {s['dissipated_work']:.5f} J")

# %%
plot_energy_budget([rolling.dataset, sliding.dataset], "Energy budget: rolling and sliding")

# %% [markdown]
# The rolling run keeps its energy (W = 0); the sliding one loses a few hundredths of a
# joule to friction, and the residual stays many orders of magnitude below it.

# %% [markdown]
# ## 4. A small sweep
#
# Does the stone still reverse with less friction, or spun more slowly? A `Sweep` runs
# every combination of its axes in compiled batches (here 3 × 3 runs of 2 s of the
# stick–slip contact, which sticks when the slip stops) and returns one field per
# result, here the spin at the end of each run.

# %%
sweep = Sweep(
    {"friction_coefficient": [0.1, 0.25, 0.4], "initial_spin": [-6.0, -4.5, -3.0]}, t_end=2.0
)
results = sweep.run(workers=1)
results["spin_final"].round(2).to_pandas()

# %%
plot_field_map(results, "spin_final")

# %% [markdown]
# Where next: the gallery has the friction threshold, custom bodies and the two friction
# laws; `celtstone reproduce` reruns the paper's figures; the API reference lists every
# public name.
