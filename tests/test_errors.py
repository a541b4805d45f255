"""The error hierarchy: one root, evidence kept, wire round trips."""

from __future__ import annotations

import pytest

from shared.errors import (
    ArmplanError,
    CallerDeadlineError,
    InvalidInputError,
    JointLimitError,
    LimitViolationError,
    PrimitiveCannotReachError,
    RemoteError,
    RobotLimitsError,
    RobotStateError,
    ServiceRunningError,
    SwivelNotReachedError,
    TooFewSamplesError,
    UnknownArmError,
    UnknownPrimitiveError,
    UnreachableTargetError,
    WrongLoginError,
    error_from_wire,
)
from shared.messages import ErrorReply

EXAMPLES: list[ArmplanError] = [
    InvalidInputError("bad", field="x"),
    UnknownArmError("middle"),
    UnknownPrimitiveError("X", ["A", "B"]),
    UnreachableTargetError(
        (0.5, 0.0, 0.0), arm="right", distance=0.5, reach=(0.1, 0.2)
    ),
    PrimitiveCannotReachError("E_R W_P", (0.1, 0, 0), (0.1, 0, 0.01), 0.01, "why"),
    JointLimitError("RElbowRoll", 2.0, 0.03, 1.54),
    LimitViolationError("RElbowRoll", "velocity", 9.0, 7.19, 12, 0.12),
    TooFewSamplesError("2 samples are too few", field="demos", found=1, needed=2),
    SwivelNotReachedError(
        4.4,
        3.52,
        shortfall=-0.88,
        elbow_miss=0.029,
        joints={"RElbowYaw": 2.08567},
        joint="RElbowYaw",
        limit=2.08567,
    ),
    WrongLoginError(source="secure/client.json5", expected="bridge", given="client"),
    RobotStateError("tcp://127.0.0.1:9559", "not awake", outcome="nothing was sent"),
    RobotLimitsError("tcp://127.0.0.1:9559", "RShoulderRoll", "upper", -0.0087, 0.3),
    CallerDeadlineError(
        "tcp://127.0.0.1:9559", 0.35, None, 6.0, outcome="nothing was sent"
    ),
    ServiceRunningError("bridge", key="armplan/alive/bridge", why="two bridges"),
]


@pytest.mark.parametrize("error", EXAMPLES, ids=lambda e: type(e).__name__)
def test_every_error_derives_from_the_root(error: ArmplanError) -> None:
    """All errors are ArmplanErrors with a kind, a message and evidence."""
    assert isinstance(error, ArmplanError)
    assert error.kind and error.message and isinstance(error.evidence, dict)


@pytest.mark.parametrize("error", EXAMPLES, ids=lambda e: type(e).__name__)
def test_errors_round_trip_over_the_wire(error: ArmplanError) -> None:
    """to_wire -> ErrorReply JSON -> to_error rebuilds the same class and evidence."""
    reply = ErrorReply.model_validate_json(ErrorReply.from_error(error).to_json())
    again = reply.to_error()
    assert type(again) is type(error)
    assert again.message == error.message and again.evidence == error.evidence


def test_unknown_kind_becomes_a_remote_error() -> None:
    """An error kind this side does not know arrives as RemoteError."""
    error = error_from_wire({"kind": "martian", "message": "m", "evidence": {"a": 1}})
    assert isinstance(error, RemoteError) and error.message == "m"


def test_messages_name_the_evidence() -> None:
    """Messages state the facts: target, distance, limits, sample."""
    assert "0.5000 m from the right shoulder" in str(EXAMPLES[3])
    assert "RElbowRoll velocity 9 rad/s at sample 12 (t = 0.120 s)" in str(EXAMPLES[6])
    assert UnknownArmError("middle").evidence == {"field": "arm", "name": "middle"}


def test_a_joint_just_outside_its_range_does_not_read_as_its_bound() -> None:
    """0.0349065 against a lower limit 0.0349066 once printed both as 0.03491
    ("0.03491 is outside [0.03491, ...]"); enough decimals now tell them apart,
    and a value far outside keeps five."""
    near = str(JointLimitError("RElbowRoll", 0.0349065, 0.0349066, 1.54462))
    assert "RElbowRoll = 0.0349065 rad is outside its range [0.0349066, 1.5446200]" in (
        near
    )
    far = str(JointLimitError("RElbowRoll", 2.0, 0.0349066, 1.54462))
    assert "RElbowRoll = 2.00000 rad is outside its range [0.03491, 1.54462]" in far


def test_a_subclass_of_the_same_kind_leaves_the_kind_to_its_parent() -> None:
    """CallerGoneError is a caller_deadline too (its own message): read from
    the wire, a caller_deadline is a CallerDeadlineError; it used to be
    rebuilt as whichever subclass was defined last."""
    from shared.errors import CallerDeadlineError, CallerGoneError, error_from_wire

    gone = CallerGoneError(
        "tcp://127.0.0.1:9559", None, 2.0, outcome="nothing was sent", overhead=0.1
    )
    assert gone.kind == "caller_deadline"
    back = error_from_wire(gone.to_wire())
    assert type(back) is CallerDeadlineError
    assert back.message == gone.message
    assert "the caller's session ended (interrupted or killed)" in back.message


def test_a_gone_callers_error_read_from_the_wire_is_a_whole_deadline_error() -> None:
    """Read from the wire, a CallerGoneError is a CallerDeadlineError: it
    has the attributes that class documents (it lacked ``left``,
    ``approach``, ``duration`` and ``overhead``: an AttributeError for a
    script reading them), and its message does not say that nothing moved
    after the approach had played."""
    from shared.errors import CallerDeadlineError, CallerGoneError, error_from_wire

    outcome = "the arm is at the trajectory's start; nothing of the trajectory was sent"
    gone = CallerGoneError("tcp://x:9559", 0.0, 2.0, outcome=outcome, overhead=0.1)
    back = error_from_wire(gone.to_wire())
    assert isinstance(back, CallerDeadlineError)
    assert (back.left, back.approach, back.duration, back.overhead) == (
        0.0,
        0.0,
        2.0,
        0.1,
    )
    assert (
        back.evidence.keys()
        == CallerDeadlineError("u", 1.0, 0.0, 2.0, outcome="o").evidence.keys()
    )
    assert "before the movement started" not in back.message
    assert f"before the trajectory was played; {outcome}" in back.message
