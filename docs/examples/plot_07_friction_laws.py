"""
The exact friction law against Padé's
=====================================

Dry friction on a contact disk of radius ε with the Hertz pressure: when the contact
both slides (speed V) and pivots (spin Ωₙ), the friction force F and the pivoting
moment M depend on the slip ratio u = V / (ε Ωₙ) of the magnitudes alone. The exact
Coulomb–Contensou law is an integral over the disk; Zhuravlev's Padé approximation is a
rational function of u with the same limits (u → 0: pure pivoting, u → ∞: pure
sliding). The figure gives F / (f N) and M / (f N ε) [1], the same functions
``celtstone friction`` prints and a run uses.
"""

import numpy as np
from matplotlib.figure import Figure

from celtstone.contact.laws import friction_functions

u = np.geomspace(1e-3, 1e3, 121)
laws = {law: friction_functions(u, law=law) for law in ("exact", "pade")}
force_gap = np.max(np.abs(laws["exact"][0] - laws["pade"][0]))
moment_gap = np.max(np.abs(laws["exact"][1] - laws["pade"][1]))
print(f"largest difference: force {force_gap:.4f}, moment {moment_gap:.4f} (in f N, f N ε)")

# %%
figure = Figure(figsize=(10.0, 3.8), layout="constrained")
force_axes, moment_axes = figure.subplots(1, 2, sharex=True)
for law, style in (("exact", "-"), ("pade", "--")):
    force, moment = laws[law]
    force_axes.semilogx(u, force, style, label=law)
    moment_axes.semilogx(u, moment, style, label=law)
force_axes.set_ylabel("friction force |F| / (f N)")
moment_axes.set_ylabel("pivoting moment |M| / (f N ε)")
for axes in (force_axes, moment_axes):
    axes.set_xlabel("slip ratio u = |V| / (ε |Ωₙ|)")
    axes.grid(alpha=0.3)
    axes.legend()
