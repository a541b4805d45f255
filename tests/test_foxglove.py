"""Foxglove channels: link poses against the robot file, schemas, timing.

The FrameTransforms are chained back into positions and compared with two
other computations of the arm's forward kinematics: pinocchio's
(``ArmModel.fk``) and a plain one written here from the URDF's XML.
"""

from __future__ import annotations

import json
import tracemalloc
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np
import pytest
from conftest import moving_trajectory
from frame_chain import chain_poses

from services.ik.kernel.chain import chain_for
from shared.messages import Decision, JointState, PointDecision, Trajectory
from shared.messages.frames import CommandFrames
from shared.primitives import BY_NAME
from shared.recording.foxglove import (
    COMMANDED_TF_TOPIC,
    DECISION_TOPIC,
    EXECUTED_TF_TOPIC,
    FRAME_TRANSFORMS_SCHEMA_NAME,
    PLANNED_PRIMITIVE_TOPIC,
    PLANNED_TF_TOPIC,
    PRIMITIVE_NAMES,
    FoxgloveChannels,
    FrameTransforms,
    PrimitiveSample,
    RobotDescription,
    arm_links,
    description_message,
    frame_transforms_schema,
)
from shared.recording.foxglove.link_poses import link_poses
from shared.recording.foxglove.schemas import FrameTransform, Quaternion, Vector3
from shared.recording.foxglove.transforms import frame_transforms, transforms_json
from shared.recording.writer import MAX_TIME
from shared.robot import ArmModel, Side, load_arm
from shared.robot.arm_model import urdf_text

TOL = 1e-9  # [m]
T0 = 1_700_000_000_123_456_789  # [ns]


def random_posture(arm: ArmModel, rng: np.random.Generator) -> np.ndarray:
    return rng.uniform(arm.limits.lower, arm.limits.upper)


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation about a unit axis."""
    k = np.array(
        [[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]]
    )
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def urdf_points(side: Side, q: np.ndarray) -> dict[str, np.ndarray]:
    """Link origins in the torso frame, chained straight from the URDF's XML."""
    joints = {j.get("name"): j for j in ET.fromstring(urdf_text()).iter("joint")}
    names = [*side.joint_names, side.hand_joint]
    r, p, out = np.eye(3), np.zeros(3), {}
    for name, angle in zip(names, [*q, 0.0], strict=True):
        joint = joints[name]
        origin = np.array(joint.find("origin").get("xyz").split(), dtype=float)
        axis = np.array(joint.find("axis").get("xyz").split(), dtype=float)
        p = p + r @ origin
        r = r @ rotation(axis, angle)
        out[joint.find("child").get("link")] = p
    return out


def test_links_follow_the_urdf_tree(arm: ArmModel) -> None:
    """The frames are the URDF's link names, root first, ending at the gripper."""
    p = arm.side.prefix
    g = p.lower()
    assert arm_links(arm.side) == (
        "torso",
        f"{p}Shoulder",
        f"{p}Bicep",
        f"{p}Elbow",
        f"{p}ForeArm",
        f"{g}_wrist",
        f"{g}_gripper",
    )


