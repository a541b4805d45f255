"""A trajectory's velocities against its positions (bridge.velocity_agreement).

The bridge's curve goes through the samples' velocities, and every later
check is made on it: velocities that disagree with the positions (times
scaled alone, other units) are refused before any frame, naming the joint
and the sample, while every trajectory the planner makes passes with margin.
The gap a correct jerk-limited trajectory can show is at most ``J h^3 / 27``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bridge.checked_frames import checked_frames
from bridge.fidelity import FOLLOW_TOLERANCE, follow_tolerance
from bridge.hand import with_hand
from bridge.limits import FrameLimits
from bridge.velocity_agreement import (
    check_velocities,
    fine_rate,
    hermite_gaps,
    positions_slopes,
    stretch_gaps,
)
from services.planner.pipeline import plan
from shared.errors import TrajectoryRefusedError
from shared.messages import PlanRequest, Trajectory, parse
from shared.robot import load_arm

LIMITS = FrameLimits.for_arm("right")

#: A trajectory's fields with one entry per sample.
PER_SAMPLE = (
    "times",
    "positions",
    "velocities",
    "accelerations",
    "primitives",
    "wrist_path",
)


def planned(**request: object) -> Trajectory:
    """The planner's trajectory for ``request`` (a PlanRequest as a dict)."""
    return plan(parse(PlanRequest, request)).trajectory


def largest_gap(trajectory: Trajectory) -> np.ndarray:
    """The largest gap of each joint (the hand's with its speeds) [rad], (j,)."""
    joined, _ = with_hand(trajectory, FrameLimits.for_arm(trajectory.arm))
    t = np.asarray(joined.times)
    q = np.asarray(joined.positions)
    v = np.asarray(joined.velocities)
    return np.asarray(stretch_gaps(v, positions_slopes(t, q), q, t).max(axis=0))


def tolerance_of(trajectory: Trajectory) -> np.ndarray:
    """Each joint's tolerance (the hand's too, with a channel) [rad], (j,)."""
    return follow_tolerance(
        with_hand(trajectory, FrameLimits.for_arm(trajectory.arm))[1]
    )


def slowed(trajectory: Trajectory, factor: float) -> Trajectory:
    """``trajectory`` with its times times ``factor``, its velocities left."""
    times = [factor * t for t in trajectory.times]
    return trajectory.model_copy(update={"times": times})


@pytest.fixture(scope="module")
def reach() -> Trajectory:
    """A planned reach (100 Hz, human pace)."""
    return planned(targets=[{"position": [0.15, -0.1, 0.05]}])


@pytest.fixture(scope="module")
def grasp() -> Trajectory:
    """A planned reach that closes the hand at the target: a hand channel with
    its planned speeds."""
    return planned(targets=[{"position": [0.12, -0.1, 0.05], "hand": "close"}])


def test_the_gap_is_the_largest_difference_of_the_two_curves() -> None:
    """The gap's closed form (the roots of its derivative) against the curve
    sampled every 1e-5 of a stretch, for seeded slope differences of every
    sign, one of them zero, and equal and opposite pairs."""
    rng = np.random.default_rng(5)
    e = rng.normal(0.0, 1.0, (400, 2))
    e[:20, 0] = 0.0
    e[20:40, 1] = -e[20:40, 0]
    e[40:60, 1] = e[40:60, 0]
    s = np.linspace(0.0, 1.0, 100_001)[:, None]
    steps = rng.uniform(0.01, 2.0, (400, 1))
    sampled = steps[:, 0] * np.abs(
        e[:, 0] * s * (1 - s) ** 2 - e[:, 1] * s**2 * (1 - s)
    ).max(axis=0)
    exact = hermite_gaps(e[:, :1], e[:, 1:], steps)[:, 0]
    assert np.all(exact >= sampled - 1e-15)
    np.testing.assert_allclose(exact, sampled, rtol=1e-9, atol=1e-15)


