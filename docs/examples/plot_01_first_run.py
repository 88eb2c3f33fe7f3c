"""
A first run and its plot
========================

Kane & Levinson's rattleback (1 kg, an ellipsoid of semi-axes 0.20, 0.03, 0.02 m with
its centre of mass 1 cm below the centre) is tilted (Euler angles α = β = 0.5°) and spun at
ω₃ = −5 rad/s about the vertical, the "wrong" way. Rolling without sliding, it
conserves energy: the spin turns into rocking, and at about 2.8 s the stone spins
the other way. ``Trajectory.plot()`` draws the spin, the tilt, the energy
and the normal force against time.
"""

import celtstone as cs

body = cs.load_body("kane_levinson_1982")
state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
run = cs.simulate(cs.RollingModel(), body, state, t_end=5.0)

# %%
# The summary holds the numbers behind the figure, in SI units: the first reversal
# time [s], the initial and final spin [rad/s], the energies [J].
summary = run.summary()
for key in ("first_reversal_time", "spin_initial", "spin_final", "max_relative_energy_drift"):
    print(f"{key:>28}: {summary[key]}")

# %%
figure = run.plot()
