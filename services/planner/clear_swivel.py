"""A reach that comes near NAO's body, taken clear by turning the elbow.

The planner refuses a trajectory that brings the arm within
``shared.robot.body.MARGIN`` of the torso, pelvis or head. Often the wrist's
path is fine and the arm's shape is not: the hand (which points along the
forearm), the forearm or the upper arm swings into the body while the wrist
stays clear. NAO's arm keeps its wrist where it is when the elbow turns
about the line from the shoulder to the wrist (the elbow's swivel; with
NAO's elbow offset the joints that do it are found by least squares,
``shared.demos.posture_from_points``), so the arm can be taken clear
without leaving the wrist path. That is the paper's function primitive
S_R E_P W_R (Table 1: "obstacle avoidance movements", the wrist fixed, the
elbow swivelling round it), here laid over the reach that moves the wrist.

:func:`keep_clear` does that for one movement's joint path that comes
nearer the body than the margin: over the samples that come within
``AIM`` (twice the margin) it turns the elbow by a swivel that rises and
falls smoothly (minimum-jerk ramps of ``RAMP`` of the path's time; held to
the end when the near samples reach it, so the goal posture turns too),
trying ``SWIVELS`` each way, smallest first (each screened on every
``SCREEN_STRIDE``-th sample first), and takes the first that keeps ``AIM``
at every sample, else the one that keeps the margin with most room. A
wanted palm keeps its roll: WristYaw turns by what the swivel changed of it
(on the way it stops at its range if it must; at the goal it may not).
Samples turned are labelled with the full primitive (every joint moves
there). A path already clear, the start posture, and the wrist path are
never changed; a path no swivel tried takes clear is returned as it was,
and the planner refuses it as before.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from services.ik.elbow_turn import AIM, SWIVELS, Turned, least_clearances, turn_elbow
from shared.messages import JointPath, Method
from shared.primitives import FULL_GRASP, FULL_REACH
from shared.robot.arm_model import ArmModel
from shared.robot.body import BODY, MARGIN, BodyPart
from shared.robot.fk_many import key_points

#: Time the swivel takes to rise and to fall [s] of the path's time.
RAMP = 0.15
#: Fewest samples a ramp spans.
RAMP_SAMPLES = 3
#: Largest joint step between two samples a turned path may take [rad],
#: unless the path as tracked had a larger one: one and a half times the
#: tracker's own largest (0.1 rad, docs/planning.md, "Known limits"; a
#: swivel of 0.7 rad over 0.15 s makes about 0.12). A palm near the
#: forearm's axis makes its roll, and so WristYaw, swing with the swivel:
#: 2.4 rad in one step, before this was checked.
STEP = 0.15
#: A swivel is first tried on every this many samples it turns (and the
#: last): a path whose screened samples do not keep the margin is not
#: turned whole. Turning a sample costs about 4 ms (a least-squares fit).
SCREEN_STRIDE = 5

#: The planner's advice in a refusal once keep_clear has tried.
REFUSED_TRIED = (
    f"turning the elbow about the wrist's path (up to {SWIVELS[-1]:g} rad "
    "either way) did not take it clear, so the plan is refused: choose "
    "targets the arm reaches without crossing the body"
)
#: The advice when a given wrist path's turn would have taken it clear but
#: its times are too short for it.
REFUSED_TOO_FAST = (
    "turning the elbow about the wrist's path would take it clear but needs "
    "more speed than the path's times allow, so the plan is refused: slow "
    "the path down, or move it away from the body"
)


class Kept(NamedTuple):
    """What :func:`keep_clear` made of a joint path.

    Attributes:
        path: The joint path, turned or as it was.
        tried: Whether it came nearer the body than the margin, so that
            swivels were tried.
    """

    path: JointPath
    tried: bool


def keep_clear(
    arm: ArmModel,
    path: JointPath,
    palm: Sequence[float] | None,
    method: Method,
    parts: tuple[BodyPart, ...] = BODY,
) -> Kept:
    """``path`` taken clear of the body by the elbow's swivel (see the module).

    Args:
        arm: The arm.
        path: One movement's joint path; its first posture is where the arm is.
        palm: The wanted palm direction (unit), or None.
        method: The method that tracked it (sets the turned samples' label).
        parts: What to keep clear of: NAO's body by default (and the other
            arm where the request holds it).

    Returns:
        ``path`` itself if it keeps the margin, or if no swivel tried does;
        else the path with the elbow turned.
    """
    q = np.asarray(path.positions, dtype=float)
    gaps = least_clearances(arm, q, parts)
    if bool(np.all(gaps >= MARGIN)):
        return Kept(path, tried=False)
    near = ~(gaps >= AIM)
    near[0] = False  # where the arm is: never turned
    weight = swivel_profile(np.asarray(path.times), near)
    aim = min(AIM, float(gaps[0]))  # a start nearer than AIM stays so
    steepest = max(STEP, _largest_step(q))
    best: Turned | None = None
    for size in SWIVELS:
        for sign in (1.0, -1.0):
            swivel = sign * size * weight
            screened = turn_elbow(arm, q, swivel, palm, SCREEN_STRIDE, parts)
            if screened is None or not screened.least >= MARGIN:
                continue  # the whole path comes no farther than these samples
            turned = turn_elbow(arm, q, swivel, palm, parts=parts)
            if turned is None or _largest_step(turned.positions) > steepest:
                continue
            if turned.least >= aim:
                return Kept(
                    _with(arm, path, turned.positions, weight, palm, method), True
                )
            if turned.least >= MARGIN and (best is None or turned.least > best.least):
                best = turned
    if best is None:
        return Kept(path, tried=True)
    return Kept(_with(arm, path, best.positions, weight, palm, method), tried=True)


def swivel_profile(times: np.ndarray, near: np.ndarray) -> np.ndarray:
    """How much of the swivel each sample turns, 0..1, shape (n,).

    1 from the first to the last ``near`` sample, with minimum-jerk ramps of
    ``RAMP`` [s] (at least ``RAMP_SAMPLES`` samples) on either side. The
    first sample, where the arm is, stays at 0: a ramp that would not fit
    before the first near sample rises from the start over ``RAMP`` instead,
    so the samples near the start turn less. The swivel is held to the end
    when the falling ramp would not fit before it.

    Args:
        times: Sample times [s], shape (n,), increasing.
        near: Which samples need the swivel, shape (n,), at least one.
    """
    index = np.flatnonzero(near)
    first, last, n = int(index[0]), int(index[-1]), len(times)
    rise, fall = np.ones(n), np.ones(n)
    rise_from, rise_to = min(_back(times, first, RAMP), first - RAMP_SAMPLES), first
    if rise_from < 0 or times[first] - times[0] < RAMP:
        rise_from = 0
        rise_to = min(max(first, _ahead(times, 0, RAMP), RAMP_SAMPLES), n - 1)
    span = times[rise_to] - times[rise_from]
    rise[:rise_to] = _minimum_jerk((times[:rise_to] - times[rise_from]) / span)
    last = max(last, rise_to)  # a late rise: full there before it falls
    fall_to = max(_ahead(times, last, RAMP), last + RAMP_SAMPLES)
    if fall_to < n:
        span = times[fall_to] - times[last]
        fall[last + 1 :] = _minimum_jerk((times[fall_to] - times[last + 1 :]) / span)
    weight = np.minimum(rise, fall)
    weight[0] = 0.0
    return weight


def _with(
    arm: ArmModel,
    path: JointPath,
    positions: np.ndarray,
    weight: np.ndarray,
    palm: Sequence[float] | None,
    method: Method,
) -> JointPath:
    """``path`` with ``positions``; the turned samples relabelled."""
    full = (FULL_GRASP if palm is not None else FULL_REACH).name
    labels = [
        full if method is Method.MP and w > 0.0 else label
        for label, w in zip(path.primitives, weight, strict=True)
    ]
    wrists = key_points(arm, positions)["wrist"]
    return path.model_copy(
        update={
            "positions": [tuple(row) for row in positions.tolist()],
            "primitives": labels,
            "wrist": [tuple(row) for row in wrists.tolist()],
        }
    )


def _largest_step(q: np.ndarray) -> float:
    """The largest change of a joint between two samples of ``q`` [rad], (n, 5)."""
    return float(np.abs(np.diff(q, axis=0)).max()) if len(q) > 1 else 0.0


def _back(times: np.ndarray, i: int, span: float) -> int:
    """The last sample at least ``span`` [s] before sample ``i`` (or 0)."""
    return max(int(np.searchsorted(times, times[i] - span, side="right")) - 1, 0)


def _ahead(times: np.ndarray, i: int, span: float) -> int:
    """The first sample at least ``span`` [s] after sample ``i`` (or n)."""
    return int(np.searchsorted(times, times[i] + span, side="left"))


def _minimum_jerk(x: np.ndarray) -> np.ndarray:
    """10 x^3 - 15 x^4 + 6 x^5 on x clipped to 0..1."""
    x = np.clip(x, 0.0, 1.0)
    return x**3 * (10.0 - 15.0 * x + 6.0 * x**2)