def _jerk_limited(
    rng: np.random.Generator, samples: int, jerk: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A seeded curve at rest at both ends, its jerk piecewise constant and at
    most ``jerk`` [rad/s^3], its pieces of any width (some shorter than a
    step), sampled at 1 s steps: times (n,), positions (n, 1), velocities
    (n, 1), n = ``samples``."""
    duration = float(samples - 1)
    pieces = int(rng.integers(3, 3 * samples))
    width = rng.uniform(0.05, 1.0, pieces)
    width *= duration / width.sum()
    start = np.concatenate([[0.0], np.cumsum(width)[:-1]])
    # the end's acceleration and speed per unit jerk of each piece: made 0
    ends = np.stack([width, width * (duration - start - width / 2)])
    j = rng.uniform(-1.0, 1.0, pieces)
    j -= np.linalg.pinv(ends) @ (ends @ j)
    j *= jerk / np.abs(j).max()
    state = np.zeros((pieces + 1, 3))  # position, speed, acceleration
    for i, (ji, w) in enumerate(zip(j, width, strict=True)):
        q, v, a = state[i]
        position = q + v * w + a * w**2 / 2 + ji * w**3 / 6
        state[i + 1] = (position, v + a * w + ji * w**2 / 2, a + ji * w)
    t = np.arange(samples, dtype=float)
    i = np.clip(np.searchsorted(start, t, side="right") - 1, 0, pieces - 1)
    dt = t - start[i]
    q, v, a = state[i].T
    position = q + v * dt + a * dt**2 / 2 + j[i] * dt**3 / 6
    speed = v + a * dt + j[i] * dt**2 / 2
    assert abs(speed[-1]) < 1e-9 * jerk * duration**2  # at rest at the end
    return t, position[:, None], speed[:, None]


def test_a_jerk_limited_curve_at_rest_keeps_the_bound() -> None:
    """2000 seeded curves at rest at both ends, jerk at most J (jumping, as
    Ruckig's), sampled every h with their own velocities: the curve through
    the velocities stays within ``J h^3 / 27`` of the positions' own (its
    slopes within ``4 J h^2 / 27``), and the worst comes within a factor
    of two of it: the bound is not loose by orders."""
    rng = np.random.default_rng(11)
    worst_gap = worst_slope = 0.0
    jerk = 1.0
    for _ in range(2000):
        t, q, v = _jerk_limited(rng, int(rng.integers(3, 40)), jerk)
        error = v - positions_slopes(t, q)
        gap = hermite_gaps(error[:-1], error[1:], np.ones((len(t) - 1, 1)))
        worst_gap = max(worst_gap, float(gap.max()) / (jerk / 27))
        worst_slope = max(worst_slope, float(np.abs(error).max()) / (4 * jerk / 27))
    print(f"\nworst gap {worst_gap:.3f}, slope {worst_slope:.3f} of the bounds")
    assert 0.5 < worst_gap <= 1.0
    assert 0.5 < worst_slope <= 1.0


def test_the_fine_rate_is_where_the_bound_meets_the_tolerance() -> None:
    """Sampled at the fine rate, the bound is the tolerance: 15.2 Hz for
    RShoulderPitch (jerk 1653.6 rad/s^3, 1 degree), 16 Hz named."""
    tolerance = follow_tolerance(LIMITS)
    rates = [fine_rate(j, tol) for j, tol in zip(LIMITS.jerk, tolerance, strict=True)]
    for rate, jerk, tol in zip(rates, LIMITS.jerk, tolerance, strict=True):
        assert jerk / rate**3 / 27 == pytest.approx(tol)
    assert rates[0] == pytest.approx(15.2, abs=0.05)
    assert max(rates) < 16.0


def test_every_planned_trajectory_passes_with_margin() -> None:
    """Seeded targets of both arms, at human pace and fastest, with the hand
    closing, at the planner's 100 Hz; 25 Hz; a wrist path at its own uneven
    times; each read back from its JSON and with its numbers written to 6
    decimals: the velocities' curve stays within a tenth of the tolerance
    (at 100 Hz within 0.001 degree; the bound is 0.0035)."""
    rng = np.random.default_rng(2024)
    trajectories = []
    for arm in ("right", "left"):
        model = load_arm(arm)
        span = 0.25 * model.limits.span
        inner = (model.limits.lower + span, model.limits.upper - span)
        for _ in range(3):
            target = model.fk(rng.uniform(*inner)).wrist.tolist()
            for extra in ({}, {"fastest": True}, {"rate": 25.0}):
                trajectories.append(
                    planned(arm=arm, targets=[{"position": target}], **extra)
                )
            trajectories.append(
                planned(arm=arm, targets=[{"position": target, "hand": "close"}])
            )
    times = [0.0, 0.3, 0.45, 1.1, 1.6]
    wrist = [[0.15, -0.1 + 0.01 * k, 0.05 + 0.005 * k] for k in range(len(times))]
    trajectories.append(planned(wrist_path={"times": times, "positions": wrist}))
    for trajectory in trajectories:
        limits = FrameLimits.for_arm(trajectory.arm)
        rounded = trajectory.model_copy(
            update={
                name: np.round(np.asarray(getattr(trajectory, name)), 6).tolist()
                for name in ("times", "positions", "velocities")
            }
        )
        for version in (parse(Trajectory, trajectory.to_json()), rounded):
            check_velocities(version, limits)
            gap = largest_gap(version)
            assert np.all(gap < 0.1 * tolerance_of(version))
        if trajectory.times[1] == 0.01:
            assert largest_gap(trajectory).max() < math.radians(1e-3)


def test_a_wrist_path_carries_the_positions_own_slopes(reach: Trajectory) -> None:
    """A wrist path's velocities are its clamped spline's: no gap at all,
    however far apart its samples (0.5 s here)."""
    wrist = [[0.15, -0.1, 0.05], [0.14, -0.11, 0.06], [0.13, -0.12, 0.07]]
    path = planned(wrist_path={"times": [0.0, 0.5, 1.0], "positions": wrist})
    assert largest_gap(path).max() < 1e-12


def test_a_hold_as_one_long_stretch_is_its_chord(reach: Trajectory) -> None:
    """The reach, then its last posture held to t = 80 000 s as one stretch:
    the positions' spline rings over it (3.2 degrees away, from the slope
    its last reach samples leave it), the trajectory's curve is still, as
    the line between the samples is: passed."""
    data = reach.model_dump()
    for name in ("positions", "wrist_path", "primitives"):
        data[name].append(data[name][-1])
    for name in ("velocities", "accelerations"):
        data[name].append([0.0] * 5)
    data["times"].append(8e4)
    held = Trajectory.model_validate(data)
    check_velocities(held, LIMITS)
    t, q, v = (
        np.asarray(getattr(held, n)) for n in ("times", "positions", "velocities")
    )
    slopes = positions_slopes(t, q)
    assert stretch_gaps(v, slopes, q, t)[-1].max() < 1e-9
    spline = hermite_gaps(
        v[-2:-1] - slopes[-2:-1], v[-1:] - slopes[-1:], t[-1:] - t[-2]
    )
    assert spline.max() > 3.0 * FOLLOW_TOLERANCE


@pytest.mark.parametrize(
    ("factor", "gap"), [(20.0, 2.7), (1000.0, 143.8)], ids=["slowed", "ms"]
)
def test_times_scaled_alone_are_refused(
    reach: Trajectory, factor: float, gap: float
) -> None:
    """Times scaled 20 times (a plan slowed by its times alone) and 1000
    times (written in milliseconds), the velocities left: every limit and
    the frame rate pass, the curve strays 2.7 and 143.8 degrees from the
    positions (the hunt's keys off the slowed plan: 2.7 and 144), refused
    naming the joint, the sample and the likely cause."""
    with pytest.raises(TrajectoryRefusedError) as refused:
        checked_frames(slowed(reach, factor), 25.0, LIMITS)
    error = refused.value
    print("\n" + error.message)
    assert error.quantity == "velocities" and error.joint == "RShoulderPitch"
    assert math.degrees(error.value) == pytest.approx(gap, abs=0.05)
    assert error.limit == FOLLOW_TOLERANCE
    assert error.frame == 37
    assert error.time == pytest.approx(0.37 * factor)
    assert error.message.startswith(
        "trajectory refused, nothing was sent: RShoulderPitch velocity -2.607 "
        f"rad/s at sample 37 (t = {0.37 * factor:.3f} s) disagrees with the "
        "positions (their curve: "
    )
    assert (
        f"rad/s there): through these velocities the curve between samples 36 "
        f"and 37 strays at least {gap:.1f} deg both from the positions' own and "
        "from the line between them (at most 1 deg); are the velocities in "
        "other units, or the times scaled without them? If they are right, the "
        "samples are too far apart to show the movement: sample it at 16 Hz "
        "or more, where any trajectory within the limits passes"
    ) in error.message


def test_velocities_in_degrees_are_refused(reach: Trajectory) -> None:
    """Velocities written in degrees per second: refused, naming a joint. The
    samples are fine already, so the refusal does not advise finer ones (it
    said "sample it at 16 Hz or more" to a 100 Hz trajectory)."""
    assert np.diff(reach.times).max() < 1.0 / 16
    degrees = np.degrees(np.asarray(reach.velocities)).tolist()
    with pytest.raises(TrajectoryRefusedError, match="disagrees with the positions"):
        checked_frames(reach.model_copy(update={"velocities": degrees}), 25.0, LIMITS)
    with pytest.raises(TrajectoryRefusedError) as refused:
        check_velocities(reach.model_copy(update={"velocities": degrees}), LIMITS)
    assert "sample it at" not in refused.value.message
    assert refused.value.message.endswith(
        "Sampled at 16 Hz or more, a trajectory within the limits passes only if "
        "they agree"
    )


def test_a_huge_velocity_is_refused_in_exponent_form(reach: Trajectory) -> None:
    """A velocity of 1e300 rad/s (no overflow to NaN, which would pass):
    refused, its gap in exponent form."""
    velocities = np.asarray(reach.velocities)
    velocities[40, 0] = 1e300
    huge = reach.model_copy(update={"velocities": velocities.tolist()})
    with pytest.raises(TrajectoryRefusedError) as refused:
        check_velocities(huge, LIMITS)
    assert "RShoulderPitch velocity 1e+300 rad/s at sample 40" in refused.value.message
    assert "strays at least 8.49e+298 deg" in refused.value.message


def test_the_hands_speeds_are_checked_when_carried(grasp: Trajectory) -> None:
    """The hand's planned speeds pass; in percent per second (100 times)
    they are refused naming RHand in its own units; without speeds (the
    bridge makes them from the hand's positions) there is nothing to
    disagree."""
    check_velocities(grasp, LIMITS)
    percent = [100.0 * v for v in grasp.hand_velocities or []]
    with pytest.raises(TrajectoryRefusedError) as refused:
        check_velocities(grasp.model_copy(update={"hand_velocities": percent}), LIMITS)
    assert refused.value.joint == "RHand"
    assert " /s at sample " in refused.value.message
    assert "(open fraction) both from" in refused.value.message
    unknown = grasp.model_copy(
        update={"hand_velocities": None, "hand_accelerations": None}
    )
    check_velocities(unknown, LIMITS)


def test_a_still_or_single_sample_trajectory_passes(reach: Trajectory) -> None:
    """One sample, or two of the same posture at rest: nothing to disagree."""
    one = reach.model_copy(
        update={name: getattr(reach, name)[:1] for name in PER_SAMPLE}
    )
    check_velocities(one, LIMITS)
    two = one.model_copy(
        update={
            "times": [0.0, 5.0],
            "positions": one.positions * 2,
            "velocities": [[0.0] * 5] * 2,
            "accelerations": [[0.0] * 5] * 2,
            "primitives": one.primitives * 2,
            "wrist_path": one.wrist_path * 2,
        }
    )
    check_velocities(two, LIMITS)
