"""Human performance measures: values, gradients and the H_G blend."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import random_posture

from services.ik.kernel import chain_for
from services.ik.measures import (
    ElbowTravel,
    GraspBlend,
    Measure,
    MeasureParams,
    NoMeasure,
    SwivelGoal,
    TotalPotentialEnergy,
    WristDiscomfortEnergy,
)
from shared.geometry import swivel_angle
from shared.geometry.swivel import elbow_offset_and_gradient
from shared.robot import ArmModel

P = MeasureParams()


def _measures(arm: ArmModel, q0: np.ndarray) -> dict[str, Measure]:
    kin0 = chain_for(arm).state(q0)
    tpe = TotalPotentialEnergy(P.mu)
    ntpe = WristDiscomfortEnergy(tpe, P.omega, P.wrist_centre)
    target = np.array(kin0.p_wrist) + np.array([0.03, 0.0, 0.02])
    return {
        "tpe": tpe,
        "ntpe": ntpe,
        "travel": ElbowTravel(np.array(kin0.p_elbow) + 0.01),
        "grasp": GraspBlend(ElbowTravel(kin0.p_elbow), ntpe, target, 0.05, P.k1, P.k2),
        "swivel": SwivelGoal(2.5, P.swivel_weight),
    }


@pytest.mark.parametrize("name", ["tpe", "ntpe", "travel", "swivel"])
def test_gradients_match_finite_differences(
    arm: ArmModel, rng: np.random.Generator, name: str
) -> None:
    """Each measure's analytic gradient equals central differences of its value."""
    h, checked = 1e-6, 0
    while checked < 40:
        q = random_posture(arm, rng)
        phi = swivel_angle(*arm.fk(q)[:3])
        if min(phi, 2 * math.pi - phi) < 0.1 or abs(phi - 2.5 - math.pi) < 0.1:
            continue
        measure = _measures(arm, random_posture(arm, rng))[name]
        fd = [
            (
                measure.value(chain_for(arm).state(q + h * e))
                - measure.value(chain_for(arm).state(q - h * e))
            )
            / (2 * h)
            for e in np.eye(5)
        ]
        np.testing.assert_allclose(
            measure.gradient(chain_for(arm).state(q)), fd, atol=1e-6
        )
        checked += 1


def test_grasp_gradient_at_fixed_blend(arm: ArmModel, rng: np.random.Generator) -> None:
    """H_G's gradient is the blend of its parts' gradients at the current dd/d."""
    q = random_posture(arm, rng)
    kin = chain_for(arm).state(q)
    m = _measures(arm, q)
    grasp = m["grasp"]
    assert isinstance(grasp, GraspBlend)
    b = grasp.blend(kin)
    expected = P.k1 * (1 - b) * np.array(
        grasp.travel.gradient(kin)
    ) + P.k2 * b * np.array(grasp.ntpe.gradient(kin))
    np.testing.assert_allclose(grasp.gradient(kin), expected)


def test_grasp_blend_hands_over_from_ntpe_to_elbow_travel(arm: ArmModel) -> None:
    """At dd = d, H_G = k2 NTPE; at the target (dd = 0), H_G = k1 s (eq. 21)."""
    q = (arm.limits.lower + arm.limits.upper) / 2
    kin = chain_for(arm).state(q)
    tpe = TotalPotentialEnergy(P.mu)
    ntpe = WristDiscomfortEnergy(tpe, P.omega, P.wrist_centre)
    travel = ElbowTravel(np.array(kin.p_elbow) + np.array([0.01, 0.0, 0.0]))
    far = GraspBlend(
        travel, ntpe, np.array(kin.p_wrist) + np.array([0.05, 0, 0]), 0.05, 2.0, 3.0
    )
    assert far.value(kin) == pytest.approx(3.0 * ntpe.value(kin))
    at = GraspBlend(travel, ntpe, kin.p_wrist, 0.05, 2.0, 3.0)
    assert at.value(kin) == pytest.approx(2.0 * travel.value(kin))


