"""The recorder's algorithm without Zenoh: routing of payloads and the writer.

Samples are fed to a RecordingSink as Zenoh would; the file must hold them
in order on the right channels, flushed while the sink is still running.
"""

from __future__ import annotations

import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from conftest import moving_trajectory
from mcap.reader import make_reader

from services.planner.pipeline import plan
from services.recorder.options import RecorderOptions
from services.recorder.routing import Incoming, relative_path, route
from services.recorder.sink import RecordingSink
from shared.errors import InvalidInputError
from shared.messages import (
    Decision,
    JointState,
    Message,
    PlanRequest,
    ReachTarget,
    Trajectory,
)
from shared.recording import read_records
from shared.recording.foxglove import (
    DECISION_TOPIC,
    EXECUTED_TF_TOPIC,
    PLANNED_PRIMITIVE_TOPIC,
    PLANNED_TF_TOPIC,
    PRIMITIVE_NAMES,
    PrimitiveSample,
)
from shared.recording.foxglove.transforms import (
    arm_angles,
    frame_transforms,
    side_of_state,
)
from shared.recording.raw_payload import ZENOH_ENCODING, RawPayload
from shared.recording.rotation import RotationPolicy, numbered_parts
from shared.robot import load_arm

NS = "armplan"
REQUEST = PlanRequest(targets=[ReachTarget(position=(0.1, -0.1, 0.0))])


def incoming(key: str, payload: bytes, t: int = 1, encoding: str = "x") -> Incoming:
    return Incoming(f"{NS}/{key}", payload, encoding, t, t + 1)


@pytest.mark.parametrize(
    ("key", "payload", "schema"),
    [
        ("plan/request", REQUEST.to_json().encode(), "PlanRequest"),
        ("plan/request", b'{"targets": []}', "json"),  # fails PlanRequest
        ("plan/request", b'{"targets": [], "extra": 1}', "json"),
        ("unknown/key", b'{"a": 1}', "json"),
        ("fit/model/update", b'{"version": 1}', "json"),  # class not in shared/ yet
        ("plan/request", b"[1, 2]", "RawPayload"),
        ("plan/request", b"\xff\xfe binary", "RawPayload"),
        ("plan/request", b"", "RawPayload"),
        ("plan/request", b"[" * 100_000, "RawPayload"),  # deep nesting
        ("unknown/key", '{"a": 1}'.encode("utf-16"), "RawPayload"),  # not UTF-8
        ("unknown/key", b'\xef\xbb\xbf{"a": 1}', "RawPayload"),  # a BOM
    ],
)
def test_each_payload_gets_the_most_specific_channel(
    key: str, payload: bytes, schema: str
) -> None:
    """Typed if it parses as the topic's class, json if an object, else raw."""
    entry = route(incoming(key, payload), NS)
    assert entry.topic == f"{NS}/{key}"
    assert entry.schema_name == schema
    if schema == "RawPayload":
        raw = RawPayload.model_validate_json(entry.data)
        assert raw.payload() == payload
        assert raw.encoding == "x"
    else:
        assert entry.data == payload
    assert (entry.message is not None) == (schema == "PlanRequest")


def test_keys_outside_the_namespace_are_untyped() -> None:
    """Only keys under the namespace are looked up in the topic registry."""
    assert relative_path("armplan/plan/request", NS) == "plan/request"
    assert relative_path("other/plan/request", NS) is None
    entry = route(
        Incoming("other/plan/request", REQUEST.to_json().encode(), "", 1, 1), NS
    )
    assert entry.schema_name == "json"


def test_the_sink_writes_in_order_and_flushes_while_running(tmp_path: Path) -> None:
    """Records in arrival order, readable (with recover) before the sink stops."""
    out = tmp_path / "sink.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
    try:
        for i in range(50):
            sink.put(incoming("misc/i", b'{"i": %d}' % i, t=i))
        time.sleep(0.5)  # > flush_every: on disk although the sink runs on
        live = [
            r.data["i"]
            for r in read_records(out, recover=True)
            if r.topic.endswith("/i")
        ]
        assert live == list(range(50))
    finally:
        paths = sink.stop()
    assert paths == [out]
    records = list(read_records(out))  # closed: whole, no recover needed
    assert [r.data["i"] for r in records if r.topic.endswith("/i")] == list(range(50))
    assert [r.log_time for r in records if r.topic.endswith("/i")] == list(range(50))
    assert sink.written == sink.received == 50
    assert sink.failed == 0


def test_a_writer_still_busy_at_the_stop_is_an_error_not_a_whole_file(
    tmp_path: Path,
) -> None:
    """A backlog the writer could not write out in time left the file without
    its summary, yet the recording was reported whole (exit code 0): the
    sink's ``error`` now says so, naming the file."""
    out = tmp_path / "busy.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
    for i in range(5000):
        sink.put(incoming("misc/i", b'{"i": %d}' % i, t=i))
    sink.stop(timeout=0.0)
    try:
        assert sink.error is not None and sink.broken.is_set()
        assert "still busy 0 s after the stop" in sink.error.message
        assert sink.error.path == str(out)
    finally:
        sink.stop()  # the writer ends on its own; the file is then closed


