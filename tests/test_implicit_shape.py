"""Implicit polynomial shapes: the Newton contact kernel against closed forms and invariants.

Reference shapes: the Kane & Levinson (1982) ellipsoid a, b, c = 0.20, 0.03, 0.02 m,
h = 0.01 m (references.md) written as the polynomial x²/a² + y²/b² + z²/c², and the
superellipsoid |x/a|^4 + |y/b|^4 + |z/c|^4 against ``superellipsoid_contact``.
The egg F = x²/a² + y²/b² + z²/c² + β z³/c³ + γ z⁴/c⁴ is convex for β² < 8γ/3
(g''(z) = 2/c² + 6βz/c³ + 12γz²/c⁴ > 0), here β = 0.3, γ = 0.1.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone.cli.main import main
from celtstone.kernels import geometry, hertz, layout
from celtstone.simulation.integrate import STATUS_NAMES

A, B, C, H = 0.20, 0.03, 0.02, 0.01
ELLIPSOID_TERMS = [[1 / A**2, 2, 0, 0], [1 / B**2, 0, 2, 0], [1 / C**2, 0, 0, 2]]
EGG_TERMS = [*ELLIPSOID_TERMS, [0.3 / C**3, 0, 0, 3], [0.1 / C**4, 0, 0, 4]]
STATE = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))


def raw_params(terms: list, start_axes: tuple, centre: tuple = (0.0, 0.0, 0.0)) -> np.record:
    """A parameter record for the kernels, bypassing the shape's validation."""
    coefficients = np.zeros(layout.MAX_TERMS)
    exponents = np.zeros((layout.MAX_TERMS, 3), dtype=np.int64)
    coefficients[: len(terms)] = [term[0] for term in terms]
    exponents[: len(terms)] = [term[1:] for term in terms]
    return layout.parameter_record(
        shape_code=layout.ShapeCode.IMPLICIT,
        start_semi_axes=start_axes,
        com_offset=H,
        start_centre=centre,
        term_count=len(terms),
        term_coefficients=coefficients,
        term_exponents=exponents,
    )


def random_pairs(count: int, seed: int) -> list[tuple[tuple, tuple]]:
    rng = np.random.default_rng(seed)
    return [(tuple(rng.normal(size=3)), tuple(rng.normal(size=3))) for _ in range(count)]


def relative(value: tuple, reference: tuple) -> float:
    return float(np.max(np.abs(np.subtract(value, reference))) / np.linalg.norm(reference))


@pytest.fixture(scope="module")
def ellipsoid() -> cs.ImplicitPolynomial:
    return cs.ImplicitPolynomial(terms=ELLIPSOID_TERMS, com_offset=H)


@pytest.fixture(scope="module")
def egg() -> cs.ImplicitPolynomial:
    return cs.ImplicitPolynomial(terms=EGG_TERMS, com_offset=H)


def test_polynomial_ellipsoid_matches_closed_form(ellipsoid: cs.ImplicitPolynomial) -> None:
    params = ellipsoid.kernel_record()
    for n, n_rate in random_pairs(500, 1):
        r, r_rate = geometry.contact(n, n_rate, params)
        r0, r0_rate = geometry.ellipsoid_contact(n, n_rate, A, B, C, H)
        assert relative(r, r0) < 1e-12
        assert relative(r_rate, r0_rate) < 1e-12


def test_start_far_from_the_answer_still_converges() -> None:
    """A poor start ellipsoid (axes off by 2x, shifted centre) only costs iterations."""
    params = raw_params(ELLIPSOID_TERMS, (2 * A, 0.5 * B, 1.5 * C), (0.05, 0.01, -0.01))
    for n, n_rate in random_pairs(200, 2):
        r, r_rate = geometry.contact(n, n_rate, params)
        r0, r0_rate = geometry.ellipsoid_contact(n, n_rate, A, B, C, H)
        assert relative(r, r0) < 1e-12
        assert relative(r_rate, r0_rate) < 1e-12


