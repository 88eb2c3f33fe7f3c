"""Model settings and friction laws are declared once (``models.SETTINGS``,
``contact.laws``): every model field has its row, every row reaches the kernel record, the
command line and the run's attributes, and every law and pressure of the kernels has words."""

from __future__ import annotations

from dataclasses import fields

import pytest

import celtstone as cs
from celtstone.cli.main import build_parser
from celtstone.contact import CONTACT_PRESSURES, FRICTION_LAWS, LAW_WORDS, PRESSURE_WORDS
from celtstone.kernels.layout import PARAMETERS, ContactPressure, FrictionLaw, FrictionLoad
from celtstone.simulation.models import MODEL_KINDS, SETTINGS, kernel_parameters, setting_defaults
from celtstone.simulation.schema import PARAMETERS as SCHEMA


@pytest.mark.parametrize("kind", list(MODEL_KINDS))
def test_every_model_field_is_a_declared_setting(kind: str) -> None:
    for field in fields(MODEL_KINDS[kind]):  # type: ignore[arg-type]
        assert field.name in SETTINGS, (kind, field.name)


@pytest.mark.parametrize("name", list(SETTINGS))
def test_every_setting_is_checked_offered_and_recorded(name: str) -> None:
    setting = SETTINGS[name]
    if setting.choices is None:
        assert name in SCHEMA, "a number's unit and range come from schema.PARAMETERS"
    if setting.record is not None:
        assert setting.record in PARAMETERS.names
    assert setting_defaults(name), "some kind of model has it"
    run = next(a for a in build_parser()._actions if a.dest == "command").choices["run"]  # type: ignore[index]
    assert any(name == action.dest for action in run._actions), "offered by celtstone run"


@pytest.mark.parametrize(
    ("setting", "enum"),
    [
        ("friction_law", FrictionLaw),
        ("contact_pressure", ContactPressure),
        ("friction_load", FrictionLoad),
    ],
)
def test_choices_are_the_kernel_codes(setting: str, enum: type) -> None:
    assert SETTINGS[setting].choices == {member.name.lower(): member.value for member in enum}


def test_every_law_and_pressure_has_words() -> None:
    assert set(LAW_WORDS) == set(FRICTION_LAWS)
    assert set(PRESSURE_WORDS) == set(ContactPressure)
    assert sorted(FRICTION_LAWS.values()) == sorted(law.value for law in FrictionLaw)
    assert set(CONTACT_PRESSURES) == {p.name.lower() for p in ContactPressure}


@pytest.mark.parametrize("law", list(FRICTION_LAWS))
@pytest.mark.parametrize("pressure", list(CONTACT_PRESSURES))
def test_a_sliding_model_reaches_the_record_and_the_attributes(law: str, pressure: str) -> None:
    model = cs.SlidingModel(
        friction_coefficient=0.3, contact_radius=2e-3, friction_law=law, contact_pressure=pressure
    )
    record = kernel_parameters(model, cs.load_body("kane_levinson_1982"))
    assert record.friction_coefficient == 0.3 and record.contact_radius == 2e-3
    assert record.friction_law == FRICTION_LAWS[law]
    assert record.contact_pressure == CONTACT_PRESSURES[pressure]
    attributes = model.attributes()
    assert attributes["friction_law"] == law and attributes["contact_pressure"] == pressure
    assert attributes["elastic_modulus"] == "none"


def test_hybrid_defaults_differ_where_declared() -> None:
    assert setting_defaults("regularisation_speed") == {"sliding": 1e-10, "hybrid": 1e-12}
    assert set(setting_defaults("capture_speed")) == {"hybrid"}
    assert set(setting_defaults("damping")) == set(MODEL_KINDS)
