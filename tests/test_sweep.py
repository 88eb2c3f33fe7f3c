"""Sweeps: parameter names and parsing, the batch driver against single runs, physics, CLI."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.cli.main import main
from celtstone.simulation.outcome import SWEPT
from celtstone.simulation.reversals import dataset_reversal_times
from celtstone.sweep import Sweep, open_sweep, parse_axis, parse_setting
from celtstone.sweep.plots import DEFAULT_MAPPED_FIELDS
from celtstone.sweep.spec import build_body, build_state
from tests.conftest import LITERATURE_EULER_ANGLES

# --------------------------------------------------------------------------- spec


def test_range_and_list_axes() -> None:
    axis = parse_axis("friction_coefficient=0.02:0.5:5")
    assert axis.name == "friction_coefficient"
    np.testing.assert_array_equal(axis.values, np.linspace(0.02, 0.5, 5))
    assert parse_axis("initial_spin=-8,0,8").values == (-8.0, 0.0, 8.0)
    assert parse_axis("contact-radius=0.001").values == (0.001,)
    assert parse_setting("friction_load=dynamic") == ("friction_load", "dynamic")


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("fricton_coefficient=0:1:3", "did you mean 'friction_coefficient'"),
        ("initial_spin=1:2", "START:STOP:COUNT"),
        ("initial_spin=1:2:2.5", "whole number"),
        ("initial_spin=1:2:0", "whole number"),
        ("initial_spin=a,b", "a number"),
        ("initial_spin=1,nan", "finite"),
        ("initial_spin", "NAME=START:STOP:COUNT"),
    ],
)
def test_bad_axes_name_the_problem(text: str, match: str) -> None:
    with pytest.raises(cs.ParameterError, match=match):
        parse_axis(text)


def test_invalid_point_fails_before_anything_is_computed(tmp_path) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(cs.ParameterError, match=r"friction_coefficient.*>= 0.*at sweep point 1"):
        Sweep({"friction_coefficient": [0.1, -0.2]})
    # a body made impossible by one combination: G outside the ellipsoid (|h| < c)
    with pytest.raises(cs.ParameterError, match=r"com_offset.*semi_axis_c=0\.005"):
        Sweep({"semi_axis_c": [0.02, 0.005]}, model="rolling")
    with pytest.raises(cs.ParameterError, match="rolling model"):
        Sweep({"friction_coefficient": [0.1]}, model="rolling")
    with pytest.raises(cs.ParameterError, match=r"omega3.*not together with initial_spin"):
        Sweep({"initial_spin": [1.0]}, fixed={"omega3": 2.0})
    with pytest.raises(cs.ParameterError, match="paraboloid"):
        Sweep({"semi_axis_a": [0.2]}, body="kane_levinson_1982_paraboloid", model="rolling")
    code = main(
        ["sweep", "--vary", "initial_spin=1,2", "--set", "mass=-1", "--out", str(tmp_path / "s")]
    )
    assert code == 2
    assert not (tmp_path / "s").exists()


def test_misalignment_angle_turns_the_principal_axes(kane_levinson: cs.Body) -> None:
    angle = math.radians(2.0)
    body = build_body(kane_levinson, {"misalignment_angle": angle})
    assert body.misalignment_angle == pytest.approx(angle, abs=1e-12)
    np.testing.assert_allclose(
        np.linalg.eigvalsh(body.inertia_array), np.linalg.eigvalsh(kane_levinson.inertia_array)
    )
    same = build_body(kane_levinson, {"misalignment_angle": kane_levinson.misalignment_angle})
    np.testing.assert_allclose(same.inertia_array, kane_levinson.inertia_array, atol=1e-18)


def test_spin_is_the_initial_omega_dot_n() -> None:
    state = build_state(
        {"initial_spin": -5.0, "omega1": 0.3, "euler_alpha": 2.0, "euler_beta": -1.0}
    )
    assert np.dot(state.omega, state.vertical) == pytest.approx(-5.0, rel=1e-15)
    assert state.omega[:2] == (0.3, 0.0)


# --------------------------------------------------------------------------- batch driver


def test_sweep_points_equal_single_runs(kane_levinson: cs.Body) -> None:
    """With the regularised contact, each point equals simulate() + reversal_times() +
    summary() with the same samples, and the default band is the reproduction's
    (dataset_reversal_times)."""
    frictions, spins = [0.35, 0.5], [-5.0, 3.0]
    sweep = Sweep(
        {"friction_coefficient": frictions, "initial_spin": spins},
        fixed={"contact": "sliding"},
        t_end=2.5,
        rtol=1e-8,
    )
    results = sweep.run(workers=2, task_points=1)
    assert results["status"].dims == ("friction_coefficient", "initial_spin")
    for f in frictions:
        for spin in spins:
            state = build_state({"initial_spin": spin})
            run = cs.simulate(
                cs.SlidingModel(friction_coefficient=f),
                kane_levinson,
                state,
                2.5,
                rtol=1e-8,
                atol=1e-12,
            )
            _assert_point_is_the_run(
                results.sel(friction_coefficient=f, initial_spin=spin), run, spin
            )
    # f = 0.35 from w3 = -5 reverses once near 1.66 s (the paper's Figure 2 case, README)
    assert results["reversal_count"].sel(friction_coefficient=0.35, initial_spin=-5.0) == 1


def _assert_point_is_the_run(point: xr.Dataset, run: cs.Trajectory, spin: float) -> None:
    """The sweep's fields of ``point`` are the single run's outcome record, name for name
    (one declaration, one reduction); and that record is what NumPy reads from the run's
    saved samples (the independent check of the compiled reduction)."""
    outcome = run.outcome()
    assert set(SWEPT) <= set(point.data_vars) and set(outcome) == set(SWEPT)
    for name in SWEPT:
        np.testing.assert_array_equal(point[name].values, outcome[name], err_msg=name)
    ds = run.dataset
    # the default band: 4 % of the initial |spin| (0.2 and 0.12 rad/s here)
    band = 0.04 * abs(spin)
    reversals = cs.reversal_times(
        ds["time"].values, ds["spin"].values, band, run.spin_crossings, run.reversal_window
    )
    np.testing.assert_array_equal(reversals, dataset_reversal_times(ds))
    first = reversals[0] if reversals.size else np.nan
    np.testing.assert_array_equal(outcome["first_reversal_time"], first)
    assert outcome["reversal_count"] == reversals.size
    energy, work, spins = ds["energy"].values, ds["dissipated_work"].values, ds["spin"].values
    assert run.ok  # the values at t_end below are NaN for a run stopped early
    assert outcome["spin_final"] == spins[-1]
    assert outcome["energy_lost"] == energy[0] - energy[-1]
    assert outcome["max_tilt"] == np.max(ds["tilt"].values)
    normal = np.fmin(run.min_normal_force, np.nanmin(ds["normal_force"].values))
    assert outcome["min_normal_force"] == normal
    assert outcome["status"] == run.status
    assert outcome["t_stop"] == run.t_stop
    scale = 1e-12 * abs(energy[0])  # the energy's own rounding, sample by sample
    assert outcome["energy_initial"] == pytest.approx(energy[0], abs=scale)
    assert outcome["energy_final"] == pytest.approx(energy[-1], abs=scale)
    assert outcome["spin_initial"] == pytest.approx(spins[0], abs=1e-15 * abs(spins[0]))
    assert outcome["dissipated_work"] == work[-1]
    assert outcome["peak_reversed_spin"] == np.max(-np.sign(spins[0]) * spins)
    assert outcome["spin_crossing_count"] == run.spin_crossings.size
    balance = np.max(np.abs(energy[0] - energy - work))
    assert outcome["max_energy_balance_error"] == pytest.approx(balance, abs=scale)
    rise = max(float(np.max(np.diff(energy), initial=0.0)), 0.0)
    assert outcome["max_energy_rise"] == pytest.approx(rise, abs=scale)


def test_hybrid_sweep_points_equal_single_runs(kane_levinson: cs.Body) -> None:
    """``contact=hybrid`` runs the stick–slip contact: each point equals simulate() with
    HybridModel on the same samples (some of them stick, a varied capture speed
    reaches the model)."""
    points = {
        "friction_coefficient": [0.35, 0.5, 0.5, 0.5],
        "initial_spin": [-5.0, -5.0, 3.0, 3.0],
        "capture_speed": [1e-10, 1e-10, 1e-10, 1e-8],
    }
    sweep = Sweep(points=points, fixed={"contact": "hybrid"}, t_end=3.0, rtol=1e-8)
    assert sweep.spec().count('"stick_method": "dop853"') == 1
    results = sweep.run(workers=2, task_points=1)
    stick_phases = 0
    for k, (f, spin, capture) in enumerate(zip(*points.values(), strict=True)):
        model = cs.HybridModel(friction_coefficient=f, capture_speed=capture)
        run = cs.simulate(model, kane_levinson, build_state({"initial_spin": spin}), 3.0, rtol=1e-8)
        _assert_point_is_the_run(results.isel(point=k), run, spin)
        stick_phases += run.summary()["stick_phases"]
    assert stick_phases >= 2  # the phase loop really switched


def test_the_stick_slip_contact_is_the_sliding_sweeps_default() -> None:
    """A sliding sweep without a contact runs the stick–slip contact (decisions §28);
    ``contact=sliding`` the regularised one; a rolling sweep has no contact."""
    assert Sweep({"initial_spin": [-5.0]}, t_end=0.1).is_hybrid
    regularised = Sweep({"initial_spin": [-5.0]}, fixed={"contact": "sliding"}, t_end=0.1)
    assert not regularised.is_hybrid
    rolling = Sweep({"initial_spin": [-5.0]}, model="rolling", t_end=0.1)
    assert not rolling.is_hybrid and "contact" not in rolling.fixed


def test_hybrid_contact_options_are_checked_per_point() -> None:
    """A capture speed needs the hybrid contact; the hybrid contact needs the sliding
    model and δ <= v_c / 10 at every point, named before anything runs."""
    with pytest.raises(cs.ParameterError, match="capture_speed"):
        Sweep({"capture_speed": [1e-8]}, fixed={"contact": "sliding"}, t_end=0.1)
    with pytest.raises(cs.ParameterError, match="rolling model"):
        Sweep({"initial_spin": [-5.0]}, model="rolling", fixed={"contact": "hybrid"}, t_end=0.1)
    with pytest.raises(cs.ParameterError, match=r"regularisation_speed.*capture_speed=1e-10"):
        Sweep(
            {"capture_speed": [1e-8, 1e-10]},
            fixed={"contact": "hybrid", "regularisation_speed": 1e-10},
            t_end=0.1,
        )
    with pytest.raises(cs.ParameterError, match=r"contact.*sliding, hybrid"):
        Sweep({"initial_spin": [-5.0]}, fixed={"contact": "stick"}, t_end=0.1)


def test_failed_points_are_recorded_and_the_others_carry_on() -> None:
    results = Sweep({"initial_spin": [-5.0, -40.0, 5.0]}, model="rolling", t_end=0.5).run(workers=1)
    assert list(results["status"].values) == ["success", "lift_off", "success"]
    lifted = results.sel(initial_spin=-40.0)
    assert 0.0 < lifted["t_stop"] < 0.5
    assert lifted["min_normal_force"] == 0.0
    assert np.isnan(lifted["spin_final"]) and np.isnan(lifted["energy_lost"])
    assert "lifts off" in str(lifted["message"].values)
    assert results["t_stop"].sel(initial_spin=5.0) == 0.5


def test_mirror_symmetry_of_misalignment_and_spin() -> None:
    """Mirroring in the plane x2 = 0 maps (misalignment d, spin s) to (-d, -s) with
    alpha = 0 (README: the mirrored body spins the mirrored way); only one sense of
    spin reverses for each sign of the misalignment (rolling, Kane & Levinson)."""
    angle = cs.load_body("kane_levinson_1982").misalignment_angle
    sweep = Sweep(
        {"misalignment_angle": [-angle, angle], "initial_spin": [-5.0, 5.0]},
        model="rolling",
        fixed={"euler_alpha": 0.0, "euler_beta": 0.5},
        t_end=4.0,
        rtol=1e-10,
    )
    r = sweep.run(workers=2)
    flipped = r.isel(misalignment_angle=slice(None, None, -1), initial_spin=slice(None, None, -1))
    for name in ("first_reversal_time", "max_tilt", "min_normal_force", "energy_lost"):
        np.testing.assert_allclose(r[name].values, flipped[name].values, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(r["spin_final"].values, -flipped["spin_final"].values, rtol=1e-6)
    np.testing.assert_array_equal(r["reversal_count"].values, [[0, 1], [1, 0]])


def test_points_list_and_memory_results_equal_the_store(tmp_path) -> None:  # type: ignore[no-untyped-def]
    points = {"damping": [0.0, 1e-5, 2e-5], "euler_beta": [0.5, 1.0, 2.0]}
    sweep = Sweep(points=points, model="rolling", t_end=0.5)
    in_memory = sweep.run(workers=1, chunk_points=2)
    stored = sweep.run(tmp_path / "p.zarr", chunk_points=2, task_points=1)
    assert in_memory["status"].dims == ("point",)
    np.testing.assert_array_equal(stored["euler_beta"].values, points["euler_beta"])
    xr.testing.assert_identical(in_memory, stored)


# --------------------------------------------------------------------------- CLI


def test_cli_sweep_writes_store_and_maps(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "grid.zarr"
    grid = [
        "sweep",
        "--model",
        "rolling",
        "--vary",
        "initial_spin=-5,5",
        "--vary",
        "damping=0:1e-5:2",
    ]
    options = ["--out", str(out), "--no-progress", "--chunk-points", "2"]
    argv = [*grid, "--t-end", "0.5", *options]
    assert main(argv) == 0
    assert "4 points" in capsys.readouterr().out
    results = open_sweep(out)
    assert results.attrs["complete"] is True
    assert results.attrs["rtol"] == 1e-8
    assert results["initial_spin"].attrs["units"] == "rad/s"
    maps = sorted(p.name for p in (tmp_path / "grid_maps").iterdir())
    assert maps == sorted(f"{name}.png" for name in DEFAULT_MAPPED_FIELDS)  # the four
    # an existing store is kept unless resumed or overwritten
    assert main(argv) == 2
    assert "--resume" in capsys.readouterr().err
    assert main([*argv, "--resume", "--no-maps"]) == 0  # nothing left to compute
    xr.testing.assert_identical(open_sweep(out), results)
    # a resume with other settings is refused, naming them
    assert main([*grid, "--t-end", "0.6", *options, "--resume"]) == 2
    assert "t_end" in capsys.readouterr().err


def test_cli_sweeps_the_stick_slip_contact(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "hybrid.zarr"
    argv = ["sweep", "--vary", "initial_spin=-5,5", "--set", "contact=hybrid", "--t-end", "0.5"]
    assert main([*argv, "--out", str(out), "--no-progress", "--no-maps"]) == 0
    results = open_sweep(out)
    assert list(results["status"].values) == ["success", "success"]
    assert results.attrs["model_contact"] == "hybrid"
    assert results.attrs["stick_method"] == "dop853"


def test_cli_points_file(tmp_path) -> None:  # type: ignore[no-untyped-def]
    table = tmp_path / "points.csv"
    table.write_text("initial_spin,euler_alpha\n-5,0.5\n5,1.0\n")
    out = tmp_path / "points.zarr"
    argv = ["sweep", "--model", "rolling", "--points", str(table), "--t-end", "0.2"]
    assert main([*argv, "--out", str(out), "--no-progress", "--no-maps"]) == 0
    results = open_sweep(out)
    np.testing.assert_array_equal(results["euler_alpha"].values, [0.5, 1.0])
    assert (tmp_path / "points_maps").exists() is False


def test_literature_tilt_is_the_default() -> None:
    assert build_state({}).euler_angles == LITERATURE_EULER_ANGLES


def test_superellipsoid_exponent_is_a_sweep_parameter(kane_levinson: cs.Body) -> None:
    import dataclasses

    shape = kane_levinson.shape
    rounded = dataclasses.replace(
        kane_levinson, shape=cs.Superellipsoid(shape.semi_axes, shape.com_offset, 2.0)
    )
    built = build_body(rounded, {"exponent": 2.5, "semi_axis_a": 0.21})
    assert built.shape == cs.Superellipsoid((0.21, 0.03, 0.02), shape.com_offset, 2.5)
    with pytest.raises(cs.ParameterError, match="body's ellipsoid shape"):
        build_body(kane_levinson, {"exponent": 3.0})
    with pytest.raises(cs.ParameterError, match=r"exponent.*\[2, 64\]"):
        build_body(rounded, {"exponent": 1.5})


def test_friction_law_and_pressure_are_fixed_choices() -> None:
    """--set friction_law=exact reaches the model; a bad option names the choices."""
    assert parse_setting("friction_law=exact") == ("friction_law", "exact")
    sweep = Sweep(
        {"friction_coefficient": [0.35]},
        fixed={"friction_law": "exact", "contact_pressure": "uniform", "friction_load": "dynamic"},
        t_end=0.1,
    )
    model = sweep.builder.model
    assert (model.friction_law, model.contact_pressure, model.friction_load) == (
        "exact",
        "uniform",
        "dynamic",
    )
    with pytest.raises(cs.ParameterError, match=r"friction_law.*pade, exact"):
        Sweep({"initial_spin": [-5.0]}, fixed={"friction_law": "padé"}, t_end=0.1)
    with pytest.raises(cs.ParameterError, match="rolling model"):
        Sweep({"initial_spin": [-5.0]}, model="rolling", fixed={"friction_law": "exact"}, t_end=0.1)
    hertz = Sweep(
        {"elastic_modulus": [3e9, 70e9]}, fixed={"poisson_ratio": 0.35}, t_end=0.1
    ).builder
    assert hertz._model((3e9,)).elastic_modulus == 3e9
