"""``armplan inspect FILE.mcap``: channels, counts and time range of a recording.

A damaged file (a recorder killed mid-write, a truncated copy) is an error
naming how many messages were readable; ``--recover`` shows that readable
prefix instead. ``--validate`` also checks every message against its
channel's schema (exit 1 if one does not match). A well-formed file is
listed whole: a channel that is not JSON (another program's, say ROS 2's
``cdr``) and a message that is not JSON are counted and marked "not read".
Names from the file (topics, schemas, the namespace) are printed with their
control characters escaped (``shared.printable``).
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

from rich.markup import escape
from rich.table import Table

from armplan.cli.console import StdoutConsole
from armplan.cli.output import print_json
from armplan.cli.parsing import add_json
from shared.errors import RecordingError
from shared.printable import printable, printable_lines
from shared.recording.inventory import ChannelStats, Inventory, take_inventory
from shared.recording.reader import CHANGED, JSON
from shared.text.counted import agreeing, counted

ORDER = 92
HELP = "show a recording's channels, message counts and time range"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``inspect``."""
    parser = commands.add_parser("inspect", help=HELP, description=HELP)
    parser.add_argument("file", metavar="FILE.mcap", help="the recording")
    parser.add_argument(
        "--recover",
        action="store_true",
        help="show the readable prefix of a damaged file instead of failing",
    )
    parser.add_argument(
        "--validate",
        action="store_true",
        help="check every message against its channel's schema",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print the recording's summary; exit 1 on damage (without --recover)."""
    inventory = take_inventory(args.file, recover=args.recover, validate=args.validate)
    error = _invalid(inventory)
    if args.json:
        # one JSON document, the error (if any) in it
        extra = {} if error is None else {"error": error.to_wire()}
        print_json({**as_json(inventory), **extra})
    else:
        _print(inventory, args.validate)
    if error is None:
        return 0
    if args.json:
        sys.stderr.write(f"armplan: error: {printable_lines(error.message)}\n")
        return 1
    raise error


def _invalid(inventory: Inventory) -> RecordingError | None:
    """The error for messages that do not match their schema, if any."""
    invalid = sum(c.invalid for c in inventory.channels)
    if not invalid:
        return None
    return RecordingError(
        f"{inventory.path}: {counted(invalid, 'message')} "
        f"{agreeing(invalid, 'does', 'do')} not match "
        f"{agreeing(invalid, 'its', 'their')} channel's schema, "
        f"e.g. {inventory.problems[0]}",
        path=str(inventory.path),
    )


def as_json(inventory: Inventory) -> dict[str, Any]:
    """The inventory as JSON-ready data (times in [ns], durations in [s]).

    Names are as the file gives them (JSON escapes control characters).
    The fields are documented in docs/recording.md ("inspect --json").
    """
    first, last = inventory.first, inventory.last
    return {
        "path": str(inventory.path),
        "messages": inventory.count,
        "start_ns": first,
        "end_ns": last,
        "duration": None if first is None or last is None else (last - first) / 1e9,
        "damage": inventory.damage,
        "damage_code": inventory.damage_code,
        "metadata": inventory.metadata,
        "channels": [
            {
                "topic": c.topic,
                "schema": c.schema,
                "encoding": c.encoding,
                "messages": c.count,
                "start_ns": c.first if c.count else None,
                "end_ns": c.last if c.count else None,
                "duration": c.duration if c.count else None,
                "invalid": c.invalid,
                "unread": c.unread,
            }
            for c in inventory.channels
        ],
        "problems": inventory.problems,
        "unread": inventory.unread,
        "clock_offset": inventory.clock_offset,
    }


def _clock(ns: int | None) -> str:
    """``ns`` [ns since the epoch] as local date and time to the millisecond."""
    if ns is None:
        return "-"
    stamp = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(ns / 1e9))
    return f"{stamp}.{ns // 1_000_000 % 1000:03d}"


