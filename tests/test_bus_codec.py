"""What a service sends back for each request: pure functions, no Zenoh."""

from __future__ import annotations

import json

import pytest

from shared.bus import Endpoint, NoArguments, Route
from shared.bus.codec import answer, reply_error
from shared.errors import (
    ArmplanError,
    InternalServiceError,
    PayloadTooLargeError,
    RequestTimeoutError,
    ServiceBusyError,
    ServiceUnavailableError,
    UnknownArmError,
)
from shared.messages import ErrorReply, Message, Vec3


class Point(Message):
    position: Vec3


ECHO = Route("echo", "test/echo", Point, Point)
KEY = "ns/test/echo"


def echo(request: Point) -> Point:
    return request


def error_of(body: bytes) -> ArmplanError:
    return ErrorReply.model_validate_json(body).to_error()


def test_a_valid_request_gets_the_reply_json() -> None:
    """The reply is the handler's message as JSON, with the time each part took."""
    result = answer(Endpoint(ECHO, echo), b'{"position": [1, 2, 3]}', KEY, 1000)
    assert result.ok
    assert json.loads(result.body) == {"position": [1.0, 2.0, 3.0]}
    timing = result.timing
    assert timing is not None and min(timing.parse, timing.handle) > 0.0
    assert timing.total == timing.parse + timing.handle + timing.reply_json


@pytest.mark.parametrize(
    "payload,field,words",
    [
        (b'{"position": [1, 2', "", "not valid JSON"),
        (b'{"target": [1, 2, 3]}', "position", "Field required"),
        (b"{}", "position", "Field required"),
        (b'{"position": [NaN, 0, 0]}', "position.0", "finite number"),
        (b"\xff\xfe", "", "not valid JSON"),
    ],
    ids=["malformed", "wrong-schema", "missing", "nan", "not-utf8"],
)
def test_bad_requests_get_invalid_input(payload: bytes, field: str, words: str) -> None:
    """Malformed JSON, the wrong schema and NaN: invalid_input naming the field."""
    result = answer(Endpoint(ECHO, echo), payload, KEY, 1000)
    error = error_of(result.body)
    assert not result.ok and error.kind == "invalid_input" and result.timing is None
    assert error.evidence["field"] == field and words in error.message


def test_a_payload_over_the_limit_is_refused_before_parsing() -> None:
    """payload_too_large with the size, the limit and the key."""
    result = answer(Endpoint(ECHO, echo), b" " * 101, KEY, 100)
    error = error_of(result.body)
    assert isinstance(error, PayloadTooLargeError)
    assert error.message == (
        "payload of 101 bytes for ns/test/echo exceeds the limit of 100 bytes"
    )
    assert (error.size, error.limit) == (101, 100)


def test_an_armplan_error_travels_with_its_kind_and_evidence() -> None:
    """The handler's typed error comes back as itself."""

    def refuse(request: Point) -> Point:
        raise UnknownArmError("middle")

    error = error_of(
        answer(Endpoint(ECHO, refuse), b'{"position": [0,0,0]}', KEY, 99).body
    )
    assert isinstance(error, UnknownArmError) and error.evidence["name"] == "middle"


def test_an_unexpected_exception_becomes_an_internal_error() -> None:
    """A bug in a handler: internal_error naming the service, key and exception."""

    def crash(request: Point) -> Point:
        raise ZeroDivisionError("division by zero")

    error = error_of(
        answer(Endpoint(ECHO, crash), b'{"position": [0,0,0]}', KEY, 99).body
    )
    assert isinstance(error, InternalServiceError)
    assert error.message == (
        "service 'echo' failed on ns/test/echo with an unexpected ZeroDivisionError: "
        "division by zero (the service keeps running; see its log)"
    )


def test_a_reply_of_the_wrong_type_is_an_internal_error() -> None:
    """The route's reply type is enforced."""
    wrong = Route("echo", "test/echo", Point, NoArguments)
    result = answer(Endpoint(wrong, echo), b'{"position": [0,0,0]}', KEY, 99)
    assert "returned Point, not NoArguments" in error_of(result.body).message


def test_an_empty_payload_means_no_arguments() -> None:
    """A query without a payload is the empty object."""
    route = Route("fit", "fit/model", NoArguments, NoArguments)
    assert answer(Endpoint(route, lambda r: r), b"", "ns/fit/model", 10).ok


def test_odd_evidence_keeps_kind_and_message() -> None:
    """Evidence that does not serialise is dropped, never the error."""
    error = ArmplanError("odd", thing=object())
    reply = ErrorReply.model_validate_json(reply_error(error))
    assert (reply.kind, reply.message, reply.evidence) == ("armplan_error", "odd", {})


@pytest.mark.parametrize(
    "error",
    [
        ServiceUnavailableError("ik", key="armplan/ik/solve", reason="gone"),
        RequestTimeoutError("ik", key="armplan/ik/solve", timeout=1.5),
        PayloadTooLargeError(size=10, limit=5, key="k"),
        InternalServiceError("ik", key="k", error_type="ValueError", detail="d"),
        ServiceBusyError("ik", key="k", queued=3),
    ],
    ids=lambda e: type(e).__name__,
)
def test_bus_errors_round_trip(error: ArmplanError) -> None:
    """Every bus error crosses the wire as its own class with its evidence."""
    again = error_of(reply_error(error))
    assert type(again) is type(error)
    assert again.message == error.message and again.evidence == error.evidence
