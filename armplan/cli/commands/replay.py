"""``armplan replay FILE.mcap``: publish a recording's messages again over Zenoh.

Each recorded Zenoh message goes out again on its key, under the current
namespace, with its original payload bytes and Zenoh encoding and its
original timing (the recorder's receipt times, see
``services.recorder.replay``) divided by ``--speed``. The files are checked
whole before the first message goes, then read as they are sent.
The derived Foxglove channels (``/tf/...``, ...) are not sent. A bridge
subscribed to ``plan/trajectory`` drives the (simulated) NAO from the
replayed trajectories: ``armplan replay session.mcap --keys plan/trajectory
--wait-for bridge``. Without ``--keys``, a recording holding ``plan/*`` or
``bridge/*`` messages is refused while a bridge is alive in the namespace
(nothing is sent), and stopped, exit 1, if one comes alive while it runs
(``services.recorder.service_watch``); a recording of ``fit/*`` messages is
refused, or stopped, for a live decide service the same way. Messages sent
while no router or peer was connected reach nobody: the summary counts
them, and the replay then exits 1.
"""

from __future__ import annotations

import argparse
import math
import sys
import threading
import time
from collections import Counter
from pathlib import Path

import zenoh

from armplan.launch.catalog import unknown_hint
from services.recorder.bridge_watch import BRIDGE, check_no_live_bridge, live_keys
from services.recorder.model_check import DECIDE, check_no_live_decide, model_keys
from services.recorder.replay import (
    Replay,
    ReplayStats,
    check_speed,
    replay,
    replay_items,
)
from services.recorder.replay_login import (
    check_publishable,
    check_rules_namespace,
    refused_by_rules,
    refused_warning,
)
from services.recorder.replay_parts import matcher
from services.recorder.service_watch import ServiceWatch, appeared, service_watches
from shared.bus import Bus, BusConfig, load_config
from shared.bus.login import login_user
from shared.bus.options import add_config_option, add_connect_options, bus_config
from shared.bus.session import has_router_or_peer
from shared.errors import (
    BridgeAppearedError,
    DecideAppearedError,
    InvalidInputError,
    RecordingError,
    ServiceAppearedError,
    ServiceUnavailableError,
)
from shared.stop_signals import stop_on_signals
from shared.text.counted import counted

