"""Messages: validation at the boundary, JSON round trips, schemas."""

from __future__ import annotations

import json
import math

import pytest

from shared.errors import InvalidInputError
from shared.messages import (
    Decision,
    ErrorReply,
    IKRequest,
    JointPath,
    PlanRequest,
    PointDecision,
    ReachTarget,
    Trajectory,
    WristPath,
    parse,
)


def test_round_trip_through_json() -> None:
    """A message survives to_json and parse unchanged."""
    request = PlanRequest(
        arm="left", targets=[ReachTarget(position=(0.1, 0.12, 0.05), dwell=0.5)]
    )
    assert parse(PlanRequest, request.to_json()) == request


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_numbers_are_refused(bad: float) -> None:
    """NaN and infinities anywhere are an InvalidInputError naming the field."""
    with pytest.raises(InvalidInputError, match=r"targets\.0\.position\.1"):
        parse(PlanRequest, {"targets": [{"position": [0.1, bad, 0.0]}]})


def test_unknown_fields_are_refused() -> None:
    """An extra field is an error naming it, not silently dropped."""
    with pytest.raises(InvalidInputError, match="foo: Extra inputs are not permitted"):
        parse(IKRequest, {"target": [0.1, 0.0, 0.0], "foo": 1})


def test_malformed_json_is_a_typed_error() -> None:
    """Text that is not JSON raises InvalidInputError saying so."""
    with pytest.raises(InvalidInputError, match="not valid JSON"):
        parse(PlanRequest, "{targets: ")
    with pytest.raises(InvalidInputError, match="not valid JSON"):
        parse(PlanRequest, b"\xff\xfe")


def test_deep_nesting_is_a_typed_error() -> None:
    """Pathologically nested input gives an error, not a crash."""
    deep = "[" * 100_000 + "]" * 100_000
    with pytest.raises(InvalidInputError):
        parse(PlanRequest, deep)


def test_wrist_path_times_must_increase() -> None:
    """A wrist path with a repeated time names the sample."""
    with pytest.raises(InvalidInputError, match=r"sample 2 .* is not after sample 1"):
        parse(WristPath, {"times": [0.0, 0.1, 0.1], "positions": [[0.1, 0, 0]] * 3})


def test_wrist_path_lengths_must_match() -> None:
    """Times and positions need the same length."""
    with pytest.raises(InvalidInputError, match="2 times but 1 positions"):
        parse(WristPath, {"times": [0.0, 0.1], "positions": [[0.1, 0, 0]]})


def test_empty_path_and_empty_task_are_refused() -> None:
    """An empty path or a task without targets is an error naming the field."""
    with pytest.raises(InvalidInputError, match="times"):
        parse(WristPath, {"times": [], "positions": []})
    with pytest.raises(InvalidInputError, match="targets"):
        parse(PlanRequest, {"targets": []})


def test_palm_direction_is_normalised_and_nonzero() -> None:
    """A palm direction is stored with unit length; the zero vector is refused."""
    assert parse(ReachTarget, {"position": [0, 0, 0], "palm": [0, 0, 2]}).palm == (
        0,
        0,
        1,
    )
    with pytest.raises(InvalidInputError, match="zero vector"):
        parse(ReachTarget, {"position": [0, 0, 0], "palm": [0, 0, 0]})


def test_trajectory_rows_must_match_times() -> None:
    """A trajectory with a short velocity row names it."""
    row = [0.0] * 5
    data = {
        "arm": "right",
        "joint_names": ["a", "b", "c", "d", "e"],
        "times": [0.0, 0.01],
        "positions": [row, row],
        "velocities": [row, row[:4]],
        "accelerations": [row, row],
        "primitives": ["S_R E_P W_P"] * 2,
        "wrist_path": [[0, 0, 0]] * 2,
    }
    with pytest.raises(InvalidInputError, match=r"velocities\[1\] has 4 values"):
        parse(Trajectory, data)


def test_every_message_has_a_json_schema() -> None:
    """Each message gives a JSON schema naming its fields (for MCAP channels)."""
    for cls in (
        PlanRequest,
        WristPath,
        Decision,
        PointDecision,
        JointPath,
        Trajectory,
        ErrorReply,
    ):
        schema = cls.json_schema()
        assert schema["type"] == "object"
        assert set(schema["properties"]) == set(cls.model_fields)
        json.dumps(schema)


@pytest.mark.parametrize(
    ("change", "field", "problem"),
    [
        (
            {"targets": [{"position": [True, -0.13, 0.05]}]},
            r"targets\.0\.position\.0",
            "valid number",
        ),
        ({"rate": False}, "rate", "valid number"),
        ({"rate": "100"}, "rate", "valid number"),
        ({"fastest": 1}, "fastest", "valid boolean"),
        ({"fastest": "yes"}, "fastest", "valid boolean"),
    ],
)
def test_json_is_read_strictly(
    change: dict[str, object], field: str, problem: str
) -> None:
    """A boolean is not a number, nor a number or string a boolean, whether the
    message comes as JSON text or as plain JSON data; integers are numbers."""
    data = {"targets": [{"position": [0.12, -0.13, 0.05]}]} | change
    for given in (json.dumps(data), json.dumps(data).encode(), data):
        with pytest.raises(
            InvalidInputError, match=f"{field}: Input should be a {problem}"
        ):
            parse(PlanRequest, given)
    whole = parse(PlanRequest, '{"targets": [{"position": [0, -1, 0]}], "rate": 50}')
    assert whole.targets[0].position == (0.0, -1.0, 0.0) and whole.rate == 50.0
    assert whole.method.value == "mp" and whole.arm.value == "right"


def _decision(**point: object) -> dict[str, object]:
    good = {
        "primitive": "S_R E_P W_P",
        "matrix": [[0, 1, 1], [1, 0, 0], [0, 0, 0]],
        "g": {"S_R E_P W_P": 0.4, "S_R E_PR W_P": 0.1},
    }
    return {"arm": "right", "times": [0.0], "points": [good | point]}


@pytest.mark.parametrize(
    ("point", "problem"),
    [
        ({"primitive": "S_X"}, "points: point 0: unknown movement primitive 'S_X'"),
        ({"matrix": [[1, 1, 1], [0, 0, 0], [0, 0, 0]]}, "is not that of 'S_R E_P W_P'"),
        ({"g": {"S_R E_P W_P": 0.4, "extra": 1.0}}, "g of unknown primitive 'extra'"),
    ],
)
def test_a_decision_must_agree_with_the_primitives(
    point: dict[str, object], problem: str
) -> None:
    """A decision names known primitives with their own matrices."""
    assert parse(Decision, _decision()).primitives == ["S_R E_P W_P"]
    with pytest.raises(InvalidInputError, match=problem):
        parse(Decision, json.dumps(_decision(**point)))