def test_chained_transforms_give_the_forward_kinematics(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Shoulder, elbow, wrist and hand from the transforms match fk() to 1e-9 m."""
    links = arm_links(arm.side)
    for _ in range(50):
        q = random_posture(arm, rng)
        poses = chain_poses(json.loads(frame_transforms(arm, q, T0).to_json()))
        fk = arm.fk(q)
        points = (links[1], links[3], links[5], links[6])
        for point, link in zip(fk._fields, points, strict=True):
            assert np.abs(poses[link][1] - getattr(fk, point)).max() < TOL, point
        wrist_rotation = arm.rotation(q, "wrist")
        assert np.abs(poses[links[5]][0] - wrist_rotation).max() < 1e-9


def test_transforms_match_the_urdf_read_directly(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Every link origin matches a chain built from the URDF XML (no pinocchio)."""
    for _ in range(50):
        q = random_posture(arm, rng)
        poses = chain_poses(json.loads(frame_transforms(arm, q, T0).to_json()))
        for link, point in urdf_points(arm.side, q).items():
            assert np.abs(poses[link][1] - point).max() < TOL, link


def test_transforms_match_the_float_kernel(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """The IK's float chain (services/ik/kernel) agrees on shoulder, elbow, wrist."""
    links = arm_links(arm.side)
    chain = chain_for(arm)
    for _ in range(20):
        q = random_posture(arm, rng)
        poses = chain_poses(json.loads(frame_transforms(arm, q, T0).to_json()))
        state = chain.state(q)
        points = (links[1], links[3], links[5])
        for origin, link in zip(state.origins[::2], points, strict=True):
            assert np.abs(poses[link][1] - np.array(origin)).max() < TOL
        assert np.abs(poses[links[5]][0] - np.array(state.rot)).max() < 1e-9


def test_timestamps_and_prefixes() -> None:
    """Every transform carries the stamp; the prefix spares the root torso."""
    arm_model = load_arm(Side.RIGHT)
    message = frame_transforms(arm_model, np.zeros(5), T0, "executed/")
    first = message.transforms[0]
    assert first.parent_frame_id == "torso"
    assert first.child_frame_id == "executed/RShoulder"
    assert message.transforms[1].parent_frame_id == "executed/RShoulder"
    assert {t.timestamp.ns for t in message.transforms} == {T0}
    assert first.timestamp.sec == T0 // 10**9
    assert first.timestamp.nsec == T0 % 10**9


def schema_fields(schema: dict[str, Any]) -> Any:
    """The nested property names of a JSON schema object."""
    if schema.get("type") == "array":
        return [schema_fields(schema["items"])]
    if "properties" not in schema:
        return schema["type"]
    return {name: schema_fields(s) for name, s in schema["properties"].items()}


def model_fields(model: Any) -> Any:
    """The nested field names of a pydantic model, shaped like schema_fields."""
    out = {}
    for name, info in model.model_fields.items():
        annotation = info.annotation
        if hasattr(annotation, "model_fields"):
            out[name] = model_fields(annotation)
        elif getattr(annotation, "__origin__", None) is list:
            out[name] = [model_fields(annotation.__args__[0])]
        else:
            out[name] = {int: "integer", float: "number", str: "string"}[annotation]
    return out


def test_the_models_mirror_foxglove_s_schema() -> None:
    """Field for field and type for type, the models are Foxglove's schema."""
    schema = frame_transforms_schema()
    assert schema["title"] == FRAME_TRANSFORMS_SCHEMA_NAME
    assert schema_fields(schema) == model_fields(FrameTransforms)
    item = schema["properties"]["transforms"]["items"]
    assert item["title"] == "foxglove.FrameTransform"
    assert item["properties"]["translation"]["title"] == "foxglove.Vector3"
    assert item["properties"]["rotation"]["title"] == "foxglove.Quaternion"
    assert item["properties"]["timestamp"]["properties"]["nsec"]["maximum"] == (
        10**9 - 1
    )


def test_a_structurally_wrong_transform_is_refused() -> None:
    """Missing fields, nsec out of range and extra fields fail validation."""
    good = FrameTransforms(
        transforms=[
            FrameTransform(
                timestamp={"sec": 1, "nsec": 2},
                parent_frame_id="torso",
                child_frame_id="RShoulder",
                translation=Vector3(x=0, y=0, z=0),
                rotation=Quaternion(x=0, y=0, z=0, w=1),
            )
        ]
    ).model_dump()
    FrameTransforms.model_validate(good)
    bad_nsec = json.loads(json.dumps(good))
    bad_nsec["transforms"][0]["timestamp"]["nsec"] = 10**9
    missing = json.loads(json.dumps(good))
    del missing["transforms"][0]["rotation"]
    extra = json.loads(json.dumps(good))
    extra["transforms"][0]["scale"] = 1
    for bad in (bad_nsec, missing, extra):
        with pytest.raises(ValueError):
            FrameTransforms.model_validate(bad)


def trajectory(side: Side = Side.RIGHT, n: int = 5) -> Trajectory:
    rows = [[0.1 * i, -0.1 * i, 0.2, 0.5 * side.sign, 0.05 * i] for i in range(n)]
    zeros = [[0.0] * 5 for _ in range(n)]
    return Trajectory(
        arm=side,
        joint_names=list(side.joint_names),
        times=[0.5 + 0.01 * i for i in range(n)],
        positions=rows,
        velocities=zeros,
        accelerations=zeros,
        primitives=["S_R E_P W_P"] * (n - 1) + ["E_R W_P"],
        wrist_path=[(0.1, -0.1, 0.0)] * n,
    )


def test_a_trajectory_gives_one_timed_pose_per_sample() -> None:
    """Planned transforms at arrival + (t - t0); planned primitive labels too."""
    traj = trajectory()
    derived = list(FoxgloveChannels().derive(traj, T0))
    poses = [d for d in derived if d.topic == PLANNED_TF_TOPIC]
    labels = [d for d in derived if d.topic == PLANNED_PRIMITIVE_TOPIC]
    assert [d.log_time for d in poses] == [T0 + i * 10_000_000 for i in range(5)]
    arm = load_arm(Side.RIGHT)
    for d, row in zip(poses, traj.positions, strict=True):
        assert d.schema_name == FRAME_TRANSFORMS_SCHEMA_NAME
        message = json.loads(d.data)
        assert message["transforms"][0]["timestamp"] == {
            "sec": d.log_time // 10**9,
            "nsec": d.log_time % 10**9,
        }
        wrist = chain_poses(message)["r_wrist"][1]
        assert np.abs(wrist - arm.fk(np.array(row)).wrist).max() < TOL
    last = PrimitiveSample.model_validate_json(labels[-1].data)
    assert (last.primitive, last.index) == ("E_R W_P", 1)
    assert json.loads(labels[-1].data)["arm"] == "right"


def test_streamed_transforms_are_the_models_json_byte_for_byte(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Made without models, each message is frame_transforms(...).to_json() to
    the byte: signed zeros, right angles, the limits, any frame prefix."""
    limits = arm.limits
    postures = np.vstack(
        [
            np.zeros(5),
            -np.zeros(5),
            np.full(5, np.pi / 2),
            np.full(5, -np.pi / 2),
            np.full(5, 1e-300),
            limits.lower,
            limits.upper,
            rng.uniform(-np.pi, np.pi, (200, 5)),
        ]
    )
    stamps = [T0 + 7_777_777 * k for k in range(len(postures))]
    for prefix in ("", "executed/", 'plan "\u00e9"\\/'):
        streamed = transforms_json(link_poses(arm, postures), stamps, prefix)
        models = [
            frame_transforms(arm, q, stamp, prefix).to_json().encode()
            for q, stamp in zip(postures, stamps, strict=True)
        ]
        assert list(streamed) == models, prefix


def test_derive_refuses_before_making_a_message() -> None:
    """A missing joint, or times past MCAP's range, raise at the call: a
    recorder writes a message's derived messages whole or not at all."""
    traj = trajectory()
    names = [*traj.joint_names[:4], "RHand"]
    lacking = Trajectory.model_validate(traj.model_dump() | {"joint_names": names})
    with pytest.raises(KeyError, match="RWristYaw"):
        FoxgloveChannels().derive(lacking, T0)
    late = MAX_TIME - 25_000_000  # samples 10 ms apart: the fourth passes 2^64 ns
    with pytest.raises(ValueError, match=r"MCAP's range .*: sample 3 falls at"):
        FoxgloveChannels().derive(traj, late)


def test_a_long_trajectory_is_derived_one_message_at_a_time() -> None:
    """Deriving 5000 samples and taking all 10 000 messages peaks under three
    times the trajectory's JSON size (the link poses, then one message at a
    time); a list of 5000 FrameTransforms models took 43 times it."""
    traj = moving_trajectory(5000, np.random.default_rng(7))
    size = len(traj.to_json().encode())
    channels = FoxgloveChannels()
    list(channels.derive(trajectory(), T0))  # the arm model and schemas, once
    tracemalloc.start()
    try:
        count = sum(1 for _ in channels.derive(traj, T0))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert count == 10_000
    assert peak < 3 * size, f"peak {peak / size:.1f} times the trajectory's JSON"


def test_a_joint_state_gives_the_executed_pose() -> None:
    """Named angles in any order, extra joints ignored, frames prefixed."""
    side = Side.LEFT
    names = [*reversed(side.joint_names), "LHand"]
    q = [0.3, -0.2, 0.4, 0.1, -0.5]
    state = JointState(time=0.1, joint_names=names, positions=[*reversed(q), 0.7])
    (derived,) = FoxgloveChannels().derive(state, T0)
    assert derived.topic == EXECUTED_TF_TOPIC
    poses = chain_poses(json.loads(derived.data))
    hand = load_arm(side).fk(np.array(q)).hand
    assert np.abs(poses["executed/l_gripper"][1] - hand).max() < TOL


def test_frames_give_the_commanded_pose_from_their_arrival() -> None:
    """Frame 0 (the start) at arrival, frame k at arrival + k / rate; joints in
    any order, the hand ignored, frames prefixed ``commanded/``."""
    side = Side.LEFT
    rng = np.random.default_rng(3)
    arm = load_arm(side)
    rows = [random_posture(arm, rng) for _ in range(4)]
    order = [4, 2, 0, 3, 1]
    names = [side.joint_names[i] for i in order] + ["LHand"]
    frames = CommandFrames(
        arm=side,
        rate=25.0,
        joint_names=names,
        start=[*rows[0][order], 0.5],
        times=[0.04, 0.08, 0.12],
        positions=[[*row[order], 0.5] for row in rows[1:]],
    )
    derived = list(FoxgloveChannels().derive(frames, T0))
    assert [d.topic for d in derived] == [COMMANDED_TF_TOPIC] * 4
    assert [d.log_time for d in derived] == [T0 + k * 40_000_000 for k in range(4)]
    for d, q in zip(derived, rows, strict=True):
        hand = chain_poses(json.loads(d.data))["commanded/l_gripper"][1]
        assert np.abs(hand - arm.fk(q).hand).max() < TOL


def test_a_state_without_an_arm_gives_nothing() -> None:
    """Head joints only: no executed pose."""
    state = JointState(time=0.0, joint_names=["HeadYaw"], positions=[0.1])
    assert list(FoxgloveChannels().derive(state, T0)) == []


def test_a_decision_gives_a_plottable_sample_per_point() -> None:
    """Index in Table 1's order and every g, under plot-friendly keys."""
    name = PRIMITIVE_NAMES[3]
    point = PointDecision(
        primitive=name,
        matrix=BY_NAME[name].matrix,
        g={name: 0.25, "W_R": 0.125},
    )
    decision = Decision.of_points(Side.RIGHT, [0.0, 0.02], [point, point])
    derived = list(FoxgloveChannels().derive(decision, T0))
    assert [d.topic for d in derived] == [DECISION_TOPIC] * 2
    assert derived[1].log_time == T0 + 20_000_000
    sample = PrimitiveSample.model_validate_json(derived[1].data)
    assert sample.index == 3
    assert sample.g == {name.replace(" ", "_"): 0.25, "W_R": 0.125}


@pytest.mark.parametrize("side", [Side.LEFT, Side.RIGHT])
def test_each_primitive_sample_names_its_arm(side: Side) -> None:
    """A decision's and a trajectory's samples carry the arm ("left" or
    "right"), and the channel's JSON schema lists it as required: a session
    planning both arms mixes them on one channel (they had no arm)."""
    name = PRIMITIVE_NAMES[0]
    point = PointDecision(primitive=name, matrix=BY_NAME[name].matrix, g={name: 0.5})
    decision = Decision.of_points(side, [0.0, 0.01], [point] * 2)
    channels = FoxgloveChannels()
    derived = list(channels.derive(decision, T0))
    derived += list(channels.derive(trajectory(side), T0))
    primitive = [d for d in derived if d.schema_name == "PrimitiveSample"]
    assert {d.topic for d in primitive} == {DECISION_TOPIC, PLANNED_PRIMITIVE_TOPIC}
    assert {json.loads(d.data)["arm"] for d in primitive} == {side.value}
    assert "arm" in primitive[0].schema["required"]


def test_a_decision_is_placed_when_the_trajectory_passes_its_points() -> None:
    """With ``trajectory_times`` a point falls at arrival plus its time there,
    not at its own time on the path's clock; the JSON of a decision recorded
    before the field existed (no key) still parses and is placed by its own
    times, as it was."""
    name = PRIMITIVE_NAMES[2]
    point = PointDecision(primitive=name, matrix=BY_NAME[name].matrix, g={name: 0.5})
    decision = Decision.of_points(Side.RIGHT, [0.0, 0.01, 0.02], [point] * 3)
    assert "trajectory_times" not in decision.to_json()  # as before the field
    timed = decision.model_validate(
        {**decision.model_dump(), "trajectory_times": [1.25, 1.5, 1.5]}
    )
    stamps = [d.log_time for d in FoxgloveChannels().derive(timed, T0)]
    assert stamps == [T0 + 1_250_000_000, T0 + 1_500_000_000, T0 + 1_500_000_000]
    old = Decision.model_validate_json(decision.to_json())
    stamps = [d.log_time for d in FoxgloveChannels().derive(old, T0)]
    assert stamps == [T0, T0 + 10_000_000, T0 + 20_000_000]


def test_the_robot_description_is_the_project_urdf() -> None:
    """/robot_description carries the URDF text in a ``data`` field."""
    d = description_message(T0)
    assert d.topic == "/robot_description"
    assert RobotDescription.model_validate_json(d.data).data == urdf_text()
