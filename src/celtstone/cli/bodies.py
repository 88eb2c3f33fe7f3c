"""``celtstone bodies``: the shipped parameter sets and their sources;
``celtstone bodies show NAME``: one body's numbers, those derived from a design included."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import numpy as np

from celtstone import list_bodies, load_body
from celtstone.bodies import load_design
from celtstone.errors import ParameterError


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone bodies``."""
    parser.add_argument(
        "action",
        nargs="?",
        choices=["show"],
        help="show NAME: print one body's numbers, the derived ones included",
    )
    parser.add_argument("name", nargs="?", help="shipped body name or .toml path (with show)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def body_numbers(name: str) -> dict[str, Any]:
    """The numbers of one body, SI units: the design it was computed from (if any), then
    mass, centre of mass, inertia, misalignment, rest-contact geometry and rocking periods."""
    body = load_body(name)
    design = load_design(name)
    numbers: dict[str, Any] = {"name": body.name, "source": body.source}
    if design is not None:
        numbers["design"] = {
            "length_m": design.length,
            "width_m": design.width,
            "height_m": design.height,
            "misalignment_deg": design.misalignment,
            "added_masses_kg_m": [[m.mass, *m.position] for m in design.added_masses],
            "solid_mass_kg": design.solid_mass,
            "solid_density_kg_per_m3": design.solid_density,
        }
    principal = np.linalg.eigvalsh(body.inertia_array)
    rho1, rho2 = (float(r) for r in body.shape.radii_of_curvature)
    pitch, roll = body.rocking_periods
    numbers.update(
        {
            "shape": body.shape.table() if body.shape.stored else body.shape.kind,
            "mass_kg": body.mass,
            "gravity_m_per_s2": body.gravity,
            "com_height_above_contact_m": body.shape.rest_height,
            "radii_of_curvature_m": [rho1, rho2],
            "inertia_kg_m2": [list(row) for row in body.inertia],
            "principal_moments_kg_m2": [float(v) for v in principal],
            "misalignment_angle_deg": math.degrees(body.misalignment_angle),
            "rocking_periods_s": {"pitch": pitch, "roll": roll},
        }
    )
    return numbers


def _shape_words(shape: dict[str, Any] | str) -> str:
    """A ``[shape]`` table in one line, its numbers to 6 digits."""
    if isinstance(shape, str):
        return shape

    def number(value: Any) -> str:
        if isinstance(value, list):
            return "[" + ", ".join(number(v) for v in value) + "]"
        return f"{value:.6g}" if isinstance(value, float) else str(value)

    return ", ".join(f"{key} = {number(value)}" for key, value in shape.items())


def _print_numbers(numbers: dict[str, Any]) -> None:
    print(f"{numbers['name']}: {numbers['source']}")
    design = numbers.get("design")
    if design is not None:
        print(
            f"  design: {design['length_m']:g} x {design['width_m']:g} x "
            f"{design['height_m']:g} m half-ellipsoid, misalignment "
            f"{design['misalignment_deg']:g} deg"
        )
        print(
            f"  solid: {design['solid_mass_kg']:.6g} kg, density "
            f"{design['solid_density_kg_per_m3']:.6g} kg/m^3"
        )
        for mass, x, y, z in design["added_masses_kg_m"]:
            print(f"  added mass {mass:.6g} kg at ({x:g}, {y:g}, {z:g}) m")
    print(f"  shape: {_shape_words(numbers['shape'])}")
    print(f"  mass m = {numbers['mass_kg']:.6g} kg, g = {numbers['gravity_m_per_s2']:g} m/s^2")
    print(f"  centre of mass G {numbers['com_height_above_contact_m']:.6g} m above the contact")
    rho1, rho2 = numbers["radii_of_curvature_m"]
    print(f"  radii of curvature at rest rho1 = {rho1:.6g} m, rho2 = {rho2:.6g} m")
    print("  central inertia tensor [kg m^2], axes 1 long, 2 across, 3 up:")
    for row in numbers["inertia_kg_m2"]:
        print("    [" + ", ".join(f"{value:.6g}" for value in row) + "]")
    moments = ", ".join(f"{value:.6g}" for value in numbers["principal_moments_kg_m2"])
    print(f"  principal moments [kg m^2]: {moments}")
    print(
        f"  misalignment: long principal axis {numbers['misalignment_angle_deg']:.4g} deg "
        "from axis 1"
    )
    periods = numbers["rocking_periods_s"]
    print(f"  rocking periods: pitch {periods['pitch']:.4g} s, roll {periods['roll']:.4g} s")


def handle(args: argparse.Namespace) -> int:
    """Print each body's name, shape, mass and source; with ``show``, one body's numbers."""
    if args.action == "show":
        if not args.name:
            raise ParameterError("name", None, "a shipped body name or a .toml path after show")
        numbers = body_numbers(args.name)
        if args.json:
            print(json.dumps(numbers, indent=2))
        else:
            _print_numbers(numbers)
        return 0
    if args.name:
        raise ParameterError("action", args.name, "show (celtstone bodies show NAME)")
    entries = {}
    for name in list_bodies():
        body = load_body(name)
        entries[name] = {
            "shape": body.shape.kind,
            "mass": body.mass,
            "source": body.source,
            "notes": body.notes,
        }
    if args.json:
        print(json.dumps(entries, indent=2))
        return 0
    for name, entry in entries.items():
        print(f"{name}: {entry['shape']}, m = {entry['mass']:g} kg")
        print(f"    source: {entry['source']}")
        if entry["notes"]:
            print(f"    notes: {entry['notes']}")
    return 0