def _print(inventory: Inventory, validate: bool) -> None:
    console = StdoutConsole(width=None if sys.stdout.isatty() else 200)
    first, last = inventory.first, inventory.last
    span = 0.0 if first is None or last is None else (last - first) / 1e9
    namespace = inventory.metadata.get("armplan", {}).get("namespace", "-")
    console.print(
        f"[bold]{_text(str(inventory.path))}[/bold]: "
        f"{counted(inventory.count, 'message')} on "
        f"{counted(len(inventory.channels), 'channel')}, "
        f"namespace {_text(namespace)}\n"
        f"from {_clock(first)} to {_clock(last)} ({span:.3f} s)"
    )
    console.print(_table(inventory, validate))
    for note in [*_unread_notes(inventory), *_clock_notes(inventory)]:
        console.print(f"[yellow]{_text(note)}[/yellow]")
    if inventory.damage == CHANGED:
        console.print(
            f"[yellow]{escape(CHANGED)}, somewhere in "
            f"{agreeing(inventory.count, 'this', 'these')} "
            f"{counted(inventory.count, 'message')} (which cannot be told): "
            "shown with the changed bytes[/yellow]"
        )
    elif inventory.damage is not None:
        console.print(
            f"[yellow]damaged after {inventory.count} readable "
            f"{agreeing(inventory.count, 'message')} "
            f"({_text(inventory.damage)}); shown: the readable prefix[/yellow]"
        )


def _text(name: str) -> str:
    """``name`` (from the file) as rich markup that prints it as it is, safely."""
    return escape(printable(name))


def _unread_notes(inventory: Inventory) -> list[str]:
    """What was not read, and what ``armplan replay`` does with it."""
    notes = []
    foreign = [c for c in inventory.foreign if c.count]  # declared alone: no matter
    if foreign:
        which = ", ".join(f"{c.topic} ({c.encoding or '(none)'})" for c in foreign)
        count = sum(c.count for c in foreign)
        notes.append(
            f"not read: {counted(count, 'message')} on "
            f"{counted(len(foreign), 'channel')} that "
            f"{agreeing(len(foreign), 'is', 'are')} not "
            f"JSON: {which}; armplan reads JSON messages only, and armplan "
            "replay refuses this file"
        )
    unread = [c for c in inventory.channels if c.encoding == JSON and c.unread]
    if unread:
        count = sum(c.unread for c in unread)
        notes.append(
            f"not read: {counted(count, 'message')} on JSON channels that "
            f"{agreeing(count, 'is', 'are')} not JSON, "
            f"e.g. {inventory.unread[0]}; {_replayed(unread)}"
        )
    return notes


def _replayed(unread: list[ChannelStats]) -> str:
    """What ``armplan replay`` does with the messages not read on ``unread``.

    It sends those of armplan's keys as they are, and nothing of a ``/...``
    channel (it said it sent them all).
    """
    sent = sum(c.unread for c in unread if c.replayed)
    kept = sum(c.unread for c in unread) - sent
    if not kept:
        return "armplan replay sends them as they are"
    if not sent:
        return "armplan replay does not send them (it sends no channel named /...)"
    return (
        f"armplan replay sends the {sent} on its keys as they are, not the "
        f"{kept} on channels named /..."
    )


def _clock_notes(inventory: Inventory) -> list[str]:
    """A warning if log and publish times of a message are far apart."""
    offset = inventory.clock_offset
    if offset is None:
        return []
    way = "behind" if offset < 0 else "ahead"
    return [
        f"warning: log time and publish (receipt) time differ by up to "
        f"{abs(offset):.3f} s (on {inventory.skew_topic}): a publisher's clock "
        f"may be off by {abs(offset):.3f} s ({way}); the times above are log "
        "times, armplan replay times messages by their receipt"
    ]


#: A channel whose messages all came within this span [s] shows no rate.
BURST = 1e-3


def _table(inventory: Inventory, validate: bool) -> Table:
    """One row per channel.

    With an ``encoding`` column if a channel is not JSON, ``not read`` if a
    message was not read, ``invalid`` if the messages were checked.
    """
    encodings = bool(inventory.foreign)
    unread = any(c.unread for c in inventory.channels)
    table = Table(show_edge=False)
    table.add_column("topic", no_wrap=True)
    table.add_column("schema", no_wrap=True)
    if encodings:
        table.add_column("encoding", no_wrap=True)
    for name in ("messages", "start [s]", "duration [s]", "rate [Hz]"):
        table.add_column(escape(name), justify="right")
    if unread:
        table.add_column("not read", justify="right")
    if validate:
        table.add_column("invalid", justify="right")
    origin = inventory.first or 0
    for c in inventory.channels:
        burst = c.duration < BURST  # a rate over a burst means nothing
        rate = "-" if burst else f"{(c.count - 1) / c.duration:.1f}"
        row = [
            _text(c.topic),
            _text(c.schema or "-"),
            *([_text(c.encoding or "(none)")] if encodings else []),
            str(c.count),
            f"{(c.first - origin) / 1e9:.3f}" if c.count else "-",
            f"{c.duration:.3f}" if c.count else "-",
            rate,
            *([str(c.unread)] if unread else []),
        ]
        table.add_row(*row, *([str(c.invalid)] if validate else []))
    return table
