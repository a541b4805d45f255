"""Demonstration messages: validation at the boundary, JSON and schemas."""

from __future__ import annotations

import math

import pytest

from shared.errors import InvalidInputError
from shared.messages import parse
from shared.messages.demo import DemoSample, DemoSubject

SAMPLE = {
    "subject": "S01",
    "trial": 3,
    "point": 7,
    "arm": "right",
    "time": 0.12,
    "shoulder": [0.0, -0.098, 0.1],
    "elbow": [0.01, -0.12, 0.0],
    "wrist": [0.03, -0.13, -0.05],
    "wrist_orientation": [2.0, 0.0, 0.0, 0.0],
    "target": [0.12, -0.09, 0.05],
    "primitive": "S_R  E_PR W_P",
}


def test_sample_round_trip_and_normalisation() -> None:
    """A sample survives JSON; quaternions are normalised, names tidied."""
    sample = parse(DemoSample, SAMPLE)
    assert sample.wrist_orientation == (1.0, 0.0, 0.0, 0.0)
    assert sample.primitive == "S_R E_PR W_P"
    assert parse(DemoSample, sample.to_json()) == sample


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("primitive", "S_R X_Y", "unknown movement primitive"),
        ("primitive", "W_R", "'W_R' is a function primitive"),
        ("primitive", "S_R E_P W_R", "a demonstration is labelled with a motion"),
        ("wrist_orientation", [0.0, 0.0, 0.0, 0.0], "must not be zero"),
        ("elbow", [0.0, math.nan, 0.0], "elbow.1"),
        ("time", -0.01, "time"),
        ("trial", -1, "trial"),
        ("subject", "", "subject"),
    ],
)
def test_bad_samples_name_the_field(field: str, value: object, message: str) -> None:
    """Each malformed field gives an InvalidInputError that names it."""
    with pytest.raises(InvalidInputError, match=message):
        parse(DemoSample, {**SAMPLE, field: value})


def test_unknown_fields_are_refused() -> None:
    """An extra field is an error, not silently dropped."""
    with pytest.raises(InvalidInputError, match="colour"):
        parse(DemoSample, {**SAMPLE, "colour": "red"})


def test_subject_sizes_are_checked() -> None:
    """Segment lengths must be positive and plausible."""
    with pytest.raises(InvalidInputError, match="upper_arm"):
        parse(DemoSubject, {"name": "S01", "upper_arm": 0.0, "forearm": 0.25})
    subject = DemoSubject(name="S01", upper_arm=0.33, forearm=0.26)
    assert subject.stature is None


def test_schemas_are_json_schemas() -> None:
    """The models give the JSON schemas of their MCAP channels."""
    schema = DemoSample.json_schema()
    assert schema["title"] == "DemoSample"
    assert {"shoulder", "elbow", "wrist", "target"} <= set(schema["properties"])