def test_without_foxglove_only_the_samples_are_written(tmp_path: Path) -> None:
    """--no-foxglove: no robot description, no derived channels."""
    out = tmp_path / "plain.mcap"
    options = RecorderOptions(output=out, keys=("**",), foxglove=False)
    sink = RecordingSink(options, NS).start()
    sink.put(incoming("plan/request", REQUEST.to_json().encode()))
    sink.stop()
    assert [r.topic for r in read_records(out)] == [f"{NS}/plan/request"]


def test_each_json_channel_notes_the_zenoh_encoding_of_its_payloads(
    tmp_path: Path,
) -> None:
    """The encoding of a JSON object was lost (a replay sent every one as
    application/json): a channel per topic, schema and encoding now, with
    the encoding in its metadata; a RawPayload channel carries none."""
    out = tmp_path / "s.mcap"
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
    for payload, encoding in [
        (REQUEST.to_json().encode(), "application/json"),
        (b'{"targets": []}', "application/json"),
        (REQUEST.to_json().encode(), "zenoh/bytes"),
        (REQUEST.to_json().encode(), "application/json"),
        (b"\xff", "zenoh/bytes"),
    ]:
        sink.put(incoming("plan/request", payload, encoding=encoding))
    sink.stop()
    with out.open("rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    schemas = {k: s.name for k, s in summary.schemas.items()}
    channels = sorted(
        (schemas[c.schema_id], c.metadata.get(ZENOH_ENCODING, "-"))
        for c in summary.channels.values()
        if c.topic == f"{NS}/plan/request"
    )
    assert channels == [
        ("PlanRequest", "application/json"),
        ("PlanRequest", "zenoh/bytes"),
        ("RawPayload", "-"),
        ("json", "application/json"),
    ]


def test_a_bad_flush_period_is_refused(tmp_path: Path) -> None:
    """flush_every must be in (0, 10] s."""
    with pytest.raises(InvalidInputError, match="flush_every must be in"):
        RecorderOptions(output=tmp_path / "x.mcap", flush_every=0.0)


def model_messages(
    message: Message, start: int, planned: str, executed: str
) -> list[tuple[str, int, bytes]]:
    """(topic, log time [ns], JSON) of each message the recorder derived from
    ``message`` before it streamed them: a pydantic model per message."""
    if isinstance(message, JointState):
        side = side_of_state(message)
        assert side is not None
        q = arm_angles(side, message.joint_names, message.positions)
        pose = frame_transforms(load_arm(side), q, start, executed)
        return [(EXECUTED_TF_TOPIC, start, pose.to_json().encode())]
    assert isinstance(message, Decision | Trajectory)
    stamps = [start + round((t - message.times[0]) * 10**9) for t in message.times]
    if isinstance(message, Decision):  # when the trajectory passes each point
        assert message.trajectory_times is not None
        stamps = [start + round(t * 10**9) for t in message.trajectory_times]
    labels = [
        PrimitiveSample(
            arm=message.arm,
            time=t,
            primitive=name,
            index=PRIMITIVE_NAMES.index(name),
        )
        for t, name in zip(message.times, message.primitives, strict=True)
    ]
    if isinstance(message, Decision):
        keys = [name.replace(" ", "_") for name in message.candidates]
        labels = [
            label.model_copy(update={"g": dict(zip(keys, row, strict=True))})
            for label, row in zip(labels, message.g, strict=True)
        ]
        return [
            (DECISION_TOPIC, stamp, label.to_json().encode())
            for stamp, label in zip(stamps, labels, strict=True)
        ]
    arm = load_arm(message.arm)
    poses = [
        frame_transforms(
            arm, arm_angles(arm.side, message.joint_names, row), stamp, planned
        )
        for stamp, row in zip(stamps, message.positions, strict=True)
    ]
    return [
        (PLANNED_TF_TOPIC, stamp, pose.to_json().encode())
        for stamp, pose in zip(stamps, poses, strict=True)
    ] + [
        (PLANNED_PRIMITIVE_TOPIC, stamp, label.to_json().encode())
        for stamp, label in zip(stamps, labels, strict=True)
    ]


def test_derived_messages_are_recorded_as_the_models_made_them(
    tmp_path: Path,
) -> None:
    """Read back from the file, the derived channels of a planned reach (its
    trajectory, decisions and a measured state, as the planner publishes
    them) hold, in order and byte for byte, what a pydantic model per
    message made before they were streamed."""
    result = plan(
        PlanRequest(
            arm="left",
            targets=[
                ReachTarget(position=(0.12, 0.12, 0.05)),
                ReachTarget(position=(0.13, 0.08, 0.15)),
            ],
        )
    )
    traj = result.trajectory
    state = JointState(
        time=0.4, joint_names=traj.joint_names, positions=traj.positions[40]
    )
    samples: list[tuple[str, Message]] = [
        ("plan/trajectory", traj),
        *(("plan/decision", d) for d in result.decisions),
        ("bridge/state", state),
    ]
    planned, executed = "plan/", 'ex "\u00e9"/'
    out = tmp_path / "reach.mcap"
    options = RecorderOptions(
        output=out, keys=("**",), planned_prefix=planned, executed_prefix=executed
    )
    sink = RecordingSink(options, NS).start()
    start = 1_700_000_000_123_456_789
    for i, (key, message) in enumerate(samples):
        sink.put(incoming(key, message.to_json().encode(), t=start + i))
    sink.stop()
    expected = [
        m
        for i, (_, message) in enumerate(samples)
        for m in model_messages(message, start + i, planned, executed)
    ]
    derived = [
        (r.topic, r.log_time, r.raw)
        for r in read_records(out)
        if r.topic.startswith("/") and r.topic != "/robot_description"
    ]
    assert len(expected) == 2 * len(traj.times) + 1 + sum(
        len(d.times) for d in result.decisions
    )
    assert derived == expected


def test_a_long_trajectory_is_written_as_it_is_derived(tmp_path: Path) -> None:
    """Recording a 5000-sample trajectory (10 000 derived messages) peaks under
    six times its JSON size, most of it parsing the sample; its derived
    messages made in full before the first was written took 45 times it."""
    payload = moving_trajectory(5000, np.random.default_rng(7)).to_json().encode()
    out = tmp_path / "long.mcap"
    tracemalloc.start()
    try:
        sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS).start()
        sink.put(incoming("plan/trajectory", payload, t=1_700_000_000_000_000_000))
        sink.stop()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert sink.error is None and sink.written == 1
    assert sink.derived == 1 + 10_000  # the robot description, poses, labels
    assert peak < 6 * len(payload), f"peak {peak / len(payload):.1f} times the JSON"