def test_quartic_matches_superellipsoid_away_from_flat_points() -> None:
    terms = [[1 / A**4, 4, 0, 0], [1 / B**4, 0, 4, 0], [1 / C**4, 0, 0, 4]]
    params = raw_params(terms, (A, B, C))
    for n, n_rate in random_pairs(300, 3):
        if min(abs(v) for v in n) < 0.05 * np.linalg.norm(n):
            continue  # near a coordinate plane the curvature vanishes (flat points)
        r, r_rate = geometry.contact(n, n_rate, params)
        r0, r0_rate = geometry.superellipsoid_contact(n, n_rate, A, B, C, H, 4.0)
        assert relative(r, r0) < 1e-11
        assert relative(r_rate, r0_rate) < 1e-9


def test_flat_rest_contact_is_refused() -> None:
    """The p = 4 superellipsoid is flat at its rest contact: no contact rate there."""
    terms = [[1 / A**4, 4, 0, 0], [1 / B**4, 0, 4, 0], [1 / C**4, 0, 0, 4]]
    with pytest.raises(cs.ParameterError, match="terms") as error:
        cs.ImplicitPolynomial(terms=terms, com_offset=H)
    assert "\n" not in str(error.value)
    params = raw_params(terms, (A, B, C))
    flat, _ = geometry.contact((0.0, 0.0, 1.0), (0.1, 0.0, 0.0), params)
    assert np.isnan(flat[0])
    # the right-hand side reports it; the run stops with status "non_convex"
    assert geometry.contact_status((0.0, 0.0, 1.0), flat, params) == layout.RHS_NON_CONVEX
    assert STATUS_NAMES[cs.solvers.STATUS_NON_CONVEX] == "non_convex"


def test_rate_is_the_derivative_along_a_path(egg: cs.ImplicitPolynomial) -> None:
    params = egg.kernel_record()
    start, direction = np.array([0.3, -0.2, 0.9]), np.array([-0.4, 0.7, 0.1])

    def vertical(t: float) -> np.ndarray:
        v = start + t * direction + 0.5 * t * t * np.array([0.2, 0.0, -0.3])
        return v / np.linalg.norm(v)

    step = 1e-5
    for t in (-0.5, 0.0, 0.4, 1.0):
        n = vertical(t)
        n_rate = (vertical(t + step) - vertical(t - step)) / (2 * step)
        _, r_rate = geometry.contact(tuple(n), tuple(n_rate), params)
        forward, _ = geometry.contact(tuple(vertical(t + step)), (0.0, 0.0, 0.0), params)
        backward, _ = geometry.contact(tuple(vertical(t - step)), (0.0, 0.0, 0.0), params)
        difference = (np.array(forward) - np.array(backward)) / (2 * step)
        assert relative(r_rate, tuple(difference)) < 1e-8


def test_egg_contact_is_on_the_surface_and_lowest(egg: cs.ImplicitPolynomial) -> None:
    params = egg.kernel_record()
    rng = np.random.default_rng(4)
    surface = rng.normal(size=(4000, 3))
    for n, _ in random_pairs(50, 5):
        r, _ = geometry.contact(n, (0.0, 0.0, 0.0), params)
        x = np.array(r) - np.array([0.0, 0.0, H])
        f = sum(c * x[0] ** i * x[1] ** j * x[2] ** k for c, i, j, k in EGG_TERMS)
        assert abs(f - 1.0) < 1e-13
        # every surface point on rays from G lies no lower along n
        points = np.array([egg.contact_point(tuple(u)) for u in surface[:20]])
        assert np.all(points @ np.array(n) >= x @ np.array(n) - 1e-15)


