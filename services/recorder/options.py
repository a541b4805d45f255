"""What a recorder records, where, and how it splits and flushes its files."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import zenoh

from shared.bus.topics import topic_paths
from shared.errors import InvalidInputError
from shared.recording.rotation import FLUSH_EVERY, MAX_FLUSH_EVERY, RotationPolicy


def default_output() -> Path:
    """``armplan-YYYYmmdd-HHMMSS-mmm.mcap`` in the current folder (local time).

    The milliseconds keep recorders started in the same second apart; the
    file is created exclusively, so two can never share one.
    """
    now = time.time()
    stamp = time.strftime("%Y%m%d-%H%M%S", time.localtime(now))
    return Path(f"armplan-{stamp}-{int(now * 1000) % 1000:03d}.mcap")


def check_keys(keys: tuple[str, ...], namespace: str) -> tuple[str, ...]:
    """``keys`` if each, under ``namespace``, is a valid Zenoh key expression.

    A key that starts with the namespace (``armplan/plan/trajectory``, copied
    from ``armplan inspect``) is refused, naming the relative form: put under
    the namespace again it recorded ``armplan/armplan/plan/trajectory``,
    which nothing publishes (a replay's ``--keys`` likewise matches nothing).

    Raises:
        InvalidInputError: naming the first bad key expression.
    """
    if not keys:
        raise InvalidInputError("no key expression to record", field="keys")
    for key in keys:
        if key.startswith(f"{namespace}/"):
            relative = key.removeprefix(f"{namespace}/")
            raise InvalidInputError(
                f"--keys {key} starts with the namespace {namespace!r}: keys are "
                f"relative to it, give {relative} (this would record "
                f"{namespace}/{key})",
                field="keys",
            )
        try:
            zenoh.KeyExpr(f"{namespace}/{key}")
        except zenoh.ZError:
            raise InvalidInputError(
                f"{key!r} is not a Zenoh key expression relative to the namespace "
                f"(e.g. plan/trajectory, bridge/*, **)",
                field="keys",
            ) from None
    return keys


@dataclass(frozen=True)
class RecorderOptions:
    """A recorder's settings.

    Attributes:
        output: The MCAP file (with rotation: the stem of the numbered files).
        keys: Key expressions relative to the namespace, e.g.
            ``("plan/trajectory", "bridge/**")``; default: every registered
            topic (``shared.bus.topics``).
        rotation: When to start a new file (default: never).
        flush_every: Longest time between flushes to the OS [s]; a recorder
            killed with SIGKILL loses at most about this much.
        foxglove: Also write the derived Foxglove channels (``/tf/...``,
            ``/decision``, ``/robot_description``).
        planned_prefix: Frame prefix of the planned arm ("" moves the URDF).
        executed_prefix: Frame prefix of the executed arm.
        commanded_prefix: Frame prefix of the arm the bridge's frames command.
        overwrite: Replace an existing recording at ``output`` (with
            rotation: its numbered files); if False, one is refused.
    """

    output: Path = field(default_factory=default_output)
    keys: tuple[str, ...] = field(default_factory=topic_paths)
    rotation: RotationPolicy = field(default_factory=RotationPolicy)
    flush_every: float = FLUSH_EVERY
    foxglove: bool = True
    planned_prefix: str = ""
    executed_prefix: str = "executed/"
    commanded_prefix: str = "commanded/"
    overwrite: bool = False

    def __post_init__(self) -> None:
        if not 0 < self.flush_every <= MAX_FLUSH_EVERY:
            raise InvalidInputError(
                f"flush_every must be in (0, {MAX_FLUSH_EVERY:g}] s, "
                f"got {self.flush_every}",
                field="flush_every",
            )