def test_a_writer_far_behind_drops_new_samples_and_says_how_many(
    tmp_path: Path,
) -> None:
    """Samples arriving while ``max_backlog`` bytes wait are dropped and
    counted (memory stays bounded); those queued before are all written."""
    out = tmp_path / "behind.mcap"
    options = RecorderOptions(output=out, keys=("**",), foxglove=False)
    sink = RecordingSink(options, NS, max_backlog=1000)
    payloads = [b'{"i": %d, "pad": "%s"}' % (i, b"x" * 280) for i in range(10)]
    for i, payload in enumerate(payloads):  # the writer has not started yet
        sink.put(incoming("misc/i", payload, t=i))
    sink.start().stop()
    kept = [r.data["i"] for r in read_records(out)]
    assert kept == [0, 1, 2, 3]  # queued while under 1000 bytes waited
    assert (sink.received, sink.written, sink.dropped) == (10, 4, 6)
    assert sink.behind_note() == "; the writer fell behind: 6 samples dropped"


def test_a_writer_behind_writes_samples_without_their_foxglove_poses(
    tmp_path: Path,
) -> None:
    """While more than ``shed_backlog`` bytes wait, trajectories are written
    without their derived messages; once caught up, with them."""
    out = tmp_path / "shed.mcap"
    rng = np.random.default_rng(3)
    trajectories = [moving_trajectory(50, rng) for _ in range(3)]
    sink = RecordingSink(RecorderOptions(output=out, keys=("**",)), NS, shed_backlog=0)
    for k, trajectory in enumerate(trajectories):
        sink.put(incoming("plan/trajectory", trajectory.to_json().encode(), t=k + 1))
    sink.start().stop()
    records = list(read_records(out))
    assert sum(r.topic == f"{NS}/plan/trajectory" for r in records) == 3
    assert sum(r.topic == PLANNED_TF_TOPIC for r in records) == 50  # the last one's
    assert (sink.written, sink.shed, sink.dropped) == (3, 2, 0)
    assert "2 written without Foxglove poses" in sink.behind_note()


def test_what_a_sample_derives_stays_in_its_file_when_it_rotates(
    tmp_path: Path,
) -> None:
    """A trajectory bigger than the rotation size: its poses and labels are in
    its own part, and the next sample starts the next part."""
    out = tmp_path / "s.mcap"
    traj = moving_trajectory(300, np.random.default_rng(3))
    options = RecorderOptions(
        output=out, keys=("**",), rotation=RotationPolicy(max_bytes=20_000)
    )
    sink = RecordingSink(options, NS).start()
    sink.put(incoming("plan/trajectory", traj.to_json().encode(), t=10**18))
    sink.put(incoming("unknown/key", b'{"a": 1}', t=10**18 + 1))
    sink.stop()
    parts = numbered_parts(out)
    assert sink.error is None and len(parts) == 2
    first = [r.topic for r in read_records(parts[0])]
    assert first.count(PLANNED_TF_TOPIC) == len(traj.times)
    assert first.count(PLANNED_PRIMITIVE_TOPIC) == len(traj.times)
    second = [r.topic for r in read_records(parts[1])]
    assert f"{NS}/unknown/key" in second and PLANNED_TF_TOPIC not in second
