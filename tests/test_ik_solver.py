"""Solving postures: methods, primitives, accuracy, limits, optimality, errors."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import random_posture
from scipy.optimize import minimize

from services.ik import solve, solve_request
from services.ik.iterate import TOLERANCE
from services.ik.kernel import chain_for
from services.ik.kernel.small import NormalSolver
from services.ik.measures import MeasureParams, SwivelGoal, TotalPotentialEnergy
from shared.errors import (
    InvalidInputError,
    JointLimitError,
    PalmRollOutOfRangeError,
    PrimitiveCannotReachError,
    SwivelNotReachedError,
    UnreachableTargetError,
)
from shared.geometry import palm_normal, swivel_angle
from shared.messages import IKRequest, Method, parse
from shared.robot import ArmModel, load_arm
from shared.robot.postures import rest

MM = 1e-3


def _reachable(
    arm: ArmModel, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """(posture, its wrist position): a target known to be reachable."""
    q = random_posture(arm, rng)
    return q, arm.fk(q).wrist


def test_full_reach_primitive_reaches_500_random_targets(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """S_R E_PR W_P puts the wrist within 1 mm of 500 reachable targets, in range."""
    worst = 0.0
    for _ in range(500):
        _, target = _reachable(arm, rng)
        sol = solve(arm, target, primitive="S_R E_PR W_P")
        assert arm.limits.contains(sol.q)
        assert sol.q[4] == rest(arm.side)[4]  # WristYaw is not active
        worst = max(worst, float(np.linalg.norm(arm.fk(sol.q).wrist - target)))
    assert worst < MM


def test_full_grasp_primitive_reaches_position_and_palm(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """S_R E_PR W_PR reaches 150 reachable wrist poses (position and palm)."""
    for _ in range(150):
        q, target = _reachable(arm, rng)
        palm = palm_normal(arm.rotation(q, "wrist"), arm.side.sign)
        sol = solve(arm, target, primitive="S_R E_PR W_PR", palm=palm)
        assert arm.limits.contains(sol.q)
        assert np.linalg.norm(arm.fk(sol.q).wrist - target) < MM
        reached = palm_normal(arm.rotation(sol.q, "wrist"), arm.side.sign)
        axis = arm.rotation(sol.q, "wrist")[:, 0]
        wanted = palm - (palm @ axis) * axis
        if np.linalg.norm(wanted) > 0.1:
            assert reached @ wanted / np.linalg.norm(wanted) > math.cos(
                math.radians(1.0)
            )


@pytest.mark.parametrize("method", [Method.LEAST_NORM, Method.SINGLE])
def test_baselines_reach_random_targets(
    arm: ArmModel, rng: np.random.Generator, method: Method
) -> None:
    """The two baselines also reach 100 reachable targets within 1 mm."""
    for _ in range(100):
        _, target = _reachable(arm, rng)
        sol = solve(arm, target, method=method)
        assert sol.primitive is None and sol.method is method
        assert arm.limits.contains(sol.q)
        assert np.linalg.norm(arm.fk(sol.q).wrist - target) < MM


def test_gpm_solution_is_a_constrained_optimum_of_tpe(rng: np.random.Generator) -> None:
    """SLSQP started at the GPM posture finds no lower TPE on the target's
    self-motion manifold (two methods agree on the optimum). With a swivel
    spring (mu > 0): with gravity alone (the fitted mu, 0) a hanging arm's
    swivel is nearly free and many optima are flat."""
    arm = load_arm("right")
    params = MeasureParams(mu=0.03)
    tpe = TotalPotentialEnergy(params.mu)
    free = np.arange(4)
    bounds = list(zip(arm.limits.lower[free], arm.limits.upper[free], strict=True))
    compared = 0
    for _ in range(100):
        _, target = _reachable(arm, rng)
        sol = solve(arm, target, primitive="S_R E_PR W_P", params=params)
        near_limit = np.minimum(
            sol.q[free] - arm.limits.lower[free], arm.limits.upper[free] - sol.q[free]
        )
        if near_limit.min() < 1e-3:
            continue  # optimum on a limit: checked by the GPM tests
        kin = chain_for(arm).state(sol.q)
        solver = NormalSolver(kin.jw, [int(k) for k in free], 0.0, 1e-8)
        grad = tpe.gradient(kin)
        projected = np.array(grad[:4]) - solver.apply(solver.times(grad))
        assert np.abs(projected).max() < 1e-5
        res = minimize(
            _tpe_of_first_four,
            sol.q[free],
            args=(arm, tpe, sol.q[4]),
            method="SLSQP",
            constraints=[
                {"type": "eq", "fun": _wrist_miss, "args": (arm, sol.q[4], target)}
            ],
            bounds=bounds,
            options={"ftol": 1e-12, "maxiter": 200},
        )
        assert res.fun >= tpe.value(kin) - 1e-7
        compared += 1
    assert compared >= 20


def test_primitive_that_cannot_reach_says_so(arm: ArmModel) -> None:
    """S_R E_P W_P cannot bring the wrist this near the shoulder: a typed
    error that names the distances ElbowYaw sweeps at the held ElbowRoll."""
    start = rest(arm.side)
    points = arm.fk(start)
    out = points.wrist - points.shoulder
    target = points.shoulder + out / np.linalg.norm(out) * 0.125
    low, high = arm.distance_span_at(start[3])
    assert not low <= 0.125 <= high
    reason = (
        f"only ShoulderPitch, ShoulderRoll, ElbowYaw move, so with ElbowRoll at "
        f"{start[3]:.4f} rad the wrist stays {low:.4f}..{high:.4f} m from the "
        "shoulder (the target is 0.1250 m from it); closest"
    )
    with pytest.raises(PrimitiveCannotReachError, match=re.escape(reason)):
        solve(arm, target, primitive="S_R E_P W_P")


@pytest.mark.parametrize("name", ["S_R E_P W_P", "S_R E_P W_PR"])
def test_shoulder_swing_reaches_what_its_joints_reach(
    arm: ArmModel, rng: np.random.Generator, name: str
) -> None:
    """S_R E_P W_P and S_R E_P W_PR land on every target (and, for W_PR, palm)
    that moving their own joints reaches from the start, though ElbowYaw then
    changes the wrist's distance from the shoulder (NAO's elbow offset); the
    other joints keep the start's angles."""
    active = [0, 1, 2] if name == "S_R E_P W_P" else [0, 1, 2, 4]
    for k in range(40):
        start = random_posture(arm, rng)
        goal = start.copy()
        goal[active] += rng.normal(scale=0.4, size=len(active))
        goal = arm.limits.clip(goal)
        target = arm.fk(goal).wrist
        palm = None
        if name == "S_R E_P W_PR" and k % 2:
            palm = palm_normal(arm.rotation(goal, "wrist"), arm.side.sign)
        sol = solve(arm, target, primitive=name, start=start, palm=palm)
        assert np.linalg.norm(arm.fk(sol.q).wrist - target) <= TOLERANCE
        assert arm.limits.contains(sol.q)
        idle = [j for j in range(5) if j not in active]
        np.testing.assert_array_equal(sol.q[idle], start[idle])


