"""Shared fixtures: both arms, a seeded random generator, a port in use, a sim;
and helpers: a random posture, a long moving trajectory."""

from __future__ import annotations

import compileall
import os
import signal
import socket
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pytest

from shared.messages import Trajectory
from shared.primitives import PRIMITIVES
from shared.robot import ArmModel, Side, load_arm

if TYPE_CHECKING:
    from bridge.sim import SimProcess


def pytest_configure(config: pytest.Config) -> None:
    """Give the tests, and every process they start, Ctrl-C and hang-ups back.

    A suite started in the background of a script (``cmd &``: SIGINT
    ignored) or under ``nohup`` (SIGHUP ignored) passes that on to each
    process a test starts, and armplan keeps an ignored stop signal ignored
    (as ``nohup`` means): the tests that stop a process with SIGINT or SIGHUP
    would wait for it in vain. A handler (not ``SIG_IGN``) is reset to the
    default in a child at ``exec``.
    """
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if signal.getsignal(signal.SIGHUP) is signal.SIG_IGN:
        signal.signal(signal.SIGHUP, signal.SIG_DFL)
    if "PYTEST_XDIST_WORKER" not in os.environ:
        compile_sources()


def compile_sources() -> None:
    """Write the bytecode of armplan's own packages once, before any test.

    The tests start many processes (services, the command line, the
    simulated NAO), and each imports hundreds of armplan's modules. Where
    ``PYTHONDONTWRITEBYTECODE`` is set, as on machines that keep images
    clean, no process leaves its bytecode behind and every one compiles the
    sources again: 0.4 s of the 1.4 s ``armplan --help`` took on a 2-CPU
    machine. ``compileall`` writes whatever that variable says, so every
    process after it reads the bytecode instead.
    """
    root = Path(__file__).resolve().parent.parent
    for package in ("armplan", "bridge", "services", "shared"):
        compileall.compile_dir(root / package, quiet=1, workers=0)


@pytest.fixture(params=[Side.RIGHT, Side.LEFT], ids=["right", "left"])
def arm(request: pytest.FixtureRequest) -> ArmModel:
    return load_arm(request.param)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


def random_posture(arm: ArmModel, rng: np.random.Generator) -> np.ndarray:
    """A posture drawn uniformly within the joint limits [rad]."""
    return rng.uniform(arm.limits.lower, arm.limits.upper)


def moving_trajectory(
    n: int, rng: np.random.Generator, side: Side = Side.RIGHT
) -> Trajectory:
    """``n`` samples at 100 Hz of an arm wandering within its limits.

    Every number has its full precision (about 380 bytes of JSON a sample,
    as a planned trajectory of a moving arm); labels change every second.
    """
    limits = load_arm(side).limits
    steps = rng.normal(0.0, 0.01, (n, 5))
    q = np.clip(limits.middle + steps.cumsum(axis=0), limits.lower, limits.upper)
    v = np.gradient(q, 0.01, axis=0)
    return Trajectory(
        arm=side,
        joint_names=list(side.joint_names),
        times=(0.01 * np.arange(n)).tolist(),
        positions=q.tolist(),
        velocities=v.tolist(),
        accelerations=np.gradient(v, 0.01, axis=0).tolist(),
        primitives=[PRIMITIVES[i // 100 % len(PRIMITIVES)].name for i in range(n)],
        wrist_path=rng.uniform(-0.2, 0.2, (n, 3)).tolist(),
    )


@pytest.fixture
def busy_port() -> Iterator[int]:
    """A port on 127.0.0.1 that another socket listens on, for the test's time."""
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        yield int(taken.getsockname()[1])


@pytest.fixture
def sim(tmp_path: Path) -> Iterator[SimProcess]:
    """A simulated NAO process logging to ``tmp_path / "sim.jsonl"``."""
    from bridge.sim import SimProcess  # libqi: loaded only by the tests using it

    process = SimProcess(log_path=tmp_path / "sim.jsonl")
    process.start()
    try:
        yield process
    finally:
        process.stop()
