"""Hostile property test: random bodies, models and starts thrown at ``simulate``.

Whatever comes in, the outcome is clean: a one-line :class:`ParameterError` before any
integration, or a run that reports a known status, whose samples are finite when it
succeeds, whose |n| stays 1, and which never leaks a NumPy warning (pytest turns every
warning into an error; implausible-input warnings are celtstone's own and allowed).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from hypothesis import example, given
from hypothesis import strategies as st

import celtstone as cs
from celtstone.simulation.integrate import STATUS_NAMES

# log10 ranges of the body: hostile on purpose, far beyond any stone
lengths = st.floats(-4.0, 2.0)  # m: 0.1 mm .. 100 m
masses = st.floats(-12.0, 12.0)  # kg
spins = st.floats(-30.0, 30.0)  # rad/s
tilts = st.floats(-60.0, 60.0)  # deg


@st.composite
def bodies(draw: st.DrawFn) -> cs.Body:
    """An ellipsoid with G on axis 3 and the inertia tensor of a mass distribution,
    misaligned from the shape's axes by an angle in the horizontal plane."""
    a = 10.0 ** draw(lengths)
    b = a * draw(st.floats(0.05, 1.0))
    c = b * draw(st.floats(0.05, 1.0))
    offset = c * draw(st.floats(-0.95, 0.95))
    mass = 10.0 ** draw(masses)
    # second moments Sx, Sy, Sz of a mass distribution about G: the principal moments
    # Sy + Sz, Sx + Sz, Sx + Sy always obey the triangle inequality
    spread = 10.0 ** draw(st.floats(-2.0, 2.0))  # gyration radius / size, hostile range
    sx, sy, sz = (mass * (spread * d * draw(st.floats(0.05, 1.0))) ** 2 for d in (a, b, c))
    first, second, third = sy + sz, sx + sz, sx + sy
    angle = draw(st.floats(-0.7, 0.7))
    rotation = np.array(
        [
            [math.cos(angle), -math.sin(angle), 0.0],
            [math.sin(angle), math.cos(angle), 0.0],
            [0, 0, 1],
        ]
    )
    inertia = rotation @ np.diag([first, second, third]) @ rotation.T
    inertia = (inertia + inertia.T) / 2.0
    return cs.Body(
        name="random",
        mass=mass,
        inertia=tuple(tuple(float(v) for v in row) for row in inertia),  # type: ignore[arg-type]
        shape=cs.Ellipsoid((a, b, c), offset),
        gravity=10.0 ** draw(st.floats(-1.0, 2.0)),
    )


models = st.one_of(
    st.builds(cs.RollingModel, damping=st.sampled_from([0.0, 1e-6, 1e-4])),
    st.builds(
        cs.SlidingModel,
        friction_coefficient=st.floats(0.0, 2.0),
        contact_radius=st.floats(1e-5, 5e-3),
        friction_load=st.sampled_from(["static", "dynamic"]),
        friction_law=st.sampled_from(["pade", "exact"]),
    ),
)


@given(
    body=bodies(),
    model=models,
    omega=st.tuples(spins, spins, spins),
    euler_angles=st.tuples(tilts, tilts),
)
@example(  # mass 1e300 with the rolling model ended as friction_singular with NaN before
    body=cs.Body(
        name="heavy",
        mass=1e300,
        inertia=((2.0e-4, -2.0e-5, 0.0), (-2.0e-5, 1.6e-3, 0.0), (0.0, 0.0, 1.7e-3)),
        shape=cs.Ellipsoid((0.2, 0.03, 0.02), 0.01),
    ),
    model=cs.RollingModel(),
    omega=(0.0, 0.0, -5.0),
    euler_angles=(0.5, 0.5),
)
def test_any_input_ends_cleanly(
    body: cs.Body,
    model: cs.Model,
    omega: tuple[float, float, float],
    euler_angles: tuple[float, float],
) -> None:
    state = cs.InitialState(omega, euler_angles)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cs.PlausibilityWarning)
        try:
            run = cs.simulate(model, body, state, 0.3, max_steps=20_000, n_samples=31)
        except cs.ParameterError as error:
            assert "\n" not in str(error)
            return
    assert run.status in STATUS_NAMES.values()
    data = run.dataset
    assert data.sizes["time"] >= 1
    n = data["n"].values
    assert np.all(np.isfinite(n))
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-6)
    if run.ok:
        assert data["time"].values[-1] == 0.3
        for name in ("spin", "energy", "normal_force", "omega", "tilt"):
            assert np.all(np.isfinite(data[name].values)), name
        assert run.summary()["status"] == "success"
    else:
        assert run.message.startswith("stopped at t = ")
