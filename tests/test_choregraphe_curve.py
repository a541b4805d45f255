"""The curve Choregraphe's runtime plays through a behavior's keys and their
tangents (written, or BezierAuto for keys without), and the check that
refuses keys whose curve breaks a limit."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.bezier_auto import auto_handles, auto_slopes
from bridge.bezier_curve import CurvePeaks, PlayedCurve, check_played_curve
from bridge.checks import check_accelerations, check_speeds
from bridge.key_tangents import tangent_handles
from bridge.limits import FrameLimits
from shared.errors import TrajectoryRefusedError
from shared.robot.postures import rest


def test_slopes_follow_the_runtimes_rules() -> None:
    """updateBezierAutoTangents: 0 at the ends and where a key is not
    between its neighbours (a turn, or level with one); else the
    neighbours' slope, cut so that no handle (a third of the way) passes
    the neighbour's value."""
    frames = np.arange(1, 8)
    values = np.array([0.0, 1.0, 2.0, 2.1, 1.0, 1.0, 0.0])[:, None]
    beta = auto_slopes(frames, values)[:, 0]
    assert beta[0] == 0.0 and beta[-1] == 0.0
    assert beta[1] == pytest.approx(1.0)  # (2 - 0) / 2: handles within 1
    # (2.1 - 1) / 2 = 0.55 would put the right handle at 2 + 0.55 / 3 > 2.1:
    # cut to 3 * 0.1 = 0.3
    assert beta[2] == pytest.approx(0.3)
    assert beta[3] == 0.0  # a turn
    assert beta[4] == 0.0 and beta[5] == 0.0  # level with a neighbour


def test_auto_handles_are_the_runtimes_offsets() -> None:
    """updateBezierAutoTangents' offsets: left (-1/3, -beta / 3) times the
    frames to the left neighbour, right (1/3, beta / 3) times those to the
    right one; (0, 0) where there is no neighbour."""
    frames = np.array([1, 2, 4, 5])
    values = np.array([0.0, 1.0, 3.0, 3.5])[:, None]
    beta = auto_slopes(frames, values)[:, 0]
    left, right = auto_handles(frames, values)
    np.testing.assert_allclose(left[:, 0, 0], [0.0, -1 / 3, -2 / 3, -1 / 3])
    np.testing.assert_allclose(right[:, 0, 0], [1 / 3, 2 / 3, 1 / 3, 0.0])
    np.testing.assert_allclose(left[:, 0, 1], left[:, 0, 0] * beta)
    np.testing.assert_allclose(right[:, 0, 1], right[:, 0, 0] * beta)


