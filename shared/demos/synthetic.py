"""The synthetic demonstration set: the paper's protocol, made by a model.

16 subjects (``anthropometry``) each reach the 16 grid points (``grid``) 5
times from the hanging arm, sampled at 100 Hz, moving as ``reach_model``
describes; marker noise is added and every trial is retargeted to NAO
(``retarget``). The same seed gives the same set, bit for bit.
"""

from __future__ import annotations

import numpy as np

from shared.demos.anthropometry import Subject, draw_subjects
from shared.demos.grid import grid_targets
from shared.demos.reach_model import (
    MARKER_NOISE,
    Style,
    draw_style,
    plan_reach,
    sample_reach,
)
from shared.demos.retarget import ArmSize, ArmTrack, nao_arm_size, retarget
from shared.demos.rotations import FloatArray, matrix_from_rotation_vector
from shared.demos.trial import DemoSet, Trial
from shared.errors import InvalidInputError
from shared.messages.motion_model import MAX_SAMPLE_RATE, MIN_SAMPLE_RATE
from shared.robot.side import Side

#: The paper's protocol (Section V.A).
SUBJECTS, TRIALS, RATE = 16, 5, 100.0
#: Most subjects, and most trials per subject and point, one set may have.
MOST = 1000
#: Most trials one set may have in all (subjects x trials x points): about
#: 15 times the paper's 1280, some 230 MB and 1.5 minutes to make at 100 Hz.
#: 1000 subjects x 1000 trials x 16 points once passed: 16 million trials,
#: over 200 GB, hours.
MOST_TRIALS = 20_000
#: Orientation noise of the wrist frame [rad].
ORIENTATION_NOISE = 0.01


def _check(
    seed: int,
    subjects: int,
    trials: int,
    rate: float,
    points: tuple[int, ...] | None,
) -> None:
    """Raise InvalidInputError naming the first argument out of its domain."""
    if seed < 0:
        raise InvalidInputError(f"seed must be 0 or more, got {seed}", field="seed")
    for name, value in (("subjects", subjects), ("trials", trials)):
        if not 1 <= value <= MOST:
            raise InvalidInputError(
                f"{name} must be 1..{MOST}, got {value}", field=name
            )
    if not MIN_SAMPLE_RATE <= rate <= MAX_SAMPLE_RATE:
        raise InvalidInputError(
            f"rate must be {MIN_SAMPLE_RATE:g} to {MAX_SAMPLE_RATE:g} Hz, got {rate}",
            field="rate",
        )
    for point in points or ():
        if not 1 <= point <= 16:
            raise InvalidInputError(
                f"grid point {point} does not exist: points are 1..16", field="points"
            )
    count = len(points) if points else 16
    total = subjects * trials * count
    if total > MOST_TRIALS:
        raise InvalidInputError(
            f"{subjects} subjects x {trials} trials x {count} points = {total} "
            f"trials, more than the {MOST_TRIALS} one set may have (the paper's "
            f"protocol has {SUBJECTS * TRIALS * 16}): ask for fewer subjects, "
            "trials or points",
            field="trials",
            total=total,
            most=MOST_TRIALS,
        )


def synthesize(
    seed: int = 0,
    *,
    subjects: int = SUBJECTS,
    trials: int = TRIALS,
    rate: float = RATE,
    points: tuple[int, ...] | None = None,
) -> DemoSet:
    """The synthetic demonstrations, retargeted to NAO's right arm.

    Args:
        seed: Seed of the one random generator everything is drawn from.
        subjects: Number of subjects.
        trials: Trials per subject and point.
        rate: Sample rate [Hz].
        points: Grid points to reach (1..16); all if ``None``.

    Raises:
        InvalidInputError: for a negative seed, subjects or trials outside
            1..``MOST``, a rate outside the motion model's 1 to 10 000 Hz, a
            point outside 1..16, or more than ``MOST_TRIALS`` trials in all
            (subjects x trials x points), before anything is drawn.
    """
    _check(seed, subjects, trials, rate, points)
    rng = np.random.default_rng(seed)
    people = draw_subjects(subjects, rng)
    styles = [draw_style(rng) for _ in people]
    size = nao_arm_size(Side.RIGHT)
    chosen = points or tuple(range(1, 17))
    out: list[Trial] = []
    for person, style in zip(people, styles, strict=True):
        targets = grid_targets(person.arm_length)
        number = 0
        for point in chosen:
            for _ in range(trials):
                out.append(
                    _trial(
                        person,
                        style,
                        targets[point - 1],
                        point,
                        number,
                        rng,
                        rate,
                        size,
                    )
                )
                number += 1
    return DemoSet({p.name: p for p in people}, out)


def _trial(
    person: Subject,
    style: Style,
    target: FloatArray,
    point: int,
    number: int,
    rng: np.random.Generator,
    rate: float,
    size: ArmSize,
) -> Trial:
    """One reach: plan, sample, add marker noise, retarget."""
    reach = sample_reach(plan_reach(person, style, target, rng), person, rate)
    n = len(reach.times)
    noisy = ArmTrack(
        rng.normal(0.0, MARKER_NOISE, size=(n, 3)),
        reach.elbow + rng.normal(0.0, MARKER_NOISE, size=(n, 3)),
        reach.wrist + rng.normal(0.0, MARKER_NOISE, size=(n, 3)),
    )
    track = retarget(noisy, size)
    wobble = matrix_from_rotation_vector(rng.normal(0.0, ORIENTATION_NOISE, (n, 3)))
    return Trial(
        person.name,
        number,
        point,
        Side.RIGHT,
        reach.times,
        track.shoulder,
        track.elbow,
        track.wrist,
        wobble @ reach.wrist_frame,
        track.wrist[-1].copy(),
        reach.labels,
    )
