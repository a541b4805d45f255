"""Messages: validation at the boundary, JSON round trips, schemas."""

from __future__ import annotations

import json
import math
from typing import Annotated

import pytest
from pydantic import TypeAdapter

import shared.messages
from shared.errors import InvalidInputError
from shared.messages import (
    CommandFrames,
    Decision,
    ErrorReply,
    ExecutedJointStates,
    IKRequest,
    JointPath,
    PlanRequest,
    PointDecision,
    ReachTarget,
    Trajectory,
    WristPath,
    parse,
)
from shared.messages.base import Message
from shared.primitives import BY_NAME
from shared.robot import Side


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
    with pytest.raises(
        InvalidInputError, match=r"sample 2 \(t = 0.1 s\) comes 0 s after sample 1"
    ):
        parse(WristPath, {"times": [0.0, 0.1, 0.1], "positions": [[0.1, 0, 0]] * 3})


def _timed(times: list[float]) -> dict[str, dict[str, object]]:
    """A joint path, a trajectory and command frames at ``times``, by class."""
    n, row = len(times), [0.0] * 5
    names = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]
    common = {"arm": "right", "joint_names": names, "times": times}
    return {
        "JointPath": common
        | {"positions": [row] * n, "primitives": ["x"] * n, "wrist": [[0, 0, 0]] * n},
        "Trajectory": common
        | {
            "positions": [row] * n,
            "velocities": [row] * n,
            "accelerations": [row] * n,
            "primitives": ["x"] * n,
            "wrist_path": [[0, 0, 0]] * n,
        },
        "CommandFrames": common | {"rate": 25.0, "start": row, "positions": [row] * n},
    }


@pytest.mark.parametrize(
    ("times", "message"),
    [
        ([1.0, 1.0 + 1e-15], r"sample 1 \(t = 1 s\) comes 1.11e-15 s after sample 0"),
        ([1.0, 0.5], r"sample 1 \(t = 0.5 s\) comes -0.5 s after sample 0"),
        ([1.0, 1e308], r"times\[1\] is 1e\+308 s: times must be finite and within"),
        ([1.0, 90_001.0], r"the times span 90000 s, more than 86400 s \(a day\)"),
    ],
)
def test_every_timed_message_checks_its_times(times: list[float], message: str) -> None:
    """Steps under a microsecond once made NaN speeds (an internal error),
    1e308 s overflowed, and a joint path's times were not checked at all;
    clock timestamps (Unix time) pass, a microsecond apart."""
    classes = {"JointPath": JointPath, "Trajectory": Trajectory}
    for name, data in _timed(times).items():
        with pytest.raises(InvalidInputError, match=message):
            parse(classes.get(name, CommandFrames), data)
    for fine in ([0.5, 0.5 + 1e-6, 1.0], [1.7e9, 1.7e9 + 0.01]):
        for name, data in _timed(fine).items():
            parse(classes.get(name, CommandFrames), data)


def test_measured_times_need_only_increase() -> None:
    """Readings of the robot may come closer than a microsecond apart."""
    row = [0.0] * 5
    states = ExecutedJointStates(
        arm="right",
        joint_names=["a"] * 5,
        times=[0.0, 1e-9],
        measured=[row, row],
        commanded=[row, row],
    )
    assert states.times == [0.0, 1e-9]


@pytest.mark.parametrize(
    ("end", "message"),
    [
        (600.01, r"the path lasts .* longer than 600 s"),
        (1e308, r"times\[1200\] is 1e\+308 s"),
    ],
)
def test_wrist_path_lasts_at_most_ten_minutes(end: float, message: str) -> None:
    """A path longer than 600 s is refused with its duration (1e308 s once
    overflowed the motion decision's arithmetic); 600 s is accepted. (Two
    a second: a path sampled less than once a second is refused.)"""
    times = [0.5 * k for k in range(1200)] + [end]
    with pytest.raises(InvalidInputError, match=message):
        parse(WristPath, {"times": times, "positions": [[0.1, 0, 0]] * len(times)})
    times = [0.5 * k for k in range(1201)]
    assert times[-1] == 600.0
    parse(WristPath, {"times": times, "positions": [[0.1, 0, 0]] * len(times)})


