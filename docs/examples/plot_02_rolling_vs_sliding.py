"""
Rolling against sliding
=======================

The same start (tilt 0.5 rad, ω₃ = −5 rad/s) rolling without sliding and rolling with
sliding: dry friction of coefficient f = 0.35 on a Hertz contact disk of radius
ε = 1 mm, Zhuravlev's Padé law, normal force N = m g (the paper's first
approximation). Sliding dissipates energy, the friction work W [J], and the reversal
comes later and weaker.
"""

import celtstone as cs
from celtstone.plotting import plot_spin_comparison

body = cs.load_body("kane_levinson_1982")
state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
rolling = cs.simulate(cs.RollingModel(), body, state, t_end=4.0)
sliding_model = cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3)
sliding = cs.simulate(sliding_model, body, state, t_end=4.0)

for name, run in (("rolling", rolling), ("sliding", sliding)):
    s = run.summary()
    print(
        f"{name:>8}: first reversal {s['first_reversal_time']} s, W = {s['dissipated_work']:.3g} J"
    )

# %%
figure = plot_spin_comparison(
    [[rolling.dataset], [sliding.dataset]], "Spin, rolling (left) and sliding f = 0.35 (right)"
)