def test_function_primitive_swivels_the_elbow_round_the_held_wrist(
    arm: ArmModel,
) -> None:
    """S_R E_P W_R holds the wrist and moves the swivel angle to its goal."""
    start = np.array([0.3, -0.3, 1.0, 0.9, 0.0]) * np.array([1, *[arm.side.sign] * 4])
    points = arm.fk(start)
    phi0 = swivel_angle(*points[:3])
    goal = phi0 + 0.3
    sol = solve(arm, points.wrist, primitive="S_R E_P W_R", start=start, swivel=goal)
    after = arm.fk(sol.q)
    assert np.linalg.norm(after.wrist - points.wrist) < MM
    assert swivel_angle(*after[:3]) == pytest.approx(goal, abs=1e-3)
    assert SwivelGoal(goal, 1.0).value(chain_for(arm).state(sol.q)) < 1e-6
    with pytest.raises(PrimitiveCannotReachError, match="holds the wrist in place"):
        solve(arm, points.wrist + 0.01, primitive="S_R E_P W_R", start=start)


def _bent_start(arm: ArmModel) -> np.ndarray:
    """A bent arm in front of the shoulder, mirrored for the left arm [rad]."""
    return np.array([0.3, -0.3, 1.0, 0.9, 0.0]) * np.array([1, *[arm.side.sign] * 4])


