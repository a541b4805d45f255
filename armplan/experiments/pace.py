"""How near human pace the planner stays away from the grid: random reaches and chains.

The grid reaches and the demo task keep within a few per cent of the
duration the human law asks for (``services.timing.reach_duration``). This
experiment looks where they do not go, with the real in-process planner:

- ``reaches``: single reaches to random reachable targets (the wrist of a
  random posture within the joint ranges), half from the arm hanging at
  rest, half from random postures; no palm. The postures keep clear of
  NAO's body and the targets are ones the planner takes
  (``shared.robot.body``); a reach whose way comes near the body is
  refused, and counted as such.
- ``chains``: tasks of ``CHAIN_LENGTH`` random targets, each with a random
  palm direction, from the arm at rest. A palm that no posture within the
  ranges can meet at its target is refused with the planner's error; that
  is counted and its message kept, not hidden.

The tasks are drawn for the right arm; the left arm's are their mirrors
(``mirror_task``), so a seed gives both arms the same reaches and their
results can be compared.

For each planned task the ratio is the trajectory's duration over the sum
of the human durations of its movements (each from the posture where it
starts to the one where it ends), so 1 is human pace; and whether any
sample brings a joint within ``NEAR_LIMIT`` of a limit it started further
from (the joints give way near a limit, which can slow the reach:
docs/planning.md, Known limits).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from services.planner.pipeline import plan
from services.planner.stages import Stages
from services.timing import reach_duration
from shared.errors import ArmplanError, InvalidInputError
from shared.messages import Method, PlanRequest
from shared.messages.measure_params import MeasureParams
from shared.robot.arm_model import ArmModel, load_arm
from shared.robot.body import MARGIN, closest, first_point_near
from shared.robot.postures import mirror, rest
from shared.robot.side import Side

#: Targets per chain.
CHAIN_LENGTH = 4
#: Least distance the wrist moves in a random reach [m].
LEAST_MOVE = 0.03
#: A joint this close to a limit counts as near it [rad].
NEAR_LIMIT = 0.05
#: Mirrors a point or direction in the torso frame onto the other arm's side.
MIRROR_Y = np.array([1.0, -1.0, 1.0])
#: Most reaches, and most chains, one run may plan (about 0.1 s per task
#: and method on the benchmark machine: 1000 of each, about 10 minutes).
MOST = 1000


class PaceTask(NamedTuple):
    """One random task.

    Attributes:
        kind: ``"reach"`` or ``"chain"``.
        start: Start posture [rad], shape (5,).
        targets: Wrist targets [m], shape (k, 3).
        palms: Palm directions (unit), shape (k, 3), or ``None``.
    """

    kind: str
    start: np.ndarray
    targets: np.ndarray
    palms: np.ndarray | None


class PaceRun(NamedTuple):
    """What planning one task gave.

    Attributes:
        task: The task.
        ratio: Trajectory duration over the human durations' sum [-], or
            ``None`` if the planner refused the task.
        asked: The human durations' sum [s], or ``None`` if refused.
        near_limit: Some sample brings a joint within ``NEAR_LIMIT`` of a
            limit it started further from.
        error: The planner's message if it refused, else ``None``.
    """

    task: PaceTask
    ratio: float | None
    asked: float | None
    near_limit: bool
    error: str | None


def random_posture(arm: ArmModel, rng: np.random.Generator) -> np.ndarray:
    """A posture drawn uniformly within the joint ranges [rad], shape (5,).

    Only a posture whose arm keeps clear of NAO's body is taken
    (``shared.robot.body``).
    """
    lower, upper = np.array(arm.limits.lower), np.array(arm.limits.upper)
    while True:
        q = lower + rng.random(len(lower)) * (upper - lower)
        if closest(arm, [q]).clearance >= MARGIN:
            return q


def random_target(
    arm: ArmModel, here: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    """The wrist of a random posture, at least ``LEAST_MOVE`` from ``here`` [m].

    Only a target the planner takes (not in NAO's body) is drawn.
    """
    while True:
        target = arm.fk(random_posture(arm, rng)).wrist
        if np.linalg.norm(target - here) < LEAST_MOVE:
            continue
        if first_point_near([target]) is None:
            return target


def random_palm(rng: np.random.Generator) -> np.ndarray:
    """A direction drawn uniformly on the sphere, shape (3,)."""
    while True:
        v = rng.normal(size=3)
        norm = float(np.linalg.norm(v))
        if norm > 1e-6:
            return v / norm


def random_tasks(arm: ArmModel, reaches: int, chains: int, seed: int) -> list[PaceTask]:
    """``reaches`` random reaches, then ``chains`` random chains (see the module).

    The left arm's tasks are the mirrors of the right arm's of the same
    seed: drawing within each arm's own ranges gave the arms different
    reaches, which could not be compared.

    Raises:
        InvalidInputError: a negative seed, a count outside 0..``MOST``, or
            no task at all; names the option.
    """
    _check_counts(reaches, chains, seed)
    if arm.side is Side.LEFT:
        right = random_tasks(load_arm(Side.RIGHT), reaches, chains, seed)
        return [mirror_task(task) for task in right]
    rng = np.random.default_rng(seed)
    tasks = []
    for k in range(reaches):
        start = rest(arm.side) if k % 2 == 0 else random_posture(arm, rng)
        target = random_target(arm, arm.fk(start).wrist, rng)
        tasks.append(PaceTask("reach", start, target[None], None))
    for _ in range(chains):
        start, targets = rest(arm.side), []
        here = arm.fk(start).wrist
        for _ in range(CHAIN_LENGTH):
            here = random_target(arm, here, rng)
            targets.append(here)
        palms = np.array([random_palm(rng) for _ in targets])
        tasks.append(PaceTask("chain", start, np.array(targets), palms))
    return tasks


def mirror_task(task: PaceTask) -> PaceTask:
    """``task`` for the other arm: its mirror in the torso's x-z plane."""
    return task._replace(
        start=mirror(task.start),
        targets=task.targets * MIRROR_Y,
        palms=None if task.palms is None else task.palms * MIRROR_Y,
    )


def _check_counts(reaches: int, chains: int, seed: int) -> None:
    if seed < 0:
        raise InvalidInputError(f"--seed must be 0 or more, got {seed}", field="seed")
    for name, value in (("reaches", reaches), ("chains", chains)):
        if not 0 <= value <= MOST:
            raise InvalidInputError(
                f"--{name} must be 0..{MOST}, got {value}", field=name
            )
    if reaches + chains == 0:
        raise InvalidInputError(
            "--reaches and --chains are both 0: nothing to plan", field="reaches"
        )


def run_task(
    arm: ArmModel,
    task: PaceTask,
    method: Method,
    stages: Stages | None = None,
    measures: MeasureParams | None = None,
) -> PaceRun:
    """Plan ``task`` with ``method`` in this process and measure its pace.

    Args:
        arm: The arm.
        task: The task.
        method: The planning method.
        stages: The planner's stages (default: in this process, shipped model).
        measures: The IK measures' weights (default: the model's).
    """
    targets = [
        {"position": tuple(p)}
        if n is None
        else {"position": tuple(p), "palm": tuple(n)}
        for p, n in zip(task.targets, _palms_or_none(task), strict=True)
    ]
    request = PlanRequest.model_validate(
        {
            "arm": arm.side.value,
            "targets": targets,
            "start": task.start.tolist(),
            "method": method.value,
            "measures": None if measures is None else measures.model_dump(),
        }
    )
    try:
        result = plan(request, stages)
    except ArmplanError as exc:
        return PaceRun(task, None, None, False, str(exc))
    asked = sum(
        reach_duration(arm, np.array(path.positions[0]), np.array(path.positions[-1]))
        for path in result.joint_paths
    )
    q = np.array(result.trajectory.positions)
    ratio = result.trajectory.times[-1] / asked
    return PaceRun(task, ratio, asked, near_limit(arm, q), None)


def near_limit(arm: ArmModel, q: np.ndarray) -> bool:
    """True if a joint of ``q`` [rad], shape (n, 5), nears a limit.

    Within ``NEAR_LIMIT`` of a limit it was not that near to in ``q[0]``.
    """
    lower, upper = np.array(arm.limits.lower), np.array(arm.limits.upper)
    room = np.minimum(q - lower, upper - q)  # (n, 5) distance to the nearer limit
    return bool(np.any((room.min(axis=0) < NEAR_LIMIT) & (room[0] >= NEAR_LIMIT)))


def _palms_or_none(task: PaceTask) -> list[np.ndarray | None]:
    return [None] * len(task.targets) if task.palms is None else list(task.palms)
