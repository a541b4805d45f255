"""``armplan export``: a trajectory as a Choregraphe behavior or Python script."""

from __future__ import annotations

import argparse
import json
from typing import Any

from armplan.cli.output import apart_from, print_json
from armplan.cli.parsing import add_json
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.input_files import read_at_most
from shared.messages import Trajectory, parse
from shared.messages.base import MAX_RATE, MIN_RATE
from shared.output_paths import check_output_file
from shared.text.counted import counted

ORDER = 60
HELP = "write a trajectory as a Choregraphe behavior (.xar) or Python script"
FORMATS = ("choregraphe", "python")


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``export``."""
    parser = commands.add_parser("export", help=HELP, description=HELP)
    parser.add_argument("format", choices=FORMATS, help="choregraphe or python")
    parser.add_argument("trajectory", help="trajectory JSON (armplan plan --json)")
    parser.add_argument("-o", "--output", required=True, help="file to write")
    parser.add_argument(
        "--rate", type=float, default=25.0, help="frame rate [Hz] (default 25)"
    )
    add_json(parser)
    parser.set_defaults(run=run)


#: Largest trajectory file read [bytes]: MAX_TRAJECTORY_SAMPLES as
#: ``armplan plan --json`` writes them take about 35 MB.
MAX_TRAJECTORY_BYTES = 64 * 1024 * 1024


def read_trajectory(path: str) -> Trajectory:
    """The trajectory in a JSON file (bare, or under a ``"trajectory"`` key)."""
    try:
        data: Any = json.loads(read_at_most(path, MAX_TRAJECTORY_BYTES))
    except OSError as exc:
        raise InvalidInputError(
            f"cannot read {path}: {exc.strerror}", field="trajectory"
        ) from None
    except ValueError as exc:
        raise InvalidInputError(
            f"{path} is not JSON: {exc}", field="trajectory"
        ) from None
    if isinstance(data, dict) and isinstance(data.get("trajectory"), dict):
        data = data["trajectory"]
    _refuse_error_document(data, path)
    return parse(Trajectory, data)


def _refuse_error_document(data: Any, path: str) -> None:
    """Refuse a file that holds a command's error (``{"error": {...}}``), not a plan.

    ``armplan plan --json > f.json`` writes the error there when planning
    fails; exported, it used to read "invalid Trajectory: arm: Field
    required; and 8 more problems".
    """
    error = data.get("error") if isinstance(data, dict) else None
    if not isinstance(error, dict) or "times" in data:
        return
    kind, message = error.get("kind", "?"), error.get("message", "")
    raise InvalidInputError(
        f"{path} holds an armplan error ({kind}), not a trajectory: the command "
        f"that wrote it failed: {message}",
        field="trajectory",
        error_kind=kind,
    )


def run(args: argparse.Namespace) -> int:
    """Check the frames against the limits, then write them.

    Whole or not at all: a write that fails part-way leaves an older file of
    that name as it was (``shared.output_paths.write_output_text``). The
    summary goes to stderr when the export does to stdout (``apart_from``:
    ``-o /dev/stdout > play.py`` held both).
    """
    with apart_from(args.output):
        return _export(args)


def _export(args: argparse.Namespace) -> int:
    """:func:`run`, its summary on stdout."""
    from bridge import (
        FrameLimits,
        checked_frames,
        frame_velocities,
        write_behavior,
        write_python,
    )
    from bridge.choregraphe import timeline_fps

    if not MIN_RATE <= args.rate <= MAX_RATE:
        raise InvalidInputError(
            f"--rate must be in [{MIN_RATE:g}, {MAX_RATE:g}] Hz, got {args.rate!r}",
            field="rate",
        )
    if args.format == "choregraphe":
        timeline_fps(args.rate, "--rate")
    check_output_file(args.output, inputs=[args.trajectory])
    trajectory = read_trajectory(args.trajectory)
    try:
        limits = FrameLimits.for_arm(trajectory.arm)
        behavior = args.format == "choregraphe"
        frames = checked_frames(trajectory, args.rate, limits, behavior=behavior)
    except TrajectoryRefusedError as error:  # the bridge's words are "sent"
        raise error.instead("nothing was written") from None
    if args.format == "choregraphe":
        velocities = frame_velocities(trajectory, frames)
        path = write_behavior(frames, args.output, velocities=velocities)
    else:
        path = write_python(frames, args.output)
    summary = {
        "path": str(path),
        "format": args.format,
        "arm": trajectory.arm.value,
        "frames": len(frames.times),
        "rate": frames.rate,
        "duration": frames.duration,
    }
    _print_summary(summary, args.json)
    return 0


def _print_summary(summary: dict[str, Any], as_json: bool) -> None:
    """Print what was written on stdout, as JSON or as one line."""
    if as_json:
        print_json(summary)
        return
    print(
        f"wrote {summary['path']}: {counted(summary['frames'], 'frame')} "
        f"at {summary['rate']:g} fps "
        f"({summary['duration']:.3f} s, {summary['arm']} arm)"
    )
