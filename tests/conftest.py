"""Shared fixtures: both arms, and a seeded random generator."""

from __future__ import annotations

import numpy as np
import pytest

from shared.robot import ArmModel, Side, load_arm


@pytest.fixture(params=[Side.RIGHT, Side.LEFT], ids=["right", "left"])
def arm(request: pytest.FixtureRequest) -> ArmModel:
    return load_arm(request.param)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


def random_posture(arm: ArmModel, rng: np.random.Generator) -> np.ndarray:
    """A posture drawn uniformly within the joint limits [rad]."""
    return rng.uniform(arm.limits.lower, arm.limits.upper)