ORDER = 91
HELP = "publish a recording's messages again over Zenoh with their timing"
#: Time the session stays open after the last message [s]. Closed at once,
#: the last message (a 52 kB trajectory) went missing twice in about 40
#: replays on its way through a second router, though the first had it;
#: Zenoh has no flush to wait for. A mitigation, not a proven cure.
LINGER = 0.5


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``replay``."""
    parser = commands.add_parser("replay", help=HELP, description=HELP)
    parser.add_argument(
        "files",
        nargs="*",  # at least one: checked in run, with a hint (_check_files)
        metavar="FILE.mcap",
        help="the recording (the numbered files of a rotating one, in order)",
    )
    parser.add_argument(
        "--speed",
        type=float,
        default=1.0,
        metavar="X",
        help="time scale: 2 plays twice as fast (default 1, the original timing)",
    )
    parser.add_argument(
        "--keys",
        nargs="+",
        action="extend",
        metavar="KEY",
        help="only these key expressions, relative to the namespace, e.g. "
        "plan/trajectory (default: every recorded key); it takes every word "
        "up to the next option, so give all the files first, or all of them "
        "after -- that ends the keys, or repeat --keys",
    )
    parser.add_argument(
        "--recover",
        action="store_true",
        help="replay the readable prefix of a damaged file",
    )
    parser.add_argument(
        "--wait-for",
        nargs="+",
        default=[],
        metavar="SERVICE",
        help="wait until these services are alive first, e.g. bridge",
    )
    parser.add_argument(
        "--wait",
        type=float,
        default=10.0,
        metavar="S",
        help="how long to wait for the router and --wait-for services [s] "
        "(default: %(default)g)",
    )
    add_config_option(parser)
    add_connect_options(parser)
    parser.set_defaults(run=run)


def _check_files(args: argparse.Namespace) -> None:
    """Raise: no FILE.mcap given, or ``--keys`` or ``--wait-for`` took one.

    An option with several values takes every word up to the next option:
    ``replay s-0001.mcap --keys plan/trajectory s-0002.mcap`` replayed the
    first part alone, the second taken for a key that matches nothing.
    """
    took = [
        (option, value)
        for option, values in (("--keys", args.keys), ("--wait-for", args.wait_for))
        for value in values or ()
        if value.endswith(".mcap")
    ]
    _check_no_option_taken(args.files)
    if args.files and not took:
        return
    hint = (
        f"{took[0][0]} took {took[0][1]} as one of its values (it takes every "
        "word up to the next option): give all the files first, or all of them "
        "after -- (files cannot stand on both sides of it)"
        if took
        else ""
    )
    if args.files:
        raise InvalidInputError(hint, field="files")
    what = f"; {hint}" if hint else ""
    raise InvalidInputError(f"no FILE.mcap to replay was given{what}", field="files")


def _check_no_option_taken(files: list[str]) -> None:
    """Raise if an option after ``--`` was taken for a file, or a name is empty.

    After ``--`` every word is a file: ``replay --keys plan/trajectory --
    s.mcap --connect tcp/HOST:PORT`` said "--connect: no such file".
    A file that exists under such a name is replayed as asked.
    """
    for word in files:
        if not word:  # Path("") is ".": "is a folder, not an MCAP file"
            raise InvalidInputError(
                "a file's name is empty (''): name each MCAP file", field="files"
            )
        if word.startswith("-") and not Path(word).exists():
            raise InvalidInputError(
                f"{word} was taken for a file: after --, every word is a file; "
                "give the options before -- (e.g. --keys plan/trajectory "
                "--connect tcp/HOST:PORT -- s.mcap)",
                field="files",
            )


def _check_wait(wait: float) -> None:
    if not (math.isfinite(wait) and wait >= 0.0):
        raise InvalidInputError(
            f"--wait must be 0 or more seconds, got {wait}", field="wait"
        )


def _say_damage(items: Replay) -> None:
    """Warn of each damaged file replayed (``--recover``): its rest is lost.

    Its summary, ``sent N of N messages``, read as a whole recording's.
    """
    for part in items.parts:
        if part.damage is not None:
            which = (
                "nothing of it is replayed"  # not "replaying those 0 (0 of them"
                if part.readable == 0
                else f"replaying it ({part.count} to send)"  # not "it 1 (1 of them"
                if part.readable == 1
                else f"replaying those {part.readable} ({part.count} of them to send)"
            )
            sys.stderr.write(
                f"armplan replay: warning: {part.path} is damaged after "
                f"{counted(part.readable, 'readable message')} ({part.damage}); "
                f"{which}; what came after is lost\n"
            )


#: Replays longer than this are announced [s].
LONG = 3600.0
#: Units a long replay's length is said in: (name, seconds), longest first.
_SPANS = (("years", 365.25 * 86400.0), ("days", 86400.0), ("hours", 3600.0))


def _say_long(duration: float, speed: float) -> None:
    """Warn that the replay will take ``duration`` [s], if over ``LONG``.

    A file whose log times are years apart (another tool's, stamped from
    two clocks) replayed for years with no word: the replay sat silent
    between two messages. A long recording replays as long, said once.
    """
    if duration <= LONG:
        return
    name, seconds = next(span for span in _SPANS if duration >= span[1])
    length = f"{duration / seconds:.3g}"
    unit = name.removesuffix("s") if length == "1" else name
    sys.stderr.write(
        f"armplan replay: warning: this replay takes {length} {unit} "
        f"({duration:.6g} s at speed {speed:g}); --speed shortens it, Ctrl-C "
        "stops it\n"
    )


def _no_key_matches(args: argparse.Namespace, items: Replay, namespace: str) -> None:
    """Raise: ``--keys`` matched nothing; name the keys the recording holds.

    A key given with its namespace (``armplan/plan/trajectory``, as
    ``inspect`` prints it; the file's or the replay's ``namespace``) is
    named in its relative form, as ``armplan record`` does.
    """
    held = items.recorded
    namespaces = items.namespaces | {namespace}
    raise InvalidInputError(
        f"no recorded message matches --keys {' '.join(args.keys)}; the recording "
        f"holds {', '.join(held) if held else 'no messages'}"
        f"{_relative_hint(args.keys, held, namespaces)}",
        field="keys",
    )


def _nothing_to_replay(items: Replay) -> None:
    """Raise: the files hold no message a replay sends.

    An empty recording (a ``record`` stopped before anything was published,
    or one of keys nobody published) said "sent 0 of 0 messages", exit 0,
    as a script's proof that a session was replayed. The channels derived
    for Foxglove (``/robot_description``, ``/tf/...``) are not named.
    """
    files = ", ".join(str(part.path) for part in items.parts)
    verb = "holds" if len(items.parts) == 1 else "hold"
    readable = " readable" if any(part.damage for part in items.parts) else ""
    answers = sorted(
        {t for part in items.parts for t in part.spans if not t.startswith("/")}
    )
    but = (
        f" but the recorder's own questions' answers ({', '.join(answers)}), "
        "which no service publishes"
        if answers
        else ""
    )
    raise InvalidInputError(
        f"nothing to replay: {files} {verb} no{readable} recorded Zenoh messages{but}",
        field="files",
    )


def _relative_hint(keys: list[str], held: list[str], namespaces: set[str]) -> str:
    """``"; keys are relative ..."`` if a key less its namespace matches.

    Only a key under one of ``namespaces`` (the files' or the replay's):
    ``fit/**`` is no namespaced ``**``.
    """
    for key in keys:
        for namespace in sorted(namespaces):
            rest = key.removeprefix(f"{namespace}/")
            if rest not in ("", key) and any(map(matcher([rest]), held)):
                return f"; keys are relative to the namespace: give {rest}"
    return ""


#: Exit code of a replay stopped by SIGINT, SIGTERM or SIGHUP before its end
#: (as a shell reports Ctrl-C), so that a script can tell it from a whole one.
INTERRUPTED = 130


def run(args: argparse.Namespace) -> int:
    """Check the files, then send their messages at their (scaled) times."""
    _check_files(args)
    check_speed(args.speed)  # before connecting: a bad option, not a lost router
    _check_wait(args.wait)
    config = bus_config(args)
    items = replay_items(
        args.files, keys=args.keys, recover=args.recover, namespace=config.namespace
    )
    if args.keys and not items:
        _no_key_matches(args, items, config.namespace)
    _say_damage(items)
    if not items:
        _nothing_to_replay(items)
    check_speed(args.speed, items.latest)
    _say_long(items.latest / args.speed, args.speed)
    user = login_user(config)
    refused = {} if user is None else _refused(args, config, items, user)
    stop = stop_on_signals()
    try:
        bus = Bus.connect(config, wait=args.wait, stop=stop)
    except ServiceUnavailableError:
        if stop.is_set():  # asked to stop while waiting for the router
            return _interrupted()
        raise
    with bus:
        missing = bus.wait_alive(args.wait_for, args.wait, stop)
        if stop.is_set():
            return _interrupted()
        if missing:
            raise bus.not_alive(missing, args.wait, unknown_hint(missing))
        live = [] if args.keys is not None else live_keys(items)  # --keys: asked
        models = [] if args.keys is not None else model_keys(items)
        guarded = {BRIDGE: live, DECIDE: models}
        with service_watches(bus, guarded, stop) as watches:  # before: no gap
            check_no_live_decide(bus, models)
            check_no_live_bridge(bus, live)
            stats, offline, began = _send(bus, items, args.speed, watches, stop)
    dropped = (
        f"; a secured router drops the {sum(refused.values())} user {user!r} may "
        "not publish"
        if refused
        else ""
    )
    sys.stdout.write(
        f"armplan replay: sent {stats.sent} of {counted(len(items), 'message')} in "
        f"{stats.duration:.3f} s (speed {args.speed:g}, at most "
        f"{stats.late * 1000:.1f} ms late){dropped}{_offline(offline, items)}\n"
    )
    if stop.is_set() and stats.sent < len(items):
        return _interrupted()
    if offline:
        endpoints = ", ".join(config.endpoints)
        why = (
            f"the replay lost its connection to the router or peer at {endpoints}"
            if began
            else f"no router or peer was connected at {endpoints} when the replay began"
        )
        raise ServiceUnavailableError(
            "router",
            reason=f"{why}: {offline} of {counted(len(items), 'message')} went "
            "out while no router or peer was connected, and reached nobody",
        )
    return 0


def _send(
    bus: Bus,
    items: Replay,
    speed: float,
    watches: list[ServiceWatch],
    stop: threading.Event,
) -> tuple[ReplayStats, int, bool]:
    """Send ``items``; stats, how many went out with no router, link at first.

    Returns the replay's stats, the messages sent while no router or peer
    was connected, and whether one was connected at the first message.
    The ``watches``' flags are checked immediately before each put: once a
    watched service (a bridge, a decide service) is seen, nothing more is
    sent (a put already made cannot be recalled), and :func:`_halted` ends
    the replay.

    Raises:
        BridgeAppearedError: if a bridge was seen (see :func:`_halted`).
        DecideAppearedError: if a decide service was seen.
        RecordingError: if a message cannot be read to be sent (after saying
            how many were sent).
    """
    config = bus.config
    sent = offline = 0
    done: Counter[str] = Counter()  # messages sent per relative key
    connected: bool | None = None  # known from the first message on
    began = True  # whether a router or peer was connected at the first

    def publish(path: str, payload: bytes, encoding: str) -> None:
        nonlocal sent, offline, connected, began
        now = has_router_or_peer(bus.session)
        if now != connected:
            if connected is None:
                began = now
            _say_link(now, connected is None, config)
            connected = now
        seen = appeared(watches)  # right before the put
        if seen is not None:
            raise _halted(bus, items, sent, done, offline, seen)
        if not connected:  # the put reaches nobody: see _say_link
            offline += 1
        bus.session.put(
            bus.key(path),
            payload,
            encoding=zenoh.Encoding(encoding),
            congestion_control=zenoh.CongestionControl.BLOCK,
        )
        sent += 1
        done[path] += 1

    try:
        stats = replay(items, publish, speed=speed, stop=stop)
    except RecordingError:  # a message found bad only when read to be sent
        sys.stdout.write(
            f"armplan replay: sent {sent} of {counted(len(items), 'message')}, then "
            f"stopped at a message it could not read{_offline(offline, items)}\n"
        )
        if sent:
            time.sleep(LINGER)  # see LINGER
        raise
    # woke the wait (stop set); seen only after the last put: the replay is whole
    seen = appeared(watches)
    if seen is not None and stats.sent < len(items):
        raise _halted(bus, items, sent, done, offline, seen)
    if stats.sent:
        time.sleep(LINGER)  # see LINGER
    return stats, offline, began


def _halted(
    bus: Bus,
    items: Replay,
    sent: int,
    done: Counter[str],
    offline: int,
    seen: ServiceWatch,
) -> ServiceAppearedError:
    """Say how far the replay got before ``seen``'s service came alive; the error.

    The messages sent before get ``LINGER`` to leave, as at a replay's end.
    """
    namespace = bus.config.namespace
    error = DecideAppearedError if seen.service == DECIDE else BridgeAppearedError
    sys.stdout.write(
        f"armplan replay: sent {sent} of {counted(len(items), 'message')}, then "
        f"stopped: {error.who} came alive in namespace {namespace!r}"
        f"{_offline(offline, items)}\n"
    )
    if sent:
        time.sleep(LINGER)  # see LINGER
    held = {
        key: items.counts[key] - done[key]
        for key in seen.keys
        if items.counts[key] > done[key]
    }
    return error(namespace=namespace, sent=sent, total=len(items), held=held)


def _refused(
    args: argparse.Namespace, config: BusConfig, items: Replay, user: str
) -> dict[str, int]:
    """The keys a secured router drops of the replay of ``user``; warn of them.

    Raises:
        InvalidInputError: if the router would drop every message (another
            namespace than the login file's, or only keys ``user`` may not
            publish).
    """
    login = load_config(args.config)  # its namespace, without --namespace
    check_rules_namespace(user, config.namespace, login.namespace, login.source)
    refused = refused_by_rules(items.counts, user)
    check_publishable(refused, len(items), user, login.source, bool(args.keys))
    if refused:
        warning = refused_warning(refused, user, login.source)
        sys.stderr.write(f"armplan replay: warning: {warning}\n")
    return refused


def _say_link(connected: bool, first: bool, config: BusConfig) -> None:
    """Warn that the router or peer went away, or say that it is back.

    Zenoh reconnects a replay by itself, but a put made while no router or
    peer is connected reaches nobody, and a put gets no answer: a replay
    whose router was killed for 6 of its 10.6 s said "sent 175 of 175
    messages" and exited 0. It now counts those puts (each is checked with
    ``has_router_or_peer`` just before it: a replay may connect to a peer),
    says when the link goes and comes back, and exits 1 if any went out so.
    ``first``: this is the first message; a link there is not news, and none
    there is not "lost".
    """
    endpoints = ", ".join(config.endpoints)
    if connected:
        if not first:
            sys.stderr.write(
                f"armplan replay: the router or peer at {endpoints} is back\n"
            )
    elif first:
        sys.stderr.write(
            f"armplan replay: warning: no router or peer is connected at "
            f"{endpoints} at the start; the messages sent until one connects "
            "reach nobody\n"
        )
    else:
        sys.stderr.write(
            f"armplan replay: warning: lost the router or peer at {endpoints}; the "
            "messages sent until it is back reach nobody\n"
        )


def _offline(offline: int, items: Replay) -> str:
    """The summary's note of the messages sent with no router, or ``""``."""
    if not offline:
        return ""
    return (
        f"; {offline} of {counted(len(items), 'message')} went out while no "
        "router or peer was connected"
    )


def _interrupted() -> int:
    """Say the replay was stopped before its end; its exit code."""
    sys.stderr.write("armplan replay: interrupted before the end\n")
    return INTERRUPTED
