"""``celtstone bodies``: the shipped parameter sets and their sources."""

from __future__ import annotations

import argparse
import json

from celtstone import list_bodies, load_body


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone bodies``."""
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def handle(args: argparse.Namespace) -> int:
    """Print each body's name, shape, mass and source."""
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
