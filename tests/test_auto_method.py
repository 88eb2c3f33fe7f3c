"""The switching method ``auto`` (``solvers._auto``): DOP853 where nothing is stiff, Radau
where the friction law makes it so, and the same answers as either."""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from celtstone import solvers
from celtstone.kernels import layout
from celtstone.simulation.models import initial_vector, kernel_parameters
from celtstone.solvers import _auto

BODY = "kane_levinson_1982"


def _problem(model: cs.RollingModel | cs.SlidingModel, spin: float) -> tuple[np.record, np.ndarray]:
    state = cs.InitialState((0.0, 0.0, spin), (0.5, 0.5))
    return kernel_parameters(model, cs.load_body(BODY)), initial_vector(state)


def _solve(model: int, method: str, params, y0, t_end: float, **options) -> solvers.RawSolution:  # type: ignore[no-untyped-def]
    options = {"rtol": 1e-8, "atol": 1e-12, **options}
    times = np.linspace(0.0, t_end, 201)
    return solvers.solve(model, method, params, y0, t_end, sample_times=times, **options)


@pytest.mark.parametrize(
    ("matrix", "expected"),
    [
        (np.diag([-1e6, -1.0, -2.0]), 1e6),  # a stiff real mode
        (np.array([[0.0, 200.0, 0.0], [-200.0, 0.0, 0.0], [0.0, 0.0, -1.0]]), 200.0),  # rocking
        (np.zeros((4, 4)), 0.0),
    ],
)
def test_the_spectral_radius_estimate_finds_the_dominant_mode(
    matrix: np.ndarray, expected: float
) -> None:
    n = matrix.shape[0]
    estimate = _auto.spectral_radius(np.ascontiguousarray(matrix), n, np.empty(n), np.empty(n))
    assert estimate == pytest.approx(expected, rel=0.1, abs=1e-12)


def test_the_spectral_radius_estimate_is_within_a_factor_of_numpys() -> None:
    """Random 9 x 9 matrices with eigenvalues spread over four decades, as a sliding
    Jacobian's: the estimate is a switching threshold's input and needs the magnitude."""
    rng = np.random.default_rng(2026_11_26)
    for _ in range(20):
        basis = rng.normal(size=(9, 9))
        values = -np.logspace(0, 4, 9) * rng.uniform(0.5, 1.0, 9)
        matrix = basis @ np.diag(values) @ np.linalg.inv(basis)
        exact = np.max(np.abs(np.linalg.eigvals(matrix)))
        estimate = _auto.spectral_radius(matrix, 9, np.empty(9), np.empty(9))
        assert exact / 2 < estimate < 2 * exact


def test_where_nothing_is_stiff_auto_takes_dop853s_steps_exactly() -> None:
    """Rolling, and sliding at low friction (the slip law barely stiff): no switch, no
    Radau step, every sample bit for bit DOP853's (its Jacobian checks change nothing)."""
    for model, spin, t_end in (
        (cs.RollingModel(), -5.0, 5.0),
        (cs.SlidingModel(0.02, 1e-3), 8.0, 2.0),
    ):
        params, y0 = _problem(model, spin)
        auto = _solve(model.code, "auto", params, y0, t_end)
        explicit = _solve(model.code, "dop853", params, y0, t_end)
        assert auto.status == explicit.status == solvers.STATUS_SUCCESS
        assert auto.n_switches == 0 and auto.n_radau_steps == 0
        assert auto.n_accepted == explicit.n_accepted
        np.testing.assert_array_equal(auto.samples, explicit.samples)
        np.testing.assert_array_equal(auto.crossings, explicit.crossings)
        assert auto.njev > 0  # it did look: ρ every CHECK_STEPS steps


