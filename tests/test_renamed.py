"""One meaning per name: each renamed input (``schema.RENAMED``) is refused under its old
name with a hint naming the new one, on the command line, in sweeps and in Python; run
files and reproduction data written before the rename still read."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import xarray as xr

import celtstone as cs
from celtstone.cli.main import main
from celtstone.files.export import read_run, write
from celtstone.plotting.labels import run_label
from celtstone.reproduce.report import collect
from celtstone.simulation.models import SETTINGS
from celtstone.simulation.schema import PARAMETERS as SCHEMA_PARAMETERS
from celtstone.simulation.schema import RENAMED, RENAMED_ATTRIBUTES
from celtstone.sweep import Sweep
from celtstone.sweep.spec import CHOICES, MODEL, PARAMETERS


def _one_error_line(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    """Run ``celtstone ARGV``; assert exit 2 and one line on stderr; return it."""
    status = main(argv)
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize(
    ("option", "value", "new"),
    [("--normal-force", "dynamic", "--friction-load"), ("--tilt", "0.5,0.5", "--euler-angles")],
)
def test_run_refuses_an_old_option_naming_the_new(
    capsys: pytest.CaptureFixture[str], option: str, value: str, new: str
) -> None:
    line = _one_error_line(capsys, ["run", "--model", "sliding", option, value])
    assert f"renamed {new}" in line and option in line


@pytest.mark.parametrize(
    ("flag", "text", "new"),
    [
        ("--vary", "spin=-5,5", "initial_spin"),
        ("--vary", "tilt_alpha=0,1", "euler_alpha"),
        ("--vary", "tilt_beta=0,1", "euler_beta"),
        ("--set", "normal_force=dynamic", "friction_load"),
        ("--set", "tilt_alpha=1", "euler_alpha"),
        ("--set", "spin=-5", "initial_spin"),
    ],
)
def test_sweep_refuses_an_old_name_naming_the_new(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, flag: str, text: str, new: str
) -> None:
    axis = [] if flag == "--vary" else ["--vary", "damping=0,1e-6"]
    out = tmp_path / "s.zarr"
    line = _one_error_line(capsys, ["sweep", flag, text, *axis, "--out", str(out)])
    assert f"renamed {new}" in line, line
    assert not out.exists()


def test_every_old_sweep_name_is_refused_in_python() -> None:
    sweep_names = {*PARAMETERS, *CHOICES}
    for old, new in RENAMED.items():
        if new not in sweep_names:
            continue
        with pytest.raises(cs.ParameterError, match=f"renamed {new}"):
            Sweep({old: [1.0]}, t_end=0.1)
    with pytest.raises(cs.ParameterError, match="renamed friction_load"):
        Sweep({"damping": [0.0]}, fixed={"normal_force": "dynamic"}, t_end=0.1)


def test_python_refuses_the_old_names() -> None:
    with pytest.raises(cs.ParameterError, match=r"tilt .*renamed euler_angles") as caught:
        cs.InitialState(tilt=(0.5, 0.5))  # type: ignore[call-arg]
    assert caught.value.name == "tilt"
    with pytest.raises(cs.ParameterError, match="renamed friction_load"):
        cs.model_from_name("sliding", normal_force="dynamic")
    assert cs.InitialState(euler_angles=(1.0, 2.0)).euler_angles == (1.0, 2.0)


def test_every_numeric_model_setting_is_a_sweep_parameter() -> None:
    """The model's numbers and options of a sweep are ``models.SETTINGS``, nothing else."""
    numbers = {name for name, setting in SETTINGS.items() if setting.choices is None}
    options = {name for name, setting in SETTINGS.items() if setting.choices is not None}
    assert {name for name, p in PARAMETERS.items() if p.group == MODEL} == numbers
    for name in numbers:
        assert PARAMETERS[name].unit == SCHEMA_PARAMETERS[name].unit
    for name in options:
        assert CHOICES[name] == tuple(SETTINGS[name].choices or ())


@pytest.fixture(scope="module")
def old_run_file(tmp_path_factory: pytest.TempPathFactory, kane_levinson: cs.Body) -> Path:
    """A sliding run saved with the attribute keys written before the rename."""
    model = cs.SlidingModel(friction_load="dynamic")
    dataset = cs.simulate(model, kane_levinson, cs.InitialState(), 0.05).dataset.copy()
    for old, new in RENAMED_ATTRIBUTES.items():
        dataset.attrs[old] = dataset.attrs.pop(new)
    return write(dataset, tmp_path_factory.mktemp("old") / "old.nc")


def test_an_old_run_file_reads_under_the_new_names(old_run_file: Path) -> None:
    attrs = read_run(old_run_file).attrs
    assert attrs["friction_load"] == "dynamic"
    assert attrs["initial_euler_angles_deg"] == "[0.5, 0.5]"
    assert not set(RENAMED_ATTRIBUTES) & set(attrs)


def test_an_old_run_file_plots_and_labels(
    old_run_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    figure = tmp_path / "old.png"
    assert main(["plot", str(old_run_file), "--out", str(figure)]) == 0
    assert figure.stat().st_size > 0
    capsys.readouterr()
    with xr.open_dataset(old_run_file) as opened:  # read without read_run
        assert run_label(opened).endswith("dynamic N")


def test_old_reproduction_data_reads_under_the_new_key(tmp_path: Path) -> None:
    (tmp_path / "data").mkdir()
    case = {"model": "sliding", "normal_force": "static"}
    # a result as a target wrote it (every one names its study and t_end), keyed the old way
    result = {"target": "fig2", "body": "b", "study": "b", "t_end": 20.0, "cases": [case]}
    (tmp_path / "data" / "fig2_b.json").write_text(json.dumps(result), encoding="utf-8")
    assert collect(tmp_path)["fig2"]["b"]["cases"] == [
        {"model": "sliding", "friction_load": "static"}
    ]


def test_did_you_mean_is_implemented_once() -> None:
    """Every "did you mean" goes through ``errors.did_you_mean``: difflib is used there only."""
    source = Path(cs.__file__).parent
    users = [
        path.relative_to(source).as_posix()
        for path in source.rglob("*.py")
        if re.search(r"^\s*(import difflib|from difflib)", path.read_text("utf-8"), re.M)
    ]
    assert users == ["errors.py"]
