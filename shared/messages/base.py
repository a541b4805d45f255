"""The base of every armplan message, and validation at the boundary.

Messages are frozen pydantic models that reject unknown fields and non-finite
numbers. The same model gives the JSON wire format (``to_json``) and the JSON
schema of its MCAP channel (``json_schema``). Outside data enters through
:func:`parse`, which turns pydantic's ``ValidationError`` into the project's
typed :class:`~shared.errors.InvalidInputError` naming the field.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from difflib import SequenceMatcher
from typing import Annotated, Any, ClassVar, TypeVar

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    GetCoreSchemaHandler,
    SerializerFunctionWrapHandler,
    ValidationError,
    model_serializer,
)
from pydantic_core import CoreSchema

from shared.errors import InvalidInputError
from shared.messages.fail_fast import fail_fast


class FieldError(ValueError):
    """A validator's error about one field of its message (not the whole).

    A model validator's ``ValueError`` has no location in pydantic: raised
    as a ``FieldError``, :func:`parse` names ``field`` (a dotted path within
    the message that raised it) as the field at fault, instead of the whole.
    """

    def __init__(self, field: str, message: str) -> None:
        super().__init__(message)
        self.field = field


class Message(BaseModel):
    """Base of every message exchanged between armplan processes."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    @classmethod
    def __get_pydantic_core_schema__(
        cls, source: type[BaseModel], handler: GetCoreSchemaHandler
    ) -> CoreSchema:
        """pydantic's schema, each list stopping at its first wrong item.

        See ``shared.messages.fail_fast``: a list's every wrong item cost
        its own error, gigabytes for a request within ``max_payload``.
        """
        return fail_fast(handler(source))

    def to_json(self) -> str:
        """The message as compact JSON (the wire format)."""
        return self.model_dump_json()

    @classmethod
    def json_schema(cls) -> dict[str, Any]:
        """The JSON schema of this message (used for MCAP channels)."""
        return cls.model_json_schema()


class OptionalFieldsMessage(Message):
    """A message with fields that are left out of its JSON and dumps when None.

    A field added to a message that others already read and compare (the
    trajectory JSON of the SPEC) is optional: left out when ``None``, the
    message's JSON stays byte for byte what it was before the field existed.
    ``omitted_when_none`` names those fields.
    """

    omitted_when_none: ClassVar[tuple[str, ...]] = ()

    @model_serializer(mode="wrap")
    def _omit_none(self, handler: SerializerFunctionWrapHandler) -> Any:
        data = handler(self)
        for name in self.omitted_when_none:
            if getattr(self, name) is None:
                data.pop(name, None)
        return data


def unit_direction(v: Sequence[float]) -> tuple[float, float, float]:
    """``v`` (3 finite values) scaled to unit length; ValueError if zero.

    Its largest part is divided out first, so that huge finite values (1e308)
    do not overflow to a zero vector.
    """
    scale = max(abs(v[0]), abs(v[1]), abs(v[2]))
    if scale == 0.0:
        raise ValueError("a direction must not be the zero vector")
    u = (v[0] / scale, v[1] / scale, v[2] / scale)
    norm = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    if scale * norm < 1e-9:
        raise ValueError(
            f"a direction must not be the zero vector (its length {scale * norm:g} "
            "is under 1e-9)"
        )
    return (u[0] / norm, u[1] / norm, u[2] / norm)