def bezier(curve: PlayedCurve) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The runtime's Bezier segments sampled densely: time and value of each
    point, from the control points (key, its right handle a third along,
    the next key's left handle, the next key)."""
    ts, qs = [], []
    s = np.linspace(0.0, 1.0, 4001)[:, None]
    t, q = curve.times, curve.values
    for i in range(len(t) - 1):
        dt = t[i + 1] - t[i]
        px = [t[i], t[i] + dt / 3, t[i + 1] - dt / 3, t[i + 1]]
        py = [q[i], q[i] + curve.right[i], q[i + 1] + curve.left[i + 1], q[i + 1]]
        w = [(1 - s) ** 3, 3 * s * (1 - s) ** 2, 3 * s**2 * (1 - s), s**3]
        ts.append(sum(wk * x for wk, x in zip(w, px, strict=True))[:, 0])
        qs.append(sum(wk * y for wk, y in zip(w, py, strict=True)))
    return ts, qs


def random_curve(rng: np.random.Generator, fps: int, handles: str) -> PlayedCurve:
    """Twelve keys of two curves, a frame apart, with BezierAuto handles or
    handles of random slopes (``handles``: "auto" or "written")."""
    times = np.arange(12) / fps
    values = np.cumsum(rng.normal(0.0, 0.05, (12, 2)), axis=0)
    frames = np.arange(1, 13)
    if handles == "auto":
        left, right = auto_handles(frames, values)
    else:
        left, right = tangent_handles(frames, rng.normal(0.0, 0.05, (12, 2)))
    return PlayedCurve(["a", "b"], times, values, left[..., 1], right[..., 1])


@pytest.mark.parametrize("handles", ["auto", "written"])
def test_the_peaks_are_those_of_the_bezier_curve(
    handles: str, rng: np.random.Generator
) -> None:
    """Extremes of angle, speed, acceleration and jerk of each segment,
    found exactly, agree with the runtime's Bezier curve built from its
    control points and differentiated numerically."""
    curve = random_curve(rng, 25, handles)
    peaks = CurvePeaks(curve)
    ts, qs = bezier(curve)
    for k, (t, q) in enumerate(zip(ts, qs, strict=True)):
        v = np.gradient(q, t, axis=0)
        a = np.gradient(v, t, axis=0)
        j = np.gradient(a, t, axis=0)
        # sampled, the extremes can only be missed, by a hair
        assert (q.min(axis=0) >= peaks.lowest[k] - 1e-12).all()
        assert (q.max(axis=0) <= peaks.highest[k] + 1e-12).all()
        np.testing.assert_allclose(q.min(axis=0), peaks.lowest[k], atol=1e-8)
        np.testing.assert_allclose(q.max(axis=0), peaks.highest[k], atol=1e-8)
        np.testing.assert_allclose(np.abs(v).max(axis=0), peaks.speed[k], rtol=1e-3)
        np.testing.assert_allclose(
            np.abs(a[2:-2]).max(axis=0), peaks.acceleration[k], rtol=2e-3
        )
        np.testing.assert_allclose(
            np.median(np.abs(j), axis=0), peaks.jerk[k], rtol=1e-3
        )


def turn(accel: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Six keys at 25 fps of RShoulderPitch turning back between keys 2 and
    3 at ``accel`` [rad/s^2] (the other joints at rest): times [s], angles
    (6, 5) [rad] and the turn's own velocities (6, 5) [rad/s]."""
    t = np.arange(6) / 25.0
    middle = 0.5 * (t[2] + t[3])
    q = np.tile(rest("right"), (6, 1))
    shape = 0.5 * accel * (t - middle) ** 2
    q[:, 0] += shape - shape.max()
    v = np.zeros_like(q)
    v[:, 0] = accel * (t - middle)
    return t, q, v


def test_a_bezier_auto_curve_over_a_limit_the_keys_keep_is_refused() -> None:
    """Keys of a turn at 0.8 of the acceleration limit, the turn between two
    keys, without tangents: their divided differences keep every limit, but
    the BezierAuto curve, level at both keys beside the turn, bends harder:
    refused, naming the joint, the keys and the curve."""
    limits = FrameLimits.for_arm("right")
    t, q, _ = turn(0.8 * limits.acceleration[0])
    velocity = check_speeds(q, t, limits)
    check_accelerations(velocity, t, limits)  # the keys keep the limits
    left, right = auto_handles(np.arange(1, 7), q)
    curve = PlayedCurve(list(limits.names), t, q, left[..., 1], right[..., 1])
    peaks = CurvePeaks(curve)
    assert peaks.acceleration[:, 0].max() > 1.2 * limits.acceleration[0]
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_played_curve(curve, limits)
    assert caught.value.joint == "RShoulderPitch"
    assert caught.value.quantity == "acceleration"
    assert "on the curve Choregraphe plays through the keys" in caught.value.message


def test_the_same_keys_with_their_velocities_play_the_turn_itself() -> None:
    """The same keys, their tangents the turn's own velocities: each segment
    is the turn (a parabola, which a Hermite cubic reproduces), at 0.8 of
    the acceleration limit and without jerk: it passes."""
    limits = FrameLimits.for_arm("right")
    accel = 0.8 * limits.acceleration[0]
    t, q, v = turn(accel)
    left, right = tangent_handles(np.arange(1, 7), v / 25.0)
    curve = PlayedCurve(list(limits.names), t, q, left[..., 1], right[..., 1])
    peaks = CurvePeaks(curve)
    np.testing.assert_allclose(peaks.acceleration[:, 0], accel, rtol=1e-9)
    assert peaks.jerk.max() < 1e-6 * limits.jerk.min()
    check_played_curve(curve, limits)


def test_a_curve_leaving_a_joints_range_between_keys_is_refused() -> None:
    """Keys inside RShoulderRoll's range, a handle past its upper bound: the
    curve between the keys goes out of range, and is refused with quantity
    position, naming the bound."""
    limits = FrameLimits.for_arm("right")
    q = np.tile(rest("right"), (3, 1))
    q[:, 1] = limits.upper[1] - np.array([0.01, 0.001, 0.01])
    slopes = np.zeros_like(q)
    slopes[0, 1] = 0.05  # [rad per frame]: a third of it is 0.017 rad
    left, right = tangent_handles(np.arange(1, 4), slopes)
    curve = PlayedCurve(
        list(limits.names), np.arange(3) / 25.0, q, left[..., 1], right[..., 1]
    )
    assert CurvePeaks(curve).highest[0, 1] > limits.upper[1]
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_played_curve(curve, limits)
    assert caught.value.quantity == "position"
    assert caught.value.limit == limits.upper[1]
    assert "between frames 0 and 1" in caught.value.message
    assert "is outside its range" in caught.value.message