@pytest.mark.parametrize(
    ("scale", "hint"),
    [
        (
            1000.0,
            "these look like milliseconds: divide them by 1000 (times are in "
            "seconds), or, if they are seconds, give a sample every 1 s or less",
        ),
        (1e-3, "times must be in seconds"),
    ],
)
def test_wrist_path_times_must_be_seconds(scale: float, hint: str) -> None:
    """A 0.8 s path sampled at 100 Hz with its times in milliseconds is refused
    as such (it was taken for an 800 s path, refused only for lasting over
    600 s, and a 0.5 s one for a 500 s reach), as are times a thousand times
    too fast; a sample a second still passes."""
    times = [0.01 * k * scale for k in range(81)]
    with pytest.raises(InvalidInputError) as info:
        parse(WristPath, {"times": times, "positions": [[0.1, 0, 0]] * 81})
    step, rate = 0.01 * scale, 100.0 / scale
    assert info.value.message.startswith(
        f"invalid WristPath: times: the wrist path: the times step {step:.4g} "
        f"apart (median), a sample rate of {rate:.4g} Hz if they are seconds; "
        f"wrist paths are sampled at 1 to 10000 Hz: {hint}"
    )
    assert info.value.field == "times"
    parse(WristPath, {"times": [0.0, 1.0, 2.0], "positions": [[0.1, 0, 0]] * 3})


def test_wrist_path_lengths_must_match() -> None:
    """Times and positions need the same length; the error names positions."""
    with pytest.raises(InvalidInputError, match="2 times but 1 positions") as info:
        parse(WristPath, {"times": [0.0, 0.1], "positions": [[0.1, 0, 0]]})
    assert info.value.field == "positions"


@pytest.mark.parametrize("first", [-5.0, 1.0, 1.7e9])
def test_wrist_path_times_start_at_zero(first: float) -> None:
    """Times are from the movement's start: a path starting at -5 s, 1 s or
    at a Unix timestamp is refused naming times (the planner kept them, and
    the trajectory started there), inside a plan request as wrist_path.times."""
    times = [first + 0.01 * k for k in range(3)]
    path = {"times": times, "positions": [[0.1, 0, 0]] * 3}
    with pytest.raises(InvalidInputError, match="subtract the first time") as info:
        parse(WristPath, path)
    assert info.value.field == "times"
    assert f"starts at t = {first:.9g} s, not 0" in info.value.message
    with pytest.raises(InvalidInputError) as info:
        parse(PlanRequest, json.dumps({"wrist_path": path}))
    assert info.value.field == "wrist_path.times"
    times = [0.01 * k for k in range(3)]
    assert parse(WristPath, {"times": times, "positions": [[0.1, 0, 0]] * 3})


def test_a_path_of_the_longest_duration_at_100_hz_is_accepted() -> None:
    """600 s (MAX_DURATION) at 100 Hz is 60 001 samples, both ends included:
    it was refused as more than 60 000 (MAX_SAMPLES was one short)."""
    times = [k / 100 for k in range(60_001)]
    path = parse(WristPath, {"times": times, "positions": [[0.1, 0, 0]] * 60_001})
    assert len(path.times) == 60_001 and path.times[-1] == 600.0
    with pytest.raises(InvalidInputError, match="at most 60001 items"):
        parse(
            WristPath, {"times": [*times, 600.005], "positions": [[0.1, 0, 0]] * 60_002}
        )


@pytest.mark.parametrize(
    ("data", "field"),
    [
        ({}, "targets"),
        ({"targets": [{"position": [0.1, 0, 0]}], "wrist_path": "PATH"}, "wrist_path"),
        ({"arm": "right", "wrist_path": "LEFT"}, "arm"),
        ({"wrist_path": "PATH", "rate": 50}, "rate"),
        (
            {"targets": [{"position": [0.1, 0, 0]}], "path_tolerance": 0.01},
            "path_tolerance",
        ),
        ([], ""),
        ("[1, 2", ""),
    ],
    ids=["neither", "both", "arm", "rate", "tolerance", "array", "not-json"],
)
def test_a_request_error_names_the_field_at_fault(data: object, field: str) -> None:
    """An error of the request as a whole names the field at fault, or ""
    when the whole payload is (it named "message", which is no field)."""
    path = {"times": [0.0, 0.01], "positions": [[0.1, 0, 0]] * 2}
    if isinstance(data, dict) and data.get("wrist_path") == "PATH":
        data = data | {"wrist_path": path}
    if isinstance(data, dict) and data.get("wrist_path") == "LEFT":
        data = data | {"wrist_path": path | {"arm": "left"}}
    text = data if isinstance(data, str) else json.dumps(data)
    with pytest.raises(InvalidInputError) as info:
        parse(PlanRequest, text)
    assert info.value.field == field
    assert "message" not in info.value.message.split(":")[1]