#: Frame rates [Hz] (the bridge's, the export's) and the most a plan may be
#: sampled at: at least 1 (a slower timeline cannot show a reach that lasts
#: about a second, and its period overflows the timing's arithmetic long
#: before 1e-300 Hz), at most 1000. A plan's own floor is ``MIN_PLAN_RATE``.
MIN_RATE, MAX_RATE = 1.0, 1000.0
#: Sample rates a plan may ask for [Hz]: at least 16. The robot bridge and
#: ``armplan export`` refuse a trajectory whose curve between samples strays
#: from its positions' own by more than a joint's tolerance
#: (``bridge.velocity_agreement``); any trajectory within the bridge's jerk
#: limits passes sampled at ``fine_rate`` or more, at most 15.5 Hz (WristYaw;
#: ``tests/test_plan_rate_floor.py`` holds the two together). Coarser plans
#: were planned and then refused (a reach at 5 Hz strayed 0.9 degree, at 2 Hz
#: 7.8), or passed by luck of the movement.
MIN_PLAN_RATE = 16.0
#: A plan's sample rate unless it asks for another [Hz].
DEFAULT_PLAN_RATE = 100.0

#: A point or vector in the torso frame [m] (or unitless for directions).
Vec3 = tuple[float, float, float]
#: A direction in the torso frame, normalised to unit length on input.
Direction = Annotated[Vec3, AfterValidator(unit_direction)]
#: Five joint angles in the paper's order (ShoulderPitch .. WristYaw) [rad].
JointVector = tuple[float, float, float, float, float]

M = TypeVar("M", bound=BaseModel)


def describe_validation_error(error: ValidationError) -> tuple[str, str]:
    """(field path, readable message) of the first problem in ``error``.

    A key that is no field beside a field that is missing, in one object
    (``{"phase": ...}`` for ``phases``), is a misspelt key: it is told first,
    with the field it may have meant, not as "Field required; and 1 more
    problem".
    """
    return _describe(error.errors(include_url=False))


def _describe(errors: Sequence[Any]) -> tuple[str, str]:
    """:func:`describe_validation_error` of ``errors`` (pydantic's list)."""
    misspelt = _misspelt_key(errors)
    if misspelt is not None:
        extra, missing = misspelt
        loc, meant = _dotted(extra["loc"]), _dotted(missing["loc"])
        problem = f"{loc} is not a field (did you mean {meant}?)"
        return loc, problem + _more(len(errors) - 2)
    first = errors[0]
    loc = _dotted(_location(first))
    problem = first["msg"].removeprefix("Value error, ")
    whole = not isinstance(first.get("ctx", {}).get("error"), FieldError)
    said = "got " in problem  # a validator's own "..., got (...)"
    if "input" in first and first["type"] not in ("missing",) and whole and not said:
        # A FieldError's input is its whole message, not the field's value.
        shown = repr(first["input"])
        if len(shown) > 60:
            shown = shown[:57] + "..."
        problem = f"{problem} (got {shown})"
    where = f"{loc}: " if loc else ""
    return loc, f"{where}{problem}{_more(len(errors) - 1)}"


def _location(error: Any) -> tuple[int | str, ...]:
    """Where ``error`` is: its loc, and the field a ``FieldError`` names."""
    loc = tuple(error["loc"])
    cause = error.get("ctx", {}).get("error")
    if isinstance(cause, FieldError):
        loc += tuple(cause.field.split("."))
    return loc


def _misspelt_key(errors: Sequence[Any]) -> tuple[Any, Any] | None:
    """(the extra key's error, the missing field's) of one object, or None.

    The first missing field beside which a key that is no field stands and
    looks like a misspelling of it (``_alike``); of several such keys, the
    one whose name is closest to the field's. An unrelated extra key (a
    ``comment`` beside a missing ``trajectory``) is no misspelling: then
    the errors are reported as they come. With more than
    ``MISSPELT_SEARCH`` errors none is looked for, and a key longer than
    ``MISSPELT_KEY_LENGTH`` is none.

    Linear in the errors: the extra keys are grouped by object first (each
    missing field scanned them all: 4000 unknown objects in a list, a 32 kB
    request, took 15 s, four times as many 16 times as long).
    """
    if len(errors) > MISSPELT_SEARCH:
        return None
    extras: dict[tuple[Any, ...], list[Any]] = {}
    for error in errors:
        if (
            error["type"] == "extra_forbidden"
            and len(str(error["loc"][-1])) <= MISSPELT_KEY_LENGTH
        ):
            extras.setdefault(tuple(error["loc"][:-1]), []).append(error)
    if not extras:
        return None
    for missing in (e for e in errors if e["type"] == "missing"):
        where, name = tuple(missing["loc"][:-1]), str(missing["loc"][-1])
        alike = [e for e in extras.get(where, ()) if _alike(str(e["loc"][-1]), name)]
        if alike:
            closest = max(alike, key=lambda e: _likeness(str(e["loc"][-1]), name))
            return closest, missing
    return None