def test_gaussian_curvature_of_the_ellipsoid(ellipsoid: cs.ImplicitPolynomial) -> None:
    """Hertz R_eq = 1/sqrt(K) equals the ellipsoid's abc / (nᵀQn) (docs/equations.md)."""
    params = ellipsoid.kernel_record()
    reference = layout.parameter_record(
        shape_code=layout.ShapeCode.ELLIPSOID, semi_axes=(A, B, C), com_offset=H
    )
    for n, _ in random_pairs(50, 6):
        radius = hertz.equivalent_radius(n, params)
        assert radius == pytest.approx(hertz.equivalent_radius(n, reference), rel=1e-11)
    assert ellipsoid.radii_of_curvature == pytest.approx((A * A / C, B * B / C), rel=1e-12)
    assert ellipsoid.rest_height == pytest.approx(C - H, rel=1e-12)


def test_kane_levinson_polynomial_run_matches_closed_form(
    ellipsoid: cs.ImplicitPolynomial,
) -> None:
    body = cs.load_body("kane_levinson_1982")
    polynomial = replace(body, shape=ellipsoid)
    # a tolerance well below the 1e-10 compared: the two shapes' contact points differ by
    # round-off, which can change a step's acceptance and so move each run by its own error
    tight = {"rtol": 1e-13, "atol": 1e-15}
    closed = cs.simulate(cs.RollingModel(), body, STATE, 5.0, **tight).dataset
    implicit = cs.simulate(cs.RollingModel(), polynomial, STATE, 5.0, **tight).dataset
    assert implicit.attrs["status"] == "success"
    spin, spin0 = float(implicit.spin[-1]), float(closed.spin[-1])
    assert spin == pytest.approx(spin0, rel=1e-10)
    energy = implicit.energy.values
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * energy[0]
    assert implicit.attrs["body_shape"] == "implicit_polynomial"
    table = json.loads(implicit.attrs["body_shape_table"])
    assert cs.bodies.shape_from_table(table) == ellipsoid


def test_egg_rolling_conserves_energy_and_unit_vertical(egg: cs.ImplicitPolynomial) -> None:
    body = replace(cs.load_body("kane_levinson_1982"), shape=egg)
    run = cs.simulate(cs.RollingModel(), body, STATE, 3.0).dataset
    assert run.attrs["status"] == "success"
    energy = run.energy.values
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * energy[0]
    norm = np.linalg.norm(run.n.values, axis=-1)
    assert np.max(np.abs(norm - 1.0)) < 1e-9
    # lowest point: z = c t with t² + 0.3 t³ + 0.1 t⁴ = 1, the root in (-2, 0)
    roots = np.roots([0.1, 0.3, 1.0, 0.0, -1.0])
    t = min(r.real for r in roots if abs(r.imag) < 1e-12 and -2.0 < r.real < 0.0)
    assert egg.rest_height == pytest.approx(-C * t - H, rel=1e-12)


@pytest.mark.parametrize(
    ("terms", "offset", "words"),
    [
        # x⁴/a⁴ − x²/(2a²) + ...: a waist at x = 0 (the slice there is the smallest)
        ([[1 / A**4, 4, 0, 0], [-0.5 / A**2, 2, 0, 0], *ELLIPSOID_TERMS[1:]], H, "convex"),
        # the KL ellipsoid shifted by 1 cm along axis 1: convex, but rests off axis 3
        (
            [
                *ELLIPSOID_TERMS,
                [-2 * 0.01 / A**2, 1, 0, 0],
                [0.01**2 / A**2, 0, 0, 0],
            ],
            H,
            "upright",
        ),
        (ELLIPSOID_TERMS, 0.03, "G inside"),
        ([[1.0, 2, 0, 0], [1.0, 0, 2, 0], [-1.0, 0, 0, 2]], 0.0, "bounded"),  # hyperboloid
        ([[1.0, 2, 0, 0], [1.0, 0, 2, 0]], 0.0, "convex"),  # a cylinder: found not closed
        ([[1.0, 1, 0, 0]], 0.0, "degree"),
        ([[1.0, 1.5, 0, 0]], 0.0, "integers"),
        ([[float("nan"), 2, 0, 0]], 0.0, "finite"),
        ([], 0.0, "terms"),
    ],
    ids=[
        "waist",
        "off-axis",
        "G-outside",
        "unbounded",
        "cylinder",
        "linear",
        "fraction",
        "nan",
        "empty",
    ],
)
def test_bad_shapes_are_refused(terms: list, offset: float, words: str) -> None:
    with pytest.raises(cs.ParameterError) as error:
        cs.ImplicitPolynomial(terms=terms, com_offset=offset)
    message = str(error.value)
    assert "\n" not in message
    assert words in message