def test_empty_path_and_empty_task_are_refused() -> None:
    """An empty path or a task without targets is an error naming the field."""
    with pytest.raises(InvalidInputError, match="times"):
        parse(WristPath, {"times": [], "positions": []})
    with pytest.raises(InvalidInputError, match="targets"):
        parse(PlanRequest, {"targets": []})


def test_a_path_of_one_sample_is_refused() -> None:
    """One sample has no step: it was planned as a 0 s trajectory, a single
    far posture. Refused naming the times, as a PlanRequest over the bus
    reads it too."""
    one = {"times": [0.0], "positions": [(0.12, -0.13, 0.05)]}
    with pytest.raises(InvalidInputError) as refused:
        parse(PlanRequest, {"wrist_path": one})
    assert refused.value.field == "wrist_path.times"
    assert "a wrist path needs at least 2 samples, this one has 1" in str(
        refused.value.message
    )
    two = {"times": [0.0, 0.01], "positions": [(0.12, -0.13, 0.05)] * 2}
    assert len(parse(WristPath, two).times) == 2


def test_palm_direction_is_normalised_and_nonzero() -> None:
    """A palm direction is stored with unit length; the zero vector is refused."""
    assert parse(ReachTarget, {"position": [0, 0, 0], "palm": [0, 0, 2]}).palm == (
        0,
        0,
        1,
    )
    with pytest.raises(InvalidInputError, match="zero vector"):
        parse(ReachTarget, {"position": [0, 0, 0], "palm": [0, 0, 0]})


@pytest.mark.parametrize("size", [1e-6, 1.0, 1e300, 1e308])
def test_a_direction_of_any_finite_size_becomes_unit(size: float) -> None:
    """Huge parts do not overflow the length to infinity (and the direction to
    zero); tiny ones below 1e-9 are the zero vector."""
    palm = parse(ReachTarget, {"position": [0, 0, 0], "palm": [size, size, 0]}).palm
    assert palm == pytest.approx((math.sqrt(0.5), math.sqrt(0.5), 0.0), rel=1e-15)
    with pytest.raises(InvalidInputError, match="zero vector"):
        parse(ReachTarget, {"position": [0, 0, 0], "palm": [1e-300, 0, 0]})


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


@pytest.mark.parametrize(
    ("point_times", "problem"),
    [
        ([[0.0, 0.01], []], r"point_times\[1\] is empty"),
        ([[0.0, 0.01], [0.005]], r"point_times \(joined\) must not decrease"),
        ([[0.0, 0.02]], r"point_times end at 0.02 s, after the trajectory's 0.01 s"),
    ],
)
def test_a_trajectory_s_point_times_follow_it(
    point_times: list[list[float]], problem: str
) -> None:
    """When the trajectory passes its paths' points: a time per point, not
    decreasing along the task, within its span; a rest (two points at one
    time) passes. Left out of the JSON when not given."""
    row = [0.0] * 5
    data = {
        "arm": "right",
        "joint_names": ["a", "b", "c", "d", "e"],
        "times": [0.0, 0.01],
        "positions": [row, row],
        "velocities": [row, row],
        "accelerations": [row, row],
        "primitives": ["S_R E_P W_P"] * 2,
        "wrist_path": [[0, 0, 0]] * 2,
    }
    assert "point_times" not in parse(Trajectory, data).to_json()
    good = parse(Trajectory, data | {"point_times": [[0.0, 0.01], [0.01]]})
    assert good.point_times == [[0.0, 0.01], [0.01]]
    with pytest.raises(InvalidInputError, match=problem):
        parse(Trajectory, data | {"point_times": point_times})


