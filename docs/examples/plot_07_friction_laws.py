"""
The exact friction law against Padé's
=====================================

Dry friction on a contact disk of radius ε with the Hertz pressure: when the contact
both slides (speed V) and pivots (spin Ωₙ), the friction force F and the pivoting
moment M depend on the slip ratio u = V / (ε Ωₙ) of the magnitudes alone. The exact
Coulomb–Contensou law is an integral over the disk; Zhuravlev's Padé approximation is a
rational function of u with the same limits (u → 0: pure pivoting, u → ∞: pure
sliding) that parts from it by up to a third of f N in between. The figure gives
F / (f N) and M / (f N ε) [1], the same functions ``celtstone friction`` prints and a
run uses.
"""

import numpy as np

from celtstone.contact.laws import friction_functions
from celtstone.plotting.friction import friction_law_figure

u = np.geomspace(1e-3, 1e3, 121)
laws = {law: friction_functions(u, law=law) for law in ("exact", "pade")}
force_gap = np.max(np.abs(laws["exact"][0] - laws["pade"][0]))
moment_gap = np.max(np.abs(laws["exact"][1] - laws["pade"][1]))
print(f"largest difference: force {force_gap:.3f} f N, moment {moment_gap:.3f} f N ε")

# %%
figure = friction_law_figure("hertz")
