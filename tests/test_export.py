"""Export: NetCDF and CSV round trips; a file is written whole or not at all."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.cli.main import main
from celtstone.files import export
from tests.conftest import LITERATURE_EULER_ANGLES

# every time series of a run and its CSV columns (vectors split per component)
CSV_COLUMNS = [
    "time",
    "spin",
    "tilt",
    "energy",
    "dissipated_work",
    "normal_force",
    "slip_speed",
    "friction_power",
    "friction_force",
    "com_height",
    "omega_1",
    "omega_2",
    "omega_3",
    "n_1",
    "n_2",
    "n_3",
    "slip_velocity_1",
    "slip_velocity_2",
    "slip_velocity_3",
    "quaternion_w",
    "quaternion_x",
    "quaternion_y",
    "quaternion_z",
    "com_position_x",
    "com_position_y",
    "contact_position_x",
    "contact_position_y",
]


@pytest.fixture(scope="module")
def run_dataset(kane_levinson: cs.Body) -> xr.Dataset:
    """A sliding run over the first spin reversal: spin crossings are not empty."""
    model = cs.SlidingModel(friction_coefficient=0.35, friction_load="dynamic")
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=LITERATURE_EULER_ANGLES)
    run = cs.simulate(model, kane_levinson, state, 3.0, rtol=1e-8, n_samples=301)
    return run.dataset


@pytest.fixture
def small_dataset() -> xr.Dataset:
    """A hand-made dataset of the same structure, independent of the integrators."""
    time = np.array([0.0, 0.5, 1.0])
    return xr.Dataset(
        {
            "spin": ("time", np.array([-5.0, -4.0, 0.1]), {"units": "rad/s"}),
            "omega": (("time", "axis"), np.arange(9.0).reshape(3, 3), {"units": "rad/s"}),
        },
        coords={"time": ("time", time, {"units": "s"}), "axis": [1, 2, 3]},
        attrs={"title": "synthetic", "rtol": 1e-9},
    )


# ---------------------------------------------------------------------------------------
# Round trips
# ---------------------------------------------------------------------------------------


def test_netcdf_round_trip(run_dataset: xr.Dataset, tmp_path: Path) -> None:
    target = tmp_path / "run.nc"
    assert export.write(run_dataset, target) == target
    assert [p.name for p in tmp_path.iterdir()] == ["run.nc"]
    with xr.open_dataset(target, engine="netcdf4") as stored:
        back = stored.load()
    assert run_dataset["spin_crossings"].size > 0
    assert set(back.variables) == set(run_dataset.variables)
    for name, variable in run_dataset.variables.items():
        assert back[name].dims == variable.dims, name
        np.testing.assert_array_equal(back[name].values, variable.values, err_msg=str(name))
        assert back[name].attrs == variable.attrs, name
    assert set(back.attrs) == set(run_dataset.attrs)
    for key, value in run_dataset.attrs.items():
        assert back.attrs[key] == value, key


def test_netcdf_round_trip_of_a_run_without_crossings(
    kane_levinson: cs.Body, tmp_path: Path
) -> None:
    """A run with no spin reversal has an empty ``crossing`` dimension; it still stores."""
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.0, 0.0))
    dataset = cs.simulate(cs.RollingModel(), kane_levinson, state, 1.0).dataset
    assert dataset["spin_crossings"].size == 0
    target = export.write(dataset, tmp_path / "still.nc")
    with xr.open_dataset(target, engine="netcdf4") as stored:
        back = stored.load()
    assert back["spin_crossings"].size == 0
    np.testing.assert_array_equal(back["spin"].values, dataset["spin"].values)


def _read_csv(path: Path) -> tuple[list[str], list[str], dict[str, np.ndarray]]:
    lines = path.read_text(encoding="utf-8").splitlines()
    comments = [line for line in lines if line.startswith("#")]
    body = [line for line in lines if not line.startswith("#")]
    rows = list(csv.reader(body))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    return comments, header, {name: values[:, k] for k, name in enumerate(header)}


def test_csv_columns_and_values(run_dataset: xr.Dataset, tmp_path: Path) -> None:
    target = export.write(run_dataset, tmp_path / "run.csv")
    assert [p.name for p in tmp_path.iterdir()] == ["run.csv"]
    comments, header, columns = _read_csv(target)
    assert len(comments) >= 2
    assert target.read_text(encoding="utf-8").startswith("#")
    assert header == CSV_COLUMNS
    units = next(line for line in comments if "units" in line)
    for fragment in (
        "time [s]",
        "spin [rad/s]",
        "energy [J]",
        "normal_force [N]",
        "omega_3 [rad/s]",
    ):
        assert fragment in units
    count = run_dataset.sizes["time"]
    assert all(len(values) == count for values in columns.values())
    # written with repr: every number comes back bit for bit
    np.testing.assert_array_equal(columns["time"], run_dataset["time"].values)
    np.testing.assert_array_equal(columns["spin"], run_dataset["spin"].values)
    np.testing.assert_array_equal(columns["energy"], run_dataset["energy"].values)
    for k, axis in enumerate((1, 2, 3)):
        np.testing.assert_array_equal(columns[f"omega_{axis}"], run_dataset["omega"].values[:, k])
        np.testing.assert_array_equal(columns[f"n_{axis}"], run_dataset["n"].values[:, k])
    np.testing.assert_array_equal(columns["quaternion_z"], run_dataset["quaternion"].values[:, 3])


def test_csv_of_a_small_dataset(small_dataset: xr.Dataset, tmp_path: Path) -> None:
    target = export.write(small_dataset, tmp_path / "small.CSV")  # suffix in any case
    comments, header, columns = _read_csv(target)
    assert comments[0] == "# synthetic"
    assert header == ["time", "spin", "omega_1", "omega_2", "omega_3"]
    np.testing.assert_array_equal(columns["spin"], [-5.0, -4.0, 0.1])
    np.testing.assert_array_equal(columns["omega_2"], [1.0, 4.0, 7.0])


def test_write_refuses_an_existing_file(small_dataset: xr.Dataset, tmp_path: Path) -> None:
    target = tmp_path / "run.csv"
    target.write_text("old contents\n", encoding="utf-8")
    with pytest.raises(cs.ParameterError, match="--overwrite") as caught:
        export.write(small_dataset, target)
    assert caught.value.name == "out"
    assert target.read_text(encoding="utf-8") == "old contents\n"
    assert [p.name for p in tmp_path.iterdir()] == ["run.csv"]


def test_write_replaces_an_existing_file_when_asked(
    small_dataset: xr.Dataset, tmp_path: Path
) -> None:
    """An earlier table of celtstone's (its mark) is replaced: a new file is moved in."""
    target = tmp_path / "run.csv"
    export.write(small_dataset.isel(time=[0, 1]), target)
    export.write(small_dataset, target, overwrite=True)
    assert target.read_text(encoding="utf-8").startswith("# synthetic")
    lines = target.read_text(encoding="utf-8").splitlines()
    assert (
        len([line for line in lines if not line.startswith("#")]) == 1 + small_dataset.sizes["time"]
    )
    assert [p.name for p in tmp_path.iterdir()] == ["run.csv"]


