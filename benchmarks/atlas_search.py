"""The atlas's search for the long-run finding (issue 15; docs/decisions.md §32).

Runs :func:`celtstone.atlas.search.search_points` (a Latin hypercube with a seed) through
the atlas's long runs, judged by the report's judge, and writes into ``--out``:

* ``search.zarr`` (every point: parameters, contact, counts, reversal times, verdict),
* ``search.csv`` (a row per point, provenance header),
* ``search_summary.json`` (what the report's section 7 states),
* ``CONTACT/long_run/design_NNNNN.json`` (each run's numbers: a second call resumes).

With ``--full N`` the N best points and the N closest of those with three reversals in
both runs (``closest_points``) then get all five findings
(``compute_atlas``, ``ATLAS_STUDY`` in the study of their contact, resumed where stored),
written to ``full_CONTACT/``; their verdicts are added to the summary.

Run again, the script recomputes nothing stored and keeps the costs of the call that
computed the runs (``cost.long_runs_computed``: the runs this call computed).

``--store`` copies the summary and the table into the package
(``src/celtstone/atlas/data/long_run_search_BOX.*``), where the atlas target reads them
for the report.

    .venv/bin/python benchmarks/atlas_search.py --count 240 --seed 15 --workers 2 --full 4 --store
    .venv/bin/python benchmarks/atlas_search.py --box refined --count 60 --seed 16 --full 3 --store
    .venv/bin/python benchmarks/atlas_search.py --box stone --count 30 --seed 17 --full 15 --store

``--device cuda`` runs them on a CUDA GPU (refused at once where there is none).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import time
from pathlib import Path
from typing import Any

from celtstone.atlas import compute_atlas
from celtstone.atlas.fields import ATLAS_STUDY, atlas_device, write_atlas
from celtstone.atlas.search import (
    SEARCH_BOXES,
    STORED_SEARCHES,
    closest_points,
    contact_study,
    search_dataset,
    search_long_runs,
    search_points,
    search_summary,
    search_table,
)
from celtstone.errors import CeltstoneError
from celtstone.files.export import write_json, write_table
from celtstone.reproduce.findings import FINDINGS
from celtstone.simulation.integrate import version
from celtstone.sweep.devices import DEVICES

DESIGN_FIELDS = ("length", "width_ratio", "height_ratio", "misalignment", "mass_fraction")


def _cost(start_wall: float, start_cpu: float) -> dict[str, float]:
    times = os.times()
    return {
        "wall_s": round(time.perf_counter() - start_wall, 1),
        "cpu_s": round(times.user + times.system - start_cpu, 1),
        "load_average_1min": round(os.getloadavg()[0], 2),
    }


def _previous(path: Path) -> dict[str, Any]:
    """The summary an earlier call wrote (its costs are kept where nothing is recomputed)."""
    return dict(json.loads(path.read_text(encoding="utf-8"))) if path.exists() else {}


def _stored_runs(out: Path) -> int:
    """How many long runs are stored in ``out`` (a resumed call computes only the rest)."""
    return len(list(out.glob("*/long_run/design_*.json")))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=240)
    parser.add_argument("--seed", type=int, default=15)
    parser.add_argument("--workers", type=int, default=2, help="threads on the CPU")
    parser.add_argument(
        "--device",
        default="cpu",
        choices=DEVICES,
        help="cpu, cuda (the long runs of each contact as one GPU launch per model kind, "
        "the --full atlases' sweeps on the GPU) or auto",
    )
    parser.add_argument("--box", default="wide", choices=list(SEARCH_BOXES))
    parser.add_argument("--out", default=None, help="default results/atlas_search_BOX")
    parser.add_argument("--full", type=int, default=0, help="all five for 2N closest points")
    parser.add_argument("--store", action="store_true", help="copy summary and table in")
    args = parser.parse_args()
    atlas_device(args.device, ATLAS_STUDY)  # a GPU that is not here: before --out is made
    out = Path(args.out or f"results/atlas_search_{args.box}")
    out.mkdir(parents=True, exist_ok=True)
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    load_start = round(os.getloadavg()[0], 2)
    wall, cpu = time.perf_counter(), sum(os.times()[:2])

    previous = _previous(out / "search_summary.json")
    points = search_points(args.count, args.seed, args.box)
    stored = _stored_runs(out)
    numbers = search_long_runs(
        points, out=out, workers=args.workers, progress=print, device=args.device
    )
    dataset = search_dataset(points, numbers, seed=args.seed, box=args.box)
    summary = search_summary(dataset)
    summary["cost"] = {"date": started, "load_average_start": load_start, **_cost(wall, cpu)}
    summary["cost"].update(
        workers=args.workers, device=args.device, long_runs_computed=_stored_runs(out) - stored
    )
    if summary["cost"]["long_runs_computed"] == 0 and "cost" in previous:
        summary["cost"] = previous["cost"]  # the cost of the call that computed the runs
    summary["software"] = f"celtstone {version()}"
    write_atlas(dataset, out / "search.zarr", overwrite=True)
    header = {
        "software": f"celtstone {version()}",
        "search": f"Latin hypercube, {args.count} points, seed {args.seed}, box {args.box} "
        "(celtstone.atlas.search, docs/decisions.md §32)",
        "study": ATLAS_STUDY.describe(),
        "contact": "per row: eps_1mm (the study's), or hertz_pmma_glass, hertz_pmma_pmma "
        "(the study with the Hertz radius of the pair, celtstone.atlas.hertz_study)",
        "verdict": "long_run by celtstone.reproduce.findings.JUDGES",
    }
    write_table(search_table(dataset), out / "search.csv", header, overwrite=True)
    print(json.dumps({k: summary[k] for k in ("verdicts", "contacts", "cost")}, indent=1))

    if args.full:
        wall, cpu = time.perf_counter(), sum(os.times()[:2])
        best = [points[k] for k in closest_points(dataset, args.full)]
        full = []
        resumed = all((out / f"full_{p.contact}" / "atlas.zarr").exists() for p in best)
        for contact in dict.fromkeys(p.contact for p in best):
            designs = [p.design for p in best if p.contact == contact]
            atlas = compute_atlas(
                designs,
                contact_study(contact, ATLAS_STUDY),
                out / f"full_{contact}",
                workers=args.workers,
                resume=True,
                progress=print,
                device=args.device,
            )
            for k, design in enumerate(designs):
                full.append(
                    {
                        "parameters": {
                            name: float(atlas[name].values[k]) for name in DESIGN_FIELDS
                        },
                        "contact": contact,
                        "name": design.name,
                        "verdicts": {f: str(atlas[f].values[k]) for f in FINDINGS},
                        "ours": {f: str(atlas[f"{f}_ours"].values[k]) for f in FINDINGS},
                    }
                )
        summary["full"] = full
        summary["full_cost"] = previous.get("full_cost") if resumed else _cost(wall, cpu)
        print(json.dumps(full, indent=1))
    write_json(summary, out / "search_summary.json", overwrite=True)
    if args.store:
        STORED_SEARCHES[args.box].parent.mkdir(exist_ok=True)
        shutil.copy(out / "search_summary.json", STORED_SEARCHES[args.box])
        shutil.copy(out / "search.csv", STORED_SEARCHES[args.box].with_suffix(".csv"))


if __name__ == "__main__":
    try:
        main()
    except CeltstoneError as error:  # bad input, a GPU that is not here: one line
        print(f"atlas_search: {error}", file=sys.stderr)
        sys.exit(2)