def test_a_stiff_stretch_goes_to_radau_and_the_answer_is_radaus() -> None:
    """f = 0.45, spin 4 rad/s: the stone stops spinning within 10 s and the slip law
    turns stiff (λ ~ f N / (b ε |ω·n| + δ)). auto hands that stretch to Radau, agrees with
    radau5 to the tolerance, and costs far fewer evaluations than DOP853 alone, which
    crawls at its stability limit (it is stopped at ten times auto's steps)."""
    params, y0 = _problem(cs.SlidingModel(0.45, 1e-3), 4.0)
    t_end = 10.0
    auto = _solve(layout.MODEL_SLIDING, "auto", params, y0, t_end)
    implicit = _solve(layout.MODEL_SLIDING, "radau5", params, y0, t_end)
    assert auto.status == implicit.status == solvers.STATUS_SUCCESS
    assert auto.n_switches >= 1
    assert 0 < auto.n_radau_steps < auto.n_accepted
    assert implicit.n_radau_steps == implicit.n_accepted and implicit.n_switches == 0
    np.testing.assert_allclose(auto.samples, implicit.samples, rtol=0, atol=2e-6)
    explicit = _solve(
        layout.MODEL_SLIDING, "dop853", params, y0, t_end, max_steps=10 * auto.n_accepted
    )
    assert explicit.status == solvers.STATUS_MAX_STEPS or explicit.nfev > 3 * auto.nfev


def test_a_run_that_starts_stiff_switches_after_its_first_step() -> None:
    """Spin 0.05 rad/s at f = 0.5: stiff from t = 0 (λ ~ 1e5 1/s). The first check, after
    the first accepted step, hands the run to Radau."""
    params, y0 = _problem(cs.SlidingModel(0.5, 1e-3), 0.05)
    raw = _solve(layout.MODEL_SLIDING, "auto", params, y0, 0.05)
    assert raw.status == solvers.STATUS_SUCCESS
    assert raw.n_switches >= 1
    assert raw.n_radau_steps >= raw.n_accepted - _auto.CHECK_STEPS * raw.n_switches


def test_fixed_steps_never_switch() -> None:
    params, y0 = _problem(cs.SlidingModel(0.5, 1e-3), 0.05)
    raw = _solve(layout.MODEL_SLIDING, "auto", params, y0, 1e-3, first_step=1e-5, adaptive=False)
    assert raw.n_switches == 0 and raw.n_radau_steps == 0


def test_the_sliding_models_default_to_auto_and_report_their_switches() -> None:
    """``simulate`` and a hybrid run: the slip phases' method is auto unless asked for,
    and the run's statistics carry the switches and Radau's share of the steps."""
    body = cs.load_body(BODY)
    state = cs.InitialState((0.0, 0.0, 4.0), (0.5, 0.5))
    for model in (cs.SlidingModel(0.45, 1e-3), cs.HybridModel(0.45, 1e-3)):
        run = cs.simulate(model, body, state, 3.0)
        assert run.dataset.attrs["method"] == "auto"
        assert set(solvers.STATISTICS) <= set(run.statistics)
        assert run.statistics["n_radau_steps"] <= run.statistics["n_accepted"]
    assert cs.SlidingModel.default_method == "auto"


def test_stick_slip_chatter_costs_auto_no_more_than_radau() -> None:
    """f = 0.5, spin −5.71 rad/s, stick–slip contact, 10 s: the spin dies, then the
    stone sticks and slips at every rocking half-period (51 stick phases), and every
    slip phase is stiff. auto must not cost more evaluations than Radau there (a
    version that judged DOP853 cheap on Radau's short first steps took 1.8e7 evaluations
    against Radau's 1.1e6), and must give the same answer."""
    body = cs.load_body(BODY)
    unit = cs.InitialState((0.0, 0.0, 1.0), (0.5, 0.5))
    state = cs.InitialState((0.0, 0.0, -5.714285714285714 / unit.vertical[2]), (0.5, 0.5))
    model = cs.HybridModel(0.5, 1e-3)
    runs = {
        method: cs.simulate(model, body, state, 10.0, rtol=1e-8, atol=1e-12, method=method)
        for method in ("radau5", "auto")
    }
    auto, implicit = runs["auto"], runs["radau5"]
    assert auto.summary()["stick_phases"] >= 20
    assert auto.statistics["n_switches"] > 0
    assert auto.statistics["nfev"] <= 1.2 * implicit.statistics["nfev"]
    assert abs(auto.summary()["spin_final"] - implicit.summary()["spin_final"]) < 1e-5