#: Most errors among which a misspelt key is looked for: a request with more
#: is not one a person misspelt, and each key is compared with each missing
#: field of its object (difflib).
MISSPELT_SEARCH = 1000


#: Longest key looked at as a misspelt field name [characters]: the longest
#: field name has 18, and difflib's comparison of a long key with each
#: missing field is slow (900 unknown keys of 16 000 characters, a 14 MB
#: request within ``max_payload``, kept a worker 61 s).
MISSPELT_KEY_LENGTH = 64


#: Likeness from which a key is taken for a misspelt field name.
MISSPELT_LIKENESS = 0.6


def _alike(key: str, field: str) -> bool:
    """Whether ``key`` looks like a misspelling of ``field``.

    Close by difflib's ratio (``phase`` for ``phases``), the same but for
    case, or one a start of the other (``pos`` for ``position``).
    """
    a, b = key.lower(), field.lower()
    started = len(a) >= 3 and len(b) >= 3 and (a.startswith(b) or b.startswith(a))
    return started or _likeness(a, b) >= MISSPELT_LIKENESS


def _likeness(key: str, field: str) -> float:
    """difflib's ratio of the two names, case aside, in [0, 1]."""
    return SequenceMatcher(None, key.lower(), field.lower()).ratio()


def _dotted(loc: Sequence[int | str]) -> str:
    """A field's path as ``phases.0.targets`` (``""`` for the whole message)."""
    return ".".join(str(part) for part in loc)


def _more(count: int) -> str:
    """``; and N more problems`` for ``count`` other problems, or ``""``."""
    return f"; and {count} more problem{'s' if count > 1 else ''}" if count > 0 else ""


def parse(cls: type[M], data: str | bytes | dict[str, Any] | M) -> M:
    """Validate ``data`` (JSON text or a dict) as a ``cls`` message.

    JSON is validated strictly: a number must be a JSON number and a flag a
    JSON boolean (``true`` is not 1.0, ``"0.1"`` is not 0.1); integers are
    accepted where a number is expected. A dict of plain JSON data is held
    to the same rules; a dict that holds messages or other objects (built in
    code, not read) is validated as pydantic does by default.

    Raises:
        InvalidInputError: naming the first field that is wrong, if the data
            is not valid JSON or does not match the message.
    """
    if isinstance(data, cls):
        return data
    try:
        if isinstance(data, (str, bytes, bytearray)):
            return cls.model_validate_json(data, strict=True)
        text = _plain_json(data)
        if text is not None:
            return cls.model_validate_json(text, strict=True)
        return cls.model_validate(data)
    except ValidationError as exc:
        errors = exc.errors(include_url=False)  # once: a list of millions
        first = errors[0]
        if first["type"] == "json_invalid":
            raise InvalidInputError(
                f"{cls.__name__}: not valid JSON ({first['msg']})", field=""
            ) from None
        field, message = _describe(errors)
        raise InvalidInputError(
            f"invalid {cls.__name__}: {message}", field=field
        ) from None
    except RecursionError:
        raise InvalidInputError(
            f"invalid {cls.__name__}: nested too deeply", field=""
        ) from None


def _plain_json(data: object) -> str | None:
    """``data`` as JSON text if it is plain JSON data, else None."""
    try:
        return json.dumps(data, allow_nan=True)
    except (TypeError, ValueError):
        return None
