"""Printing a planned trajectory: the SPEC's JSON, or a table and a summary.

The output depends only on the request and the ``Trajectory`` message, so a
trajectory planned here and one answered by the planner service print alike.
"""

from __future__ import annotations

import itertools
import sys
from typing import NamedTuple

import numpy as np

from armplan.cli.output import print_json, print_table
from armplan.cli.palm_line import palm_line
from shared.messages import PalmReached, PlanRequest, Trajectory
from shared.robot import Side, load_arm
from shared.text.counted import counted

#: The table shows every ``EVERY``-th sample, and the last.
EVERY = 10


class Summary(NamedTuple):
    """What a trajectory did.

    Attributes:
        duration: From the first to the last sample [s].
        primitives: The primitives that moved the arm, in order, each once
            per run of consecutive samples.
        final_error: Distance of the final wrist (forward kinematics of the
            last posture) from the goal: the last target, or the wrist path's
            last sample [m].
        largest_error: With a wrist path, the largest distance of the wrist
            from the path over all samples [m]; else ``None``.
        palms: Where a palm direction was asked, where (e.g. ``" at target
            2"``) and the palm reached there (``Trajectory.palm_reached``).
    """

    duration: float
    primitives: list[str]
    final_error: float
    largest_error: float | None
    palms: tuple[tuple[str, PalmReached], ...] = ()


def summarize(request: PlanRequest, trajectory: Trajectory) -> Summary:
    """The summary of ``trajectory``, planned for ``request``."""
    arm = load_arm(trajectory.arm)
    wrists = np.array([arm.fk(np.array(q)).wrist for q in trajectory.positions])
    runs = [name for name, _ in itertools.groupby(trajectory.primitives)]
    palms = _palms(request, trajectory)
    if request.wrist_path is None:
        goal = np.array(request.targets[-1].position)
        error = float(np.linalg.norm(wrists[-1] - goal))
        return Summary(trajectory.duration, runs, error, None, palms)
    errors = np.linalg.norm(wrists - np.array(request.wrist_path.positions), axis=1)
    return Summary(
        trajectory.duration, runs, float(errors[-1]), float(errors.max()), palms
    )


def _palms(
    request: PlanRequest, trajectory: Trajectory
) -> tuple[tuple[str, PalmReached], ...]:
    """Each palm reached, with where: the target, or the path's last sample."""
    reached = trajectory.palm_reached or []
    if request.wrist_path is not None:
        places = [" at the path's last sample"]
    elif len(request.targets) == 1:
        places = [" at the target"]
    else:
        places = [f" at target {k + 1}" for k in range(len(request.targets))]
    return tuple(
        (where, palm)
        for where, palm in zip(places, reached, strict=False)
        if palm is not None
    )


def show(request: PlanRequest, trajectory: Trajectory, as_json: bool) -> None:
    """Print the trajectory as JSON, or as a sampled table and a summary."""
    if as_json:
        print_json(trajectory.model_dump(mode="json"))
        return
    print_samples(trajectory)
    print_summary(request, trajectory, summarize(request, trajectory))


def print_samples(trajectory: Trajectory, every: int = EVERY) -> None:
    """Every ``every``-th sample and the last: time [s], joints [deg], primitive.

    With a hand channel, its open fraction too, after the joints.
    """
    n = len(trajectory.times)
    hand = trajectory.hand
    rows = [
        (
            f"{trajectory.times[i]:.3f}",
            *(f"{np.degrees(q):.2f}" for q in trajectory.positions[i]),
            *([] if hand is None else [f"{hand[i]:.2f}"]),
            trajectory.primitives[i],
        )
        for i in sorted({*range(0, n, every), n - 1})
    ]
    headers = ("t [s]", *(f"{name} [deg]" for name in trajectory.joint_names))
    if hand is not None:
        headers += (f"{Side.parse(trajectory.arm).hand_joint} [open]",)
    print_table((*headers, "primitive"), rows)


#: Below this rate [Hz] (NAO's 20 ms cycle) the summary says that reaches
#: last whole sample periods, which at such rates visibly slows them.
COARSE_RATE = 50.0


def print_summary(
    request: PlanRequest, trajectory: Trajectory, summary: Summary
) -> None:
    """Duration, samples, method and pace, primitives in order, wrist errors.

    Then the palm reached where one was asked, and the hand's actions.
    """
    n = len(trajectory.times)
    if request.wrist_path is not None:
        pace = "at the wrist path's own times"
    else:
        fastest = "fastest smooth profile within the limits"
        speed = fastest if request.fastest else "human pace"
        if request.rate < COARSE_RATE:
            period = 1.0 / request.rate
            speed += f", each reach lengthened to whole {period:g} s samples"
        pace = f"{request.rate:g} Hz, {speed}"
    lines = [
        f"duration {summary.duration:.3f} s, {counted(n, 'sample')} ({pace}); "
        f"method {trajectory.method.value}",
        "primitives in order: " + " -> ".join(summary.primitives),
    ]
    if summary.largest_error is None:
        goal = ", ".join(f"{v:.4f}" for v in request.targets[-1].position)
        lines.append(
            f"final wrist error {summary.final_error * 1e3:.3f} mm "
            f"(last target ({goal}) m)"
        )
    else:
        lines.append(
            f"final wrist error {summary.final_error * 1e3:.3f} mm from the path's "
            f"last sample; largest along the path {summary.largest_error * 1e3:.3f} mm"
        )
    lines.append(end_posture_line(trajectory))
    lines += [palm_line(palm, where) for where, palm in summary.palms]
    lines += hand_lines(request, trajectory)
    sys.stdout.write("\n" + "\n".join(lines) + "\n")


def end_posture_line(trajectory: Trajectory) -> str:
    """The last posture [rad], as ``--start`` takes it.

    The table is in degrees: a row pasted into the next plan's ``--start``
    was 57 times off. Each angle is written in full (Python's shortest
    exact form), so the next plan starts exactly where this one ends: six
    decimals started it up to 5e-7 rad away, about 1 um at the hand.
    """
    last = " ".join(repr(float(q)) for q in trajectory.positions[-1])
    return f"end posture [rad] (the next plan's --start): {last}"


def hand_lines(request: PlanRequest, trajectory: Trajectory) -> list[str]:
    """The hand's actions, and the dwells lengthened for them (none: no lines)."""
    if trajectory.hand is None:
        return []
    from services.timing.hand import hand_moves
    from shared.robot.hand import hand_motion_limits

    actions = [target.hand for target in request.targets]
    moves = hand_moves(actions, hand_motion_limits(request.arm), 1.0 / request.rate)
    said = []
    for move in moves:
        target = request.targets[move.segment]
        longer = (
            f", its {target.dwell:g} s dwell lengthened to {move.duration:g} s"
            if target.dwell < move.duration
            else ""
        )
        said.append(
            f"{actions[move.segment]} at target {move.segment + 1} "
            f"({move.duration:g} s{longer})"
        )
    hand = trajectory.hand
    return [
        f"hand (open fraction): {hand[0]:.2f} at the start, {hand[-1]:.2f} at the "
        "end; " + ("; ".join(said) if said else "it does not move")
    ]