def test_the_swivel_reached_is_reported_beside_the_swivel_asked(
    arm: ArmModel,
) -> None:
    """The IK result says which swivel was asked and which was reached."""
    start = _bent_start(arm)
    points = arm.fk(start)
    goal = swivel_angle(*points[:3]) + 0.3
    request = IKRequest(
        arm=arm.side,
        target=tuple(points.wrist),
        primitive="S_R E_P W_R",
        start=tuple(start),
        swivel=goal,
    )
    result = solve_request(arm, request)
    assert result.swivel_goal == goal
    assert result.swivel_reached == pytest.approx(goal, abs=1e-3)
    q = np.array(list(result.joints.values()))
    assert swivel_angle(*arm.fk(q)[:3]) == pytest.approx(result.swivel_reached)


def test_a_swivel_stopped_by_a_joint_limit_is_refused_naming_the_joint(
    arm: ArmModel,
) -> None:
    """Two radians on from the bent arm, ElbowYaw meets its limit 0.87 rad
    short of the goal with the wrist held: once a silent success, now a typed
    error with the swivel reached, the joint and the posture it stopped in."""
    start = _bent_start(arm)
    points = arm.fk(start)
    goal = swivel_angle(*points[:3]) + 2.0 * arm.side.sign
    with pytest.raises(SwivelNotReachedError) as caught:
        solve(arm, points.wrist, primitive="S_R E_P W_R", start=start, swivel=goal)
    error = caught.value
    elbow_yaw = arm.joint_names[2]
    assert error.joint == elbow_yaw
    assert error.limit == pytest.approx(arm.side.sign * arm.limits.upper[2])
    q = np.array([error.joints[name] for name in arm.joint_names])
    assert arm.limits.contains(q)
    after = arm.fk(q)
    assert np.linalg.norm(after.wrist - points.wrist) < MM
    assert error.reached == pytest.approx(swivel_angle(*after[:3]))
    assert abs(error.shortfall) == pytest.approx(0.87, abs=0.01)
    assert error.elbow_miss > TOLERANCE
    assert f"{elbow_yaw} is on its limit" in error.message
    assert f"elbow swivel {goal:.4f} rad not reached" in error.message


def test_too_far_target_names_the_reach() -> None:
    """Outside the reach shell: UnreachableTargetError with distance and span."""
    arm = load_arm("right")
    with pytest.raises(UnreachableTargetError) as info:
        solve(arm, np.array([0.5, -0.12, 0.05]))
    assert "0.5030 m from the right shoulder" in str(info.value)
    assert info.value.reach == pytest.approx(arm.reach)


def test_target_behind_the_back_is_unreachable() -> None:
    """In the shell but behind the shoulder: the error says how far the
    solver stopped, not that no posture gets closer (which it does not know:
    it once claimed so 138.5 mm off where a posture 5.7 mm off exists)."""
    with pytest.raises(
        UnreachableTargetError, match=r"the IK solver stopped \d+\.\d mm from it"
    ):
        solve(load_arm("right"), np.array([-0.15, -0.098, 0.1]))


def test_a_palm_no_posture_can_meet_is_named() -> None:
    """A target within reach with a palm no posture in range turns that way
    there (the right palm facing forward, 0.78 rad of roll short at best by
    sampling): the error says the target is reached and names the palm and
    the WristYaw it needs (it said the solver stopped some millimetres from
    the target, as if the target were out of reach)."""
    arm, target = load_arm("right"), np.array([0.12, -0.13, 0.05])
    assert solve(arm, target).error < 1e-5
    with pytest.raises(
        PalmRollOutOfRangeError,
        match=r"is within the right arm's reach, but the palm cannot be turned "
        r"towards \(1, 0, 0\) there: .* needs WristYaw = -?\d\.\d{3} rad, outside "
        r"its range -1\.824\.\.1\.824 rad",
    ) as refused:
        solve(arm, target, palm=np.array([1.0, 0.0, 0.0]))
    assert isinstance(refused.value, UnreachableTargetError)
    assert refused.value.kind == "palm_roll_out_of_range"


