"""A small fit and an atlas's long runs on the CPU and in numba's CUDA simulator, for
tests/test_fit_cuda.py.

Run as ``NUMBA_ENABLE_CUDASIM=1 python tests/fit_cuda_sample.py DIR`` (the variable must
be set before numba is imported, hence a process of its own). Writes to DIR
``report.json``: each fit's values, standard errors, cost, residuals, runs and device,
and each design's long-run numbers, from ``device="cpu"`` (threads) and
``device="cuda"`` (each batch of runs as one launch on the simulated GPU). Exits 77
where the simulator is unavailable, saying why.

The fit: f and ε from a spin record of 0.3 s (31 samples) of the sliding model from
Kane & Levinson's start, one start; a record of one series has every physical number's
profile walked, so the fit makes batches of one run (the residual), of several (the
Jacobian's columns beside it, the intervals' checks) and its local refits. The atlas:
the rolling and sliding long runs of 1 s of two designs (``atlas.fields._long_runs``),
the first reversing.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import warnings
from pathlib import Path
from typing import Any

DURATION = 0.3  # s of the record
LONG_RUN = 1.0  # s of the atlas's long runs
DESIGNS = (  # tests/test_atlas_search.py's; the first one's runs reverse within 1 s
    {
        "length": 0.1,
        "width_ratio": 0.25,
        "height_ratio": 0.15,
        "misalignment": 4.0,
        "mass_fraction": 0.5,
    },
    {
        "length": 0.2,
        "width_ratio": 0.3,
        "height_ratio": 0.15,
        "misalignment": 3.0,
        "mass_fraction": 0.5,
    },
)


def main() -> int:
    directory = Path(sys.argv[1])
    from sweep_cuda_sample import start_simulator

    refused = start_simulator()
    if refused is not None:
        return refused
    report: dict[str, Any] = {}
    for device in ("cuda", "cpu"):
        report[device] = {"fit": _fit(device), "long_runs": _long_runs(device)}
    (directory / "report.json").write_text(json.dumps(report))
    return 0


def _fit(device: str) -> dict[str, Any]:
    """The fit of f and ε on ``device``, in numbers."""
    import numpy as np

    import celtstone as cs

    body = cs.load_body("kane_levinson_1982")
    state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
    times = np.round(np.arange(0.0, DURATION + 1e-9, 0.01), 10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        truth = cs.simulate(
            cs.SlidingModel(friction_coefficient=0.3, contact_radius=1e-3),
            body,
            state,
            DURATION,
            sample_times=times,
        )
        spin = truth.samples.values("spin")
        noisy = spin + np.random.default_rng(0).normal(0.0, 0.05, spin.size)
        record = cs.make_record(times, {"spin": noisy})
        result = cs.fit(
            record,
            body,
            "sliding",
            ["friction_coefficient", "contact_radius"],
            fixed={"omega3": -5.0},
            sensor_bias=False,
            starts=1,
            workers=2,
            device=device,
        )
    return {
        "values": result.values.tolist(),
        "standard_errors": result.standard_errors.tolist(),
        "cost": result.cost,
        "residuals": result.residuals.tolist(),
        "runs": result.runs,
        "runs_by_stage": dict(result.runs_by_stage),
        "failed_runs": result.failed_runs,
        "device": result.summary()["device"],
    }


def _long_runs(device: str) -> list[dict[str, Any]]:
    """The atlas's long runs of ``DESIGNS`` on ``device``."""
    from celtstone.atlas import StoneDesign
    from celtstone.atlas.fields import ATLAS_STUDY, _long_runs

    study = dataclasses.replace(ATLAS_STUDY, fig3_t_end=LONG_RUN)
    designs = [StoneDesign(**d) for d in DESIGNS]
    bodies = [d.body() for d in designs]
    return _long_runs(study, designs, bodies, None, 2, False, device)


if __name__ == "__main__":
    sys.exit(main())