def test_spring_energy_vanishes_with_the_elbow_down(arm: ArmModel) -> None:
    """f_EPE = mu (pi - phi)^2 / 2 with mu = mu0 (r / L_u)^2: zero at phi = pi."""
    tpe = TotalPotentialEnergy(0.5)
    kin = chain_for(arm).state((arm.limits.lower + arm.limits.upper) / 2)
    phi = swivel_angle(kin.shoulder, kin.elbow, kin.wrist)
    e, w = kin.elbow - kin.shoulder, kin.wrist - kin.shoulder
    r = np.linalg.norm(e - (e @ w) / (w @ w) * w)
    stiffness = 0.5 * (r / np.linalg.norm(e)) ** 2
    assert tpe.elastic(kin) == pytest.approx(0.5 * stiffness * (math.pi - phi) ** 2)
    assert tpe.value(kin) == pytest.approx(kin.gravity_energy + tpe.elastic(kin))


def test_wrist_discomfort_is_quadratic_about_the_centre(arm: ArmModel) -> None:
    """NTPE - TPE = omega (theta_wa - theta_N)^2 (eq. 19)."""
    q = (arm.limits.lower + arm.limits.upper) / 2
    q[4] = 0.7
    kin = chain_for(arm).state(q)
    tpe = TotalPotentialEnergy(P.mu)
    ntpe = WristDiscomfortEnergy(tpe, 0.2, 0.1)
    assert ntpe.value(kin) - tpe.value(kin) == pytest.approx(0.2 * 0.6**2)


def test_no_measure_is_zero(arm: ArmModel) -> None:
    """The least-norm baseline's H is identically zero."""
    kin = chain_for(arm).state((arm.limits.lower + arm.limits.upper) / 2)
    assert NoMeasure().value(kin) == 0.0 and not any(NoMeasure().gradient(kin))


def test_a_straight_arm_has_no_spring() -> None:
    """With the elbow on the shoulder-wrist line the swivel is undefined: r = 0."""
    r2, grad = elbow_offset_and_gradient(
        (0.0, 0.0, 0.0),
        (0.1, 0.0, -0.05),
        (0.2, 0.0, -0.1),
        [(0.0, 0.0, 1.0)],
        [(0.0, 0.0, 0.0)],
    )
    assert r2 == pytest.approx(0.0, abs=1e-15)
    assert grad[0] == pytest.approx(
        0.0, abs=1e-15
    )  # moving the elbow off the line: 2nd order


def test_elbow_offset_gradient_matches_finite_differences(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """d(r^2)/dq equals central differences of r^2."""
    chain = chain_for(arm)

    def r2(q: np.ndarray) -> float:
        s = chain.state(q)
        return elbow_offset_and_gradient(s.p_shoulder, s.p_elbow, s.p_wrist, [], [])[0]

    for _ in range(40):
        q = random_posture(arm, rng)
        s = chain.state(q)
        _, grad = elbow_offset_and_gradient(
            s.p_shoulder, s.p_elbow, s.p_wrist, s.je, s.jw
        )
        fd = [(r2(q + 1e-6 * e) - r2(q - 1e-6 * e)) / 2e-6 for e in np.eye(5)]
        np.testing.assert_allclose(grad, fd, atol=1e-9)


def test_nao_at_its_straightest_has_a_weak_spring(arm: ArmModel) -> None:
    """NAO's straightest arm keeps its 15 mm elbow offset: a spring under 5 % of a
    bent arm's at the same swivel error."""
    chain = chain_for(arm)
    q = np.array([0.0, 0.0, 0.5, 0.0, 0.0])
    q[3] = arm.limits.lower[3] if arm.side.value == "right" else arm.limits.upper[3]
    straight = chain.state(q)
    q[3] = 1.2 * arm.side.sign
    bent = chain.state(q)
    tpe = TotalPotentialEnergy(1.0)
    k_straight, _ = tpe._spring(straight)
    k_bent, _ = tpe._spring(bent)
    assert k_straight < 0.05 * k_bent