def test_every_message_has_a_json_schema() -> None:
    """Each message gives a JSON schema naming its fields (for MCAP channels)."""
    for cls in (
        PlanRequest,
        WristPath,
        Decision,
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


def _decision(**change: object) -> dict[str, object]:
    good = {
        "arm": "right",
        "times": [0.0, 0.01],
        "primitives": ["S_R E_P W_P", "S_R E_PR W_P"],
        "candidates": ["S_R E_P W_P", "S_R E_PR W_P"],
        "g": [[0.4, 0.1], [0.3, 0.5]],
        "matrices": {
            "S_R E_P W_P": [[0, 1, 1], [1, 0, 0], [0, 0, 0]],
            "S_R E_PR W_P": BY_NAME["S_R E_PR W_P"].matrix,
        },
    }
    return good | change


@pytest.mark.parametrize(
    ("change", "problem"),
    [
        ({"primitives": ["S_R E_P W_P", "S_X"]}, "primitives.1.: unknown .* 'S_X'"),
        ({"primitives": ["S_R E_P W_P"]}, "2 times but 1 primitives and 2 rows of g"),
        ({"g": [[0.4, 0.1]]}, "2 times but 2 primitives and 1 rows of g"),
        ({"g": [[0.4, 0.1], [0.3]]}, "g\\[1\\] has 1 values, expected 2"),
        ({"g": [[0.4, 0.1], [0.3, float("nan")]]}, "finite number"),
        ({"candidates": ["S_R E_P W_P", "extra"]}, "candidates.1.: unknown .* 'extra'"),
        ({"candidates": ["W_R", "W_R"]}, "a primitive is named twice"),
        ({"matrices": {"S_R E_P W_P": BY_NAME["S_R E_P W_P"].matrix}}, "no matrix for"),
        (
            {"matrices": {"S_R E_P W_P": [[1, 1, 1], [0, 0, 0], [0, 0, 0]],
                          "S_R E_PR W_P": BY_NAME["S_R E_PR W_P"].matrix}},
            "is not the matrix of 'S_R E_P W_P'",
        ),
        ({"trajectory_times": [0.5]}, "2 times but 1 trajectory_times: one per time"),
        (
            {"trajectory_times": [0.5, 0.25]},
            "trajectory_times must not decrease: trajectory_times.1. = 0.25 s",
        ),
        ({"trajectory_times": [-0.1, 0.25]}, "trajectory_times.0. is -0.1 s"),
        ({"trajectory_times": [0.0, 1e9]}, "trajectory_times.1. is 1e.09 s"),
    ],
)  # fmt: skip
def test_a_decision_must_agree_with_the_primitives(
    change: dict[str, object], problem: str
) -> None:
    """A decision names known primitives with their own matrices, and has one
    winner and one row of g (one value per candidate) per time."""
    good = parse(Decision, json.dumps(_decision()))
    assert good.primitives == ["S_R E_P W_P", "S_R E_PR W_P"]
    assert good.points[1].g == {"S_R E_P W_P": 0.3, "S_R E_PR W_P": 0.5}
    assert good.points[1].matrix == BY_NAME["S_R E_PR W_P"].matrix
    with pytest.raises(InvalidInputError, match=problem):
        parse(Decision, _decision(**change))


def test_a_decision_s_trajectory_times_are_optional_and_kept() -> None:
    """Without them the JSON has no key (what it was before they existed);
    with them (two points passed at once allowed) they read back."""
    assert "trajectory_times" not in parse(Decision, _decision()).to_json()
    timed = parse(Decision, _decision(trajectory_times=[1.5, 1.5]))
    assert parse(Decision, timed.to_json()).trajectory_times == [1.5, 1.5]


def test_a_decision_of_points_reads_back_point_by_point() -> None:
    """Decision.of_points and Decision.points are inverse: the same records."""
    points = [
        PointDecision(name, BY_NAME[name].matrix, {"W_R": 0.1 * k, "S_R W_P": 1.0 + k})
        for k, name in enumerate(["S_R E_P W_P", "S_R W_P", "S_R W_P"])
    ]
    decision = Decision.of_points("left", [0.0, 0.5, 1.0], points)
    assert decision.points == points
    assert decision.candidates == ["W_R", "S_R W_P"]
    assert set(decision.matrices) == {"S_R E_P W_P", "S_R W_P"}
    assert parse(Decision, decision.to_json()) == decision


def test_a_wrist_path_reads_its_arm_as_a_task_does() -> None:
    """A wrist path's arm in any case, as PlanRequest's ("LEFT" was refused
    there while the task's own arm took it); left out, the wire default
    (right) stays for a path sent on its own."""
    samples = {"times": [0.0, 0.01], "positions": [[0.1, 0.1, 0.0]] * 2}
    assert parse(WristPath, {**samples, "arm": "LEFT"}).arm == "left"
    assert parse(WristPath, samples).arm == "right"
    with pytest.raises(InvalidInputError, match="arm"):
        parse(WristPath, {**samples, "arm": "middle"})


#: Every message with an arm, by name.
WITH_AN_ARM = {
    name: kind
    for name in shared.messages.__all__
    if isinstance(kind := getattr(shared.messages, name), type)
    and issubclass(kind, Message)
    and "arm" in kind.model_fields
    and kind.model_fields["arm"].annotation is Side
}


def test_an_ik_request_reads_its_arm_in_any_case() -> None:
    """ "LEFT" over the wire was refused by ``ik/solve`` (invalid_input)
    while --arm, a task and a wrist path take it."""
    request = parse(IKRequest, {"arm": "LEFT", "target": [0.12, 0.13, 0.05]})
    assert request.arm is Side.LEFT
    assert request.to_json() == IKRequest(arm="left", target=request.target).to_json()
    with pytest.raises(InvalidInputError, match="unknown arm 'both'"):
        parse(IKRequest, {"arm": "both", "target": [0.12, 0.13, 0.05]})


@pytest.mark.parametrize("name", sorted(WITH_AN_ARM))
def test_every_message_reads_its_arm_in_any_case(name: str) -> None:
    """Each message's arm field reads " Left " and "LEFT" as left, strictly
    from JSON, and refuses what is no arm: one rule at every boundary."""
    field = WITH_AN_ARM[name].model_fields["arm"]
    arm = TypeAdapter(Annotated[(field.annotation, *field.metadata)])
    for spelling in ('" Left "', '"LEFT"', '"left"'):
        assert arm.validate_json(spelling, strict=True) is Side.LEFT
    with pytest.raises(ValueError, match="unknown arm 'up'"):
        arm.validate_json('"up"', strict=True)


def test_a_request_names_its_arm_on_its_wrist_path_alone() -> None:
    """A request naming no arm was for the right one, so a path naming the
    left was refused ('wrist_path is for the left arm, the request for the
    right'); it is a left request, and round-trips as one."""
    samples = {"times": [0.0, 0.01], "positions": [[0.1, 0.1, 0.0]] * 2}
    request = parse(PlanRequest, json.dumps({"wrist_path": samples | {"arm": "left"}}))
    assert request.arm == "left" and "arm" not in request.model_fields_set
    assert parse(PlanRequest, request.to_json()) == request
    with pytest.raises(InvalidInputError, match="for the left arm, the request for"):
        parse(
            PlanRequest,
            json.dumps({"arm": "right", "wrist_path": samples | {"arm": "left"}}),
        )


@pytest.mark.parametrize("pace", [{"rate": 50.0}, {"fastest": True}])
def test_a_wrist_path_refuses_a_pace_or_rate(pace: dict[str, object]) -> None:
    """A wrist path keeps its times: a rate or fastest beside it was
    silently ignored (a 50 Hz path asked at 10 Hz gave 50 Hz samples)."""
    samples = {"times": [0.0, 0.01], "positions": [[0.1, -0.1, 0.0]] * 2}
    with pytest.raises(InvalidInputError, match="a wrist_path keeps its own times"):
        parse(PlanRequest, json.dumps({"wrist_path": samples} | pace))
    assert parse(PlanRequest, json.dumps({"wrist_path": samples, "rate": 100}))