def test_cli_runs_a_toml_polynomial_body(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "egg.toml"
    terms = ", ".join(f"[{c!r}, {i}, {j}, {k}]" for c, i, j, k in EGG_TERMS)
    path.write_text(
        'title = "test egg"\nsource = "test_implicit_shape.py"\n'
        "[body]\nmass = 1.0\ninertia = [[2.0e-4, -2.0e-5, 0.0], [-2.0e-5, 1.6e-3, 0.0], "
        "[0.0, 0.0, 1.7e-3]]\n"
        f'[shape]\nkind = "implicit_polynomial"\nterms = [{terms}]\ncom_offset = {H}\n'
    )
    status = main(["run", "--body", str(path), "--t-end", "0.5", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert status == 0
    assert summary["status"] == "success"
    assert summary["body_shape"] == "implicit_polynomial"
    assert main(["bodies"]) == 0
    assert "kane_levinson_1982" in capsys.readouterr().out


def test_sweep_builds_a_polynomial_body(egg: cs.ImplicitPolynomial) -> None:
    from celtstone.sweep.spec import build_body

    base = replace(cs.load_body("kane_levinson_1982"), shape=egg)
    moved = build_body(base, {"com_offset": 0.005})
    assert isinstance(moved.shape, cs.ImplicitPolynomial)
    assert moved.shape.com_offset == 0.005
    with pytest.raises(cs.ParameterError, match="implicit_polynomial"):
        build_body(base, {"semi_axis_a": 0.1})


def test_superellipsoid_curvature_matches_the_polynomial_one() -> None:
    """Hertz R_eq of the closed-form superellipsoid: p = 2 is the ellipsoid's; p = 4 equals
    the Newton solve on the polynomial x⁴/a⁴ + y⁴/b⁴ + z⁴/c⁴ away from its flat curves;
    R_eq is infinite at the flat rest contact, and a run there is refused."""
    closed = layout.parameter_record(
        shape_code=layout.ShapeCode.SUPERELLIPSOID, semi_axes=(A, B, C), com_offset=H, exponent=2.0
    )
    ellipsoid = layout.parameter_record(
        shape_code=layout.ShapeCode.ELLIPSOID, semi_axes=(A, B, C), com_offset=H
    )
    for n, _ in random_pairs(30, 8):
        assert hertz.equivalent_radius(n, closed) == pytest.approx(
            hertz.equivalent_radius(n, ellipsoid), rel=1e-12
        )
    closed.exponent = 4.0
    quartic = raw_params([[1 / A**4, 4, 0, 0], [1 / B**4, 0, 4, 0], [1 / C**4, 0, 0, 4]], (A, B, C))
    for n, _ in random_pairs(30, 9):
        if min(abs(component) for component in n) < 0.05:
            continue  # near a flat curve
        assert hertz.equivalent_radius(n, closed) == pytest.approx(
            hertz.equivalent_radius(n, quartic), rel=1e-9
        )
    assert hertz.equivalent_radius((0.0, 0.0, 1.0), closed) == np.inf
    flat = replace(cs.load_body("kane_levinson_1982"), shape=cs.Superellipsoid((A, B, C), H, 4.0))
    model = cs.SlidingModel(elastic_modulus=3e9, poisson_ratio=0.35)
    with pytest.raises(cs.ParameterError, match="finite radii of curvature"):
        cs.simulate(model, flat, STATE, 0.1)
