"""The summary ``armplan demo`` prints: the task, the plan, the tracking error."""

from __future__ import annotations

from pathlib import Path

from armplan.cli.palm_line import palm_line
from armplan.demo.outputs import Execution
from armplan.demo.session import DemoResult
from armplan.demo.task import Phase
from shared.messages.hand import HandAction
from shared.recording.reader import summarize
from shared.text.counted import counted


def summary_lines(result: DemoResult) -> list[str]:
    """Every line of the summary, in order."""
    run = result.execution
    return [
        *task_lines(run),
        *execution_lines(run),
        *tracking_lines(run),
        *file_lines(result.files, result.recording_error is not None),
    ]


def task_lines(run: Execution) -> list[str]:
    """The task's phases with their wrist targets.

    Under a phase, the palm wanted and reached at each of its targets that
    asks for a palm direction (``Trajectory.palm_reached``).
    """
    task = run.task
    lines = [
        f"task {task.name!r}: {task.arm.value} arm, {len(task.phases)} phases, "
        f"{len(task.targets())} wrist targets (torso frame)"
    ]
    palms = iter(run.trajectory.palm_reached or [None] * len(task.targets()))
    for number, phase in enumerate(task.phases, 1):
        lines.append(f"  {number}. {phase.name:<26} {_targets(phase)}")
        for target_number, _ in enumerate(phase.targets, 1):
            reached = next(palms)
            if reached is not None:
                lines.append(
                    "     " + palm_line(reached, f" at target {target_number}")
                )
    return lines


def _targets(phase: Phase) -> str:
    if len(phase.targets) > 2:
        return f"{len(phase.targets)} targets, from {_xyz(phase.targets[0].position)}"
    shown = [
        f"{_xyz(t.position)} hold {t.dwell:g} s{_hand(t.hand)}" for t in phase.targets
    ]
    return ", ".join(shown)


def _hand(action: HandAction | None) -> str:
    """``", close the hand"`` and the like, or nothing."""
    return "" if action is None else f", {action.value} the hand"


def _xyz(position: tuple[float, float, float]) -> str:
    return "(" + ", ".join(f"{v:+.3f}" for v in position) + ") m"


def execution_lines(run: Execution) -> list[str]:
    """How long the trajectory is, and where and how it was played."""
    trajectory, reply = run.trajectory, run.reply
    primitives = ", ".join(dict.fromkeys(trajectory.primitives))
    where = "the simulated NAO" if run.simulated else "the NAO"
    return [
        f"trajectory: {trajectory.duration:.2f} s, {len(trajectory.times)} samples; "
        f"primitives {primitives}",
        *hand_lines(run),
        f"played on {where} at {run.robot}: {counted(reply.frames, 'frame')} at "
        f"{run.rate:g} fps after a {reply.approach_duration:.2f} s approach "
        "to the start posture",
    ]


def hand_lines(run: Execution) -> list[str]:
    """What the hand does, if the task moves it (else no line)."""
    hand = run.trajectory.hand
    if hand is None:
        return []
    actions = [t.hand for t in run.task.targets() if t.hand is not None]
    closes = sum(a is HandAction.CLOSE for a in actions)
    opens = len(actions) - closes
    return [
        f"hand ({run.task.arm.hand_joint}): starts {_state(hand[0])}, closes "
        f"{closes} and opens {opens} times during the dwells, ends {_state(hand[-1])}"
    ]


def _state(opening: float) -> str:
    """An open fraction in words: open, shut, or the fraction."""
    if opening == 1.0:
        return "open"
    return "shut" if opening == 0.0 else f"{opening:.2f} open"


def tracking_lines(run: Execution) -> list[str]:
    """The tracking error per joint [deg]."""
    report = run.reply.report
    left_out = f" ({report.discarded} with slow readings left out)"
    lines = [
        f"tracking error, measured (getAngles) against commanded, {report.samples} "
        f"samples{left_out if report.discarded else ''}, latency "
        f"{report.latency * 1000:.0f} ms taken out (the call began at most "
        f"{report.start_delay * 1000:.0f} ms after it left):",
        f"  {'joint':<16}{'RMS [deg]':>10}{'max [deg]':>11}",
    ]
    for joint in report.joint_names:
        rms, peak = report.tracking_rms_deg[joint], report.tracking_max_deg[joint]
        lines.append(f"  {joint:<16}{rms:>10.3f}{peak:>11.3f}")
    if report.hand_tracking_rms is not None and report.hand_tracking_max is not None:
        lines.append(
            f"  hand {run.task.arm.hand_joint}: RMS {report.hand_tracking_rms:.3f}, "
            f"max {report.hand_tracking_max:.3f} (open fraction, 0 shut to 1 open)"
        )
    return lines


def file_lines(files: dict[str, Path], recording_failed: bool = False) -> list[str]:
    """The files written, with the recording's message count (or its failure)."""
    lines = ["wrote:"]
    for name, path in files.items():
        note = ""
        if name == "recording":
            note = FAILED_NOTE if recording_failed else _recording_note(path)
        lines.append(f"  {name:<12} {path}{note}")
    return lines


#: What the summary says of a recording that failed (the error follows).
FAILED_NOTE = " (FAILED: incomplete, without its summary; see the error below)"


def _recording_note(path: Path) -> str:
    channels = summarize(path).channels
    count = sum(n for _, n, _, _ in channels.values())
    return f" ({counted(count, 'message')} on {counted(len(channels), 'channel')})"