def test_a_roll_the_primitive_cannot_make_is_named_as_a_roll() -> None:
    """S_R W_PR holds the wrist on its target but cannot roll the palm the
    19.2 deg still needed: the error says it is the roll about the forearm
    that falls short (it said "the palm stays 19.2 deg from the wanted
    direction", though the palm's angle is not what is checked)."""
    arm = load_arm("right")
    start = np.array([1.9260609670694095, -0.26622793189168914, -0.9228339881774912])
    start = np.append(start, [1.1088699776477373, -1.0331512899623787])
    palm = np.array([-0.8834222964244314, -0.3550586231553897, -0.30577511393699597])
    with pytest.raises(
        PrimitiveCannotReachError,
        match=r"the palm's roll about the forearm stays 19\.2 deg short of "
        r"turning it towards the wanted direction; closest wrist position .* is "
        r"0\.0 mm away",
    ):
        solve(arm, arm.fk(start).wrist, primitive="S_R W_PR", palm=palm, start=start)


def test_start_outside_the_limits_is_refused() -> None:
    """A start posture out of range raises JointLimitError naming the joint."""
    q = rest("right")
    q[1] = 1.0
    with pytest.raises(JointLimitError, match=r"RShoulderRoll .* in the start posture"):
        solve(load_arm("right"), np.array([0.12, -0.13, 0.05]), start=q)


def test_option_mismatches_are_typed_errors() -> None:
    """A primitive with a baseline, or a palm without W_R/W_PR, is refused."""
    arm, target = load_arm("right"), np.array([0.12, -0.13, 0.05])
    with pytest.raises(InvalidInputError, match="applies to method 'mp' only"):
        solve(arm, target, method=Method.SINGLE, primitive="S_R E_PR W_P")
    with pytest.raises(InvalidInputError, match="does not turn the wrist"):
        solve(arm, target, primitive="S_R E_PR W_P", palm=np.array([0.0, 0.0, 1.0]))


def test_nan_target_is_refused_at_the_boundary() -> None:
    """The request message rejects a NaN target, naming the field."""
    with pytest.raises(InvalidInputError, match=r"target\.0"):
        parse(IKRequest, {"target": [float("nan"), 0.0, 0.0]})


def test_request_result_keys_joints_by_nao_name() -> None:
    """solve_request answers with joints keyed by NAO name and the reached wrist."""
    arm = load_arm("left")
    result = solve_request(arm, IKRequest(arm="left", target=(0.12, 0.13, 0.05)))
    assert list(result.joints) == list(arm.joint_names)
    assert result.error < MM
    assert result.primitive == "S_R E_PR W_P"


def test_a_requests_measure_weights_reach_the_solver() -> None:
    """The request's ``measures`` are the solver's: with a palm, single's
    posture moves with the wrist discomfort weight (the wrist's turn shifts to
    WristYaw as omega falls), and the shipped weights given explicitly change
    nothing."""
    arm = load_arm("right")

    def joints(**measures: float) -> np.ndarray:
        request = parse(
            IKRequest,
            {"target": [0.12, -0.13, 0.05], "palm": [0, 0, 1], "method": "single",
             "measures": measures},
        )  # fmt: skip
        return np.array(list(solve_request(arm, request).joints.values()))

    default = joints()
    shipped = MeasureParams()
    np.testing.assert_array_equal(joints(omega=shipped.omega, mu=shipped.mu), default)
    free, stiff = joints(omega=0.0), joints(omega=1000.0)
    assert abs(free[4]) > abs(default[4]) > abs(stiff[4])


def _tpe_of_first_four(
    x: np.ndarray, arm: ArmModel, tpe: TotalPotentialEnergy, wrist_yaw: float
) -> float:
    return tpe.value(chain_for(arm).state(np.append(x, wrist_yaw)))


def _wrist_miss(
    x: np.ndarray, arm: ArmModel, wrist_yaw: float, target: np.ndarray
) -> np.ndarray:
    return arm.fk(np.append(x, wrist_yaw)).wrist - target
