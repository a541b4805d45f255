"""The float chain of the IK agrees with pinocchio on every quantity."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_posture

from services.ik.kernel import chain_for
from services.ik.wrists import wrist_positions
from shared.robot import ArmModel

FIELDS = [
    "shoulder",
    "elbow",
    "wrist",
    "wrist_rotation",
    "wrist_jacobian",
    "elbow_jacobian",
    "wrist_angular_jacobian",
    "gravity_gradient",
]


def test_chain_agrees_with_pinocchio(arm: ArmModel, rng: np.random.Generator) -> None:
    """Positions, rotation, Jacobians and gravity agree to 1e-12 on random postures."""
    chain = chain_for(arm)
    for _ in range(300):
        q = random_posture(arm, rng)
        st, kin = chain.state(q), arm.kinematics(q)
        for name in FIELDS:
            np.testing.assert_allclose(
                getattr(st, name), getattr(kin, name), atol=1e-12
            )
        assert st.gravity_energy == pytest.approx(kin.gravity_energy, abs=1e-12)


def test_wrists_of_many_postures_agree_with_pinocchio(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """The array forward kinematics gives each posture's wrist, to 1e-12 m."""
    q = np.array([random_posture(arm, rng) for _ in range(300)])
    wrists = wrist_positions(chain_for(arm), q)
    assert wrists.shape == (300, 3)
    np.testing.assert_allclose(
        wrists, [arm.fk(posture).wrist for posture in q], atol=1e-12
    )


def test_float_fields_match_the_numpy_views(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """origins/jw/je/grav are what the numpy views show."""
    st = chain_for(arm).state(random_posture(arm, rng))
    np.testing.assert_array_equal(
        np.array(st.origins)[[0, 2, 4]], [st.shoulder, st.elbow, st.wrist]
    )
    np.testing.assert_array_equal(np.array(st.jw).T, st.wrist_jacobian)
    assert st.p_wrist == tuple(st.wrist)
