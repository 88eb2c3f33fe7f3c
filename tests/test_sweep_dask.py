"""The same sweep on a real dask.distributed cluster equals the local run point for point."""

from __future__ import annotations

from pathlib import Path

import pytest
import xarray as xr

from celtstone.cli.main import main
from celtstone.sweep import Sweep, open_sweep

distributed = pytest.importorskip("distributed")


@pytest.mark.parametrize("contact", ["sliding", "hybrid"])
def test_local_cluster_equals_local_threads(tmp_path: Path, contact: str) -> None:
    """Also the stick–slip contact, whose compiled phase loop runs on the workers."""
    fixed = {"contact": contact} if contact != "sliding" else {}
    sweep = Sweep(
        {"friction_coefficient": [0.2, 0.35, 0.5], "initial_spin": [-5.0, 5.0]},
        fixed=fixed,
        t_end=1.0,
        rtol=1e-8,
    )
    local = sweep.run(tmp_path / "local.zarr", chunk_points=2, task_points=1)
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        store = tmp_path / "cluster.zarr"
        argv = [
            "sweep",
            "--vary",
            "friction_coefficient=0.2,0.35,0.5",
            "--vary",
            "initial_spin=-5,5",
        ]
        argv += ["--t-end", "1", "--chunk-points", "2", "--no-progress", "--no-maps"]
        argv += ["--out", str(store), "--scheduler", cluster.scheduler_address]
        argv += [f"--set=contact={contact}"] if fixed else []
        assert main(argv) == 0
    xr.testing.assert_identical(open_sweep(store), local)
