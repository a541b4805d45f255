"""The simulated NAO plays frames that pass the bridge's checks within the limits.

A brisk reach, its accelerations and jerks up to 0.8 of the bridge's
limits, goes through the bridge (``RobotBridge``, real libqi) to the
simulated NAO process at 25 fps; the sim's logged states are
differentiated. The sim used to join keys with straight lines, stepping
the speed at every key: its states broke the acceleration and jerk limits
between frames that passed every check (at a 5 ms cycle, several times
over). It plays the clamped cubic spline through the keys now, and the
states lie on it.

What is asserted, and why it holds: the states are the spline's values at
their times (the servo reaches its setpoint; to the log's 6 decimals). A
k-th divided difference of a curve with a continuous (k-1)-th derivative
is a weighted mean of its k-th derivative over the window, so the states'
differences are at most the spline's own speed, acceleration and jerk,
whatever the cycle and its jitter, but for the log's rounding: 1e-6 over
the square of 5 ms is 0.04 rad/s^2 for the acceleration, and over its cube
8 rad/s^3 for the jerk, which grows quickly where a late cycle bunches two
states together; the jerk is asserted on windows of evenly spaced states.
That the spline keeps the limits for these frames is measured (below
0.8), not guaranteed by the frames' checks: no curve through keys is
bounded by their differences alone.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]

from bridge.limits import FrameLimits
from bridge.minimum_jerk import (
    PEAK_ACCELERATION,
    PEAK_JERK,
    PEAK_SPEED,
    minimum_jerk_trajectory,
)
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.messages import Trajectory
from shared.robot import load_arm
from shared.robot.postures import rest

LIMITS = FrameLimits.for_arm("right")
#: Share of the bridge's limits the reach's plan takes.
SHARE = 0.8
#: The log's rounding of angles and times [rad, s].
ROUNDING = 5e-7


def brisk(rng: np.random.Generator) -> Trajectory:
    """Rest -> two seeded postures -> rest, each segment minimum jerk and
    as short as ``SHARE`` of the limits allows (0.2-0.5 s)."""
    arm = load_arm("right").limits
    inner = (arm.lower + 0.15 * arm.span, arm.upper - 0.15 * arm.span)
    postures = [rest("right"), *rng.uniform(*inner, (2, 5)), rest("right")]
    durations = []
    for a, b in pairwise(postures):
        d = np.abs(np.asarray(b) - a)
        need = np.concatenate(
            [
                PEAK_SPEED * d / (SHARE * LIMITS.velocity),
                np.sqrt(PEAK_ACCELERATION * d / (SHARE * LIMITS.acceleration)),
                np.cbrt(PEAK_JERK * d / (SHARE * LIMITS.jerk)),
            ]
        )
        durations.append(float(np.ceil(need.max() * 100.0) / 100.0))
    return minimum_jerk_trajectory("right", postures, durations)


@pytest.fixture
def played(
    request: pytest.FixtureRequest, tmp_path: Path, rng: np.random.Generator
) -> Iterator[tuple[list[dict[str, Any]], float]]:
    """The sim's log after the brisk reach played at 25 fps, and its cycle [s]."""
    period = float(request.param)
    log_path = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log_path, period=period) as sim:
        client = NaoqiClient(sim.url)
        try:
            reply = RobotBridge(client).execute(brisk(rng), rate=25.0)
        finally:
            client.close()
    assert reply.approach_duration == 0.0  # from the sim's rest: one call
    yield read_log(log_path), period


def divided(t: np.ndarray, q: np.ndarray, order: int) -> np.ndarray:
    """``order!`` times the ``order``-th divided differences of ``q`` at ``t``."""
    d = q.copy()
    for k in range(1, order + 1):
        d = k * np.diff(d, axis=0) / (t[k:] - t[:-k])[:, None]
    return d


@pytest.mark.parametrize("played", [0.02, 0.005], indirect=True, ids=["20ms", "5ms"])
def test_the_states_stay_within_the_limits_between_frames(
    played: tuple[list[dict[str, Any]], float],
) -> None:
    log, period = played
    call = next(
        e for e in log if e["event"] == "call" and e["method"] == "angleInterpolation"
    )
    names = LIMITS.names
    states = [e for e in log if e["event"] == "state" and e["t"] >= call["t"] - 1e-6]
    t = np.array([e["t"] for e in states])
    q = np.array([[e["positions"][n] for n in names] for e in states])
    assert len(t) > 0.5 / period

    # The states lie on the spline through the start (rest) and the keys.
    keys = np.array(call["angles"]).T  # (keys, joints)
    key_times = np.concatenate([[0.0], call["times"][0]])
    curve = CubicSpline(
        key_times, np.vstack([rest("right"), keys]), bc_type="clamped", axis=0
    )
    on = curve(np.clip(t - call["t"], 0.0, key_times[-1]))
    assert np.abs(q - on).max() < 1e-5

    speed, accel = divided(t, q, 1), divided(t, q, 2)
    assert (np.abs(speed) <= LIMITS.velocity * 1.001).all()
    assert (np.abs(accel) <= LIMITS.acceleration).all()
    shares = (
        np.max(np.abs(speed) / LIMITS.velocity),
        np.max(np.abs(accel) / LIMITS.acceleration),
    )
    print(f"\ncycle {period:g} s: speed {shares[0]:.2f}, acceleration {shares[1]:.2f}")
    even = np.all(np.abs(np.diff(t)[:, None] - period) < 0.2 * period, axis=1)
    windows = even[:-2] & even[1:-1] & even[2:]
    jerk = divided(t, q, 3)[windows]
    rounding = 6.0 * 8.0 * ROUNDING / (6.0 * (0.8 * period) ** 3)
    assert windows.sum() > 0.25 * len(windows)
    assert (np.abs(jerk) <= LIMITS.jerk + rounding * (1.0 + LIMITS.velocity)).all()
    print(f"jerk {np.max(np.abs(jerk) / LIMITS.jerk):.2f} of the limits")
