"""Draw the figures of the front pages: ``docs/_static/spin_reversal.png`` (the README and
the docs' landing page) and ``docs/_static/first_plot.png`` (Getting started's first plot).

Kane & Levinson's rattleback, tilted by α = β = 0.5° and spun at ω₃ = −5 rad/s (the
"wrong" way): its spin ω·n [rad/s] against time [s], rolling without sliding and rolling
with sliding (f = 0.35 on a contact disk of radius 1 mm, the consistent friction load).
Run ``python docs/_static/make_spin_figure.py`` after a change that moves these curves;
``tests/test_docs.py`` runs :func:`draw` to check that it still draws.
"""

from __future__ import annotations

import sys
from pathlib import Path

import celtstone as cs

FIGURE = Path(__file__).with_name("spin_reversal.png")
FIRST_PLOT = Path(__file__).with_name("first_plot.png")
T_END = 10.0  # s


def draw(path: Path = FIGURE, first_plot: Path = FIRST_PLOT) -> Path:
    """Run both models, write the figure to ``path`` (PNG, 900 × 360 pixels) and the
    rolling run's ``Trajectory.plot()`` to ``first_plot``."""
    from matplotlib.figure import Figure

    body = cs.load_body("kane_levinson_1982")
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
    sliding_model = cs.SlidingModel(
        friction_coefficient=0.35, contact_radius=1e-3, friction_load="dynamic"
    )
    runs = {
        "rolling without sliding": cs.simulate(cs.RollingModel(), body, state, T_END),
        "rolling with sliding, f = 0.35": cs.simulate(sliding_model, body, state, T_END),
    }
    figure = Figure(figsize=(9.0, 3.6), dpi=100, layout="constrained")
    axes = figure.add_subplot()
    for (label, run), colour in zip(runs.items(), ("#1f77b4", "#d62728"), strict=True):
        dataset = run.raise_for_status().dataset
        axes.plot(dataset["time"], dataset["spin"], color=colour, linewidth=1.0, label=label)
    axes.axhline(0.0, color="0.5", linewidth=0.6)
    axes.set_xlim(0.0, T_END)
    axes.set_xlabel("time t [s]")
    axes.set_ylabel("spin ω·n [rad/s]")
    axes.set_title("Kane & Levinson's rattleback, spun the wrong way, spins back")
    figure.legend(loc="outside right upper", frameon=False)
    figure.savefig(path)
    runs["rolling without sliding"].plot().savefig(first_plot, dpi=80)
    return path


if __name__ == "__main__":
    print(draw(*[Path(argument) for argument in sys.argv[1:3]]))
