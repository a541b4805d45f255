"""The curve Choregraphe's runtime plays through a behavior's keys (BezierAuto),
and the check that refuses keys whose curve breaks a limit."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.bezier_auto import CurvePeaks, auto_slopes, check_played_curve
from bridge.checks import check_accelerations, check_speeds
from bridge.limits import FrameLimits
from shared.errors import TrajectoryRefusedError
from shared.messages import CommandFrames
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


def bezier(times: np.ndarray, values: np.ndarray, beta: np.ndarray, fps: float):
    """The runtime's Bezier segments sampled densely: time and value of each
    point, from the control points (key, handle a third along, ...)."""
    ts, qs = [], []
    s = np.linspace(0.0, 1.0, 4001)[:, None]
    for i in range(len(times) - 1):
        span = (times[i + 1] - times[i]) * fps  # frames
        px = [times[i], times[i] + span / 3 / fps, times[i + 1] - span / 3 / fps]
        py = [
            values[i],
            values[i] + beta[i] * span / 3,
            values[i + 1] - beta[i + 1] * span / 3,
        ]
        px.append(times[i + 1])
        py.append(values[i + 1])
        w = [(1 - s) ** 3, 3 * s * (1 - s) ** 2, 3 * s**2 * (1 - s), s**3]
        ts.append(sum(wk * x for wk, x in zip(w, px, strict=True))[:, 0])
        qs.append(sum(wk * y for wk, y in zip(w, py, strict=True)))
    return ts, qs


def test_the_peaks_are_those_of_the_bezier_curve(rng: np.random.Generator) -> None:
    """Speed, acceleration and jerk of each segment, found exactly, agree
    with the runtime's Bezier curve built from its control points and
    differentiated numerically."""
    fps = 25
    times = np.arange(12) / fps
    values = np.cumsum(rng.normal(0.0, 0.05, (12, 2)), axis=0)
    peaks = CurvePeaks(times, values, fps)
    beta = auto_slopes(np.arange(1, 13), values)
    ts, qs = bezier(times, values, beta, fps)
    for k, (t, q) in enumerate(zip(ts, qs, strict=True)):
        v = np.gradient(q, t, axis=0)
        a = np.gradient(v, t, axis=0)
        j = np.gradient(a, t, axis=0)
        np.testing.assert_allclose(np.abs(v).max(axis=0), peaks.speed[k], rtol=1e-3)
        np.testing.assert_allclose(
            np.abs(a[2:-2]).max(axis=0), peaks.acceleration[k], rtol=2e-3
        )
        np.testing.assert_allclose(
            np.median(np.abs(j), axis=0), peaks.jerk[k], rtol=1e-3
        )


def test_a_curve_over_a_limit_the_keys_keep_is_refused() -> None:
    """Keys of a turn at 0.8 of the acceleration limit, the turn between two
    keys: their divided differences keep every limit, but the BezierAuto
    curve, level at both keys beside the turn, bends harder: refused,
    naming the joint, the keys and the curve."""
    limits = FrameLimits.for_arm("right")
    accel = 0.8 * limits.acceleration[0]
    t = np.arange(6) / 25.0
    turn = 0.5 * accel * (t - 0.5 * (t[2] + t[3])) ** 2
    q = np.tile(rest("right"), (6, 1))
    q[:, 0] += turn - turn.max()
    velocity = check_speeds(q, t, limits)
    check_accelerations(velocity, t, limits)  # the keys keep the limits
    frames = CommandFrames(
        arm="right",
        rate=25.0,
        joint_names=list(limits.names),
        start=q[0].tolist(),
        times=t[1:].tolist(),
        positions=q[1:].tolist(),
    )
    peaks = CurvePeaks(t, q, 25)
    assert peaks.acceleration[:, 0].max() > 1.2 * limits.acceleration[0]
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_played_curve(frames, limits)
    assert caught.value.joint == "RShoulderPitch"
    assert caught.value.quantity == "acceleration"
    assert "on the curve Choregraphe plays through the keys" in caught.value.message