def test_written_files_have_the_usual_mode(small_dataset: xr.Dataset, tmp_path: Path) -> None:
    """Files are built in a private temporary file but end with the mode open() gives."""
    import os

    umask = os.umask(0o022)
    os.umask(umask)
    for name in ("run.nc", "run.csv"):
        path = export.write(small_dataset, tmp_path / name)
        assert path.stat().st_mode & 0o777 == 0o666 & ~umask
    table = export.write_json({"a": 1}, tmp_path / "a.json")
    assert table.stat().st_mode & 0o777 == 0o666 & ~umask


@pytest.mark.parametrize("name", ["run.txt", "run", "run.nc.part"])
def test_unknown_suffix_writes_nothing(
    small_dataset: xr.Dataset, tmp_path: Path, name: str
) -> None:
    with pytest.raises(cs.ParameterError) as caught:
        export.write(small_dataset, tmp_path / name)
    assert caught.value.name == "out"
    assert list(tmp_path.iterdir()) == []


def test_missing_directory_writes_nothing(small_dataset: xr.Dataset, tmp_path: Path) -> None:
    with pytest.raises(cs.ParameterError) as caught:
        export.write(small_dataset, tmp_path / "nowhere" / "run.nc")
    assert caught.value.name == "out"
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------------------------
# Atomicity: a failure in the middle of writing leaves no file behind
# ---------------------------------------------------------------------------------------


class _Interrupted(Exception):
    """Stands for a failure in the middle of a write (disk full, killed, ...)."""


def _failing_writer(kind: type[BaseException], written: list[Path]):
    def write_some_then_fail(path: str | Path) -> None:
        path = Path(path)
        written.append(path)
        path.write_bytes(b"CDF\x02 half a file")
        raise kind("failure in the middle of writing")

    return write_some_then_fail


@pytest.fixture(params=[".nc", ".csv"])
def failing_format(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch):
    """A suffix whose writer writes some bytes and then fails; yields (suffix, paths seen)."""
    suffix = request.param
    written: list[Path] = []

    def install(kind: type[BaseException]) -> None:
        fail = _failing_writer(kind, written)
        if suffix == ".nc":
            monkeypatch.setattr(xr.Dataset, "to_netcdf", lambda self, path, *a, **k: fail(path))
        else:
            monkeypatch.setattr(export, "to_csv", lambda dataset, path: fail(path))

    return suffix, written, install


@pytest.mark.parametrize("kind", [_Interrupted, OSError, KeyboardInterrupt])
def test_failed_write_leaves_no_file(
    small_dataset: xr.Dataset, tmp_path: Path, failing_format, kind: type[BaseException]
) -> None:
    suffix, written, install = failing_format
    install(kind)
    target = tmp_path / f"run{suffix}"
    with pytest.raises(kind):
        export.write(small_dataset, target)
    assert len(written) == 1
    # the writer got a temporary name in the target's directory, never the target
    assert written[0].parent == tmp_path
    assert written[0] != target
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("kind", [_Interrupted, KeyboardInterrupt])
def test_failed_write_keeps_the_previous_file(
    small_dataset: xr.Dataset, tmp_path: Path, failing_format, kind: type[BaseException]
) -> None:
    suffix, _, install = failing_format
    target = tmp_path / f"run{suffix}"
    export.write(small_dataset, target)  # the previous, complete file (celtstone's)
    previous = target.read_bytes()
    install(kind)
    with pytest.raises(kind):
        export.write(small_dataset, target, overwrite=True)
    assert target.read_bytes() == previous
    assert list(tmp_path.iterdir()) == [target]


def test_interrupted_cli_write_leaves_no_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, failing_format
) -> None:
    """Ctrl-C while ``--out`` is written: status 130, the message says no partial output
    was written, and indeed nothing is there."""
    suffix, written, install = failing_format
    install(KeyboardInterrupt)
    target = tmp_path / f"run{suffix}"
    status = main(["run", "--t-end", "1", "--json", "--out", str(target)])
    _, err = capsys.readouterr()
    assert status == 130
    assert "no partial output" in err
    assert len(written) == 1
    assert list(tmp_path.iterdir()) == []
