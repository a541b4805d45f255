"""The recorder as a real process on a real Zenoh router, writing real MCAP files.

A publisher session sends a session's worth of messages (every registered
topic, plus unknown keys, malformed and binary payloads); the file must hold
every one, byte for byte, in order, each valid against its channel's schema,
with the derived Foxglove channels beside them.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
import zenoh
from frame_chain import chain_poses
from mcap.reader import make_reader
from record_cli import record_command, start_recording

from armplan.launch import free_endpoint
from services.recorder import RecorderOptions, RecorderProcess
from services.recorder.control import recorder_command
from services.recorder.replay import replay_items
from services.recorder.service import Recorder
from shared.bus import Bus, BusConfig, open_router
from shared.bus.topics import topic_paths
from shared.errors import InvalidInputError, RecordingError
from shared.messages import (
    CommandFrames,
    Decision,
    JointPath,
    JointState,
    Message,
    PlanRequest,
    PointDecision,
    ReachTarget,
    TrackingReport,
    Trajectory,
)
from shared.primitives import BY_NAME
from shared.recording import read_records
from shared.recording.foxglove import (
    DECISION_TOPIC,
    EXECUTED_TF_TOPIC,
    PLANNED_TF_TOPIC,
    ROBOT_DESCRIPTION_TOPIC,
)
from shared.recording.metadata import read_metadata
from shared.recording.rotation import RotationPolicy
from shared.recording.validation import check_record
from shared.robot import Side, load_arm

NAMESPACE = "rectest"
JOINTS = list(Side.RIGHT.joint_names)
#: Longest wait for samples to reach the recorder after the last put [s].
SETTLE = 0.5


@pytest.fixture(scope="module")
def config() -> Iterator[BusConfig]:
    """A router on a free loopback port."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace=NAMESPACE)
    with open_router(config):
        yield config


def trajectory(n: int = 20) -> Trajectory:
    rows = [[0.02 * i, -0.1, 0.3, 0.4 + 0.01 * i, 0.0] for i in range(n)]
    zeros = [[0.0] * 5 for _ in range(n)]
    return Trajectory(
        arm=Side.RIGHT,
        joint_names=JOINTS,
        times=[0.01 * i for i in range(n)],
        positions=rows,
        velocities=zeros,
        accelerations=zeros,
        primitives=["S_R E_P W_P"] * n,
        wrist_path=[(0.1, -0.1, 0.0)] * n,
    )


def session_messages() -> list[tuple[str, Message]]:
    """What a planning session publishes, stage by stage."""
    traj = trajectory()
    point = PointDecision(
        primitive="S_R E_P W_P",
        matrix=BY_NAME["S_R E_P W_P"].matrix,
        g={"S_R E_P W_P": 0.5, "E_R W_P": 0.25},
    )
    states = [
        JointState(time=0.01 * i, joint_names=JOINTS, positions=traj.positions[i])
        for i in range(len(traj.times))
    ]
    return [
        ("plan/request", PlanRequest(targets=[ReachTarget(position=(0.15, -0.1, 0))])),
        (
            "plan/decision",
            Decision.of_points(Side.RIGHT, [0.0, 0.1], [point] * 2),
        ),
        (
            "plan/joint_path",
            JointPath(
                arm=Side.RIGHT,
                joint_names=JOINTS,
                times=traj.times,
                positions=traj.positions,
                primitives=traj.primitives,
                wrist=traj.wrist_path,
            ),
        ),
        ("plan/trajectory", traj),
        (
            "bridge/frames",
            CommandFrames(
                arm=Side.RIGHT,
                rate=25.0,
                joint_names=JOINTS,
                start=traj.positions[0],
                times=[0.04, 0.08],
                positions=traj.positions[1:3],
            ),
        ),
        *(("bridge/state", s) for s in states),
        (
            "bridge/report",
            TrackingReport(
                joint_names=JOINTS,
                tracking_rms_deg=dict.fromkeys(JOINTS, 0.1),
                tracking_max_deg=dict.fromkeys(JOINTS, 0.3),
                samples=len(states),
                sample_period=0.01,
                duration=0.19,
            ),
        ),
    ]


def session_payloads() -> list[tuple[str, bytes]]:
    """(relative key, payload) of a session, odd payloads included."""
    out = [(path, m.to_json().encode()) for path, m in session_messages()]
    out += [
        ("fit/model/update", b'{"version": 1, "variables": {"S_R": 2.5}}'),
        ("plan/trajectory", b'{"arm": "right", "times": "not a list"}'),  # bad
        ("bridge/state", b"\x00\x01\x02 binary \xff"),
        ("plan/request", b"[1, 2, 3]"),
        ("misc/note", b'{"text": "an unregistered key"}'),
    ]
    return out * 3


def publish_all(config: BusConfig, payloads: list[tuple[str, bytes]]) -> None:
    """Put ``payloads`` from a new session once it knows the recorder's
    subscriber (a put before the router's declarations reach a new session
    goes nowhere: once 0 of 20 messages were recorded)."""
    with Bus.connect(config) as bus:
        publishers = {
            path: bus.session.declare_publisher(
                bus.key(path), congestion_control=zenoh.CongestionControl.BLOCK
            )
            for path, _ in payloads
        }
        deadline = time.monotonic() + 5.0
        while not any(p.matching_status.matching for p in publishers.values()):
            assert time.monotonic() < deadline, "no subscriber for any key"
            time.sleep(0.01)
        for path, payload in payloads:
            publishers[path].put(payload)
        time.sleep(SETTLE)
        for publisher in publishers.values():
            publisher.undeclare()


def recorded(path: Path) -> list[tuple[str, bytes]]:
    """(relative key, original payload) of every recorded Zenoh message."""
    return [(item.path, item.payload) for item in replay_items(path)]


def test_every_message_is_recorded_in_order_byte_for_byte(
    config: BusConfig, tmp_path: Path
) -> None:
    """Every published payload, in order; the file closes with its summary."""
    payloads = session_payloads()
    out = tmp_path / "session.mcap"
    keys = [*topic_paths(), "misc/**"]
    with RecorderProcess.start(config, out, keys=keys) as recorder:
        publish_all(config, payloads)
    assert recorder.process.returncode == 0
    assert recorded(out) == payloads
    with out.open("rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None  # closed cleanly: summary written
    meta = read_metadata(out)["armplan"]
    assert meta["namespace"] == NAMESPACE
    assert meta["keys"] == ",".join(keys)


def test_channels_validate_and_foxglove_channels_are_derived(
    config: BusConfig, tmp_path: Path
) -> None:
    """Each record parses as its schema's model; typed, json and raw channels."""
    out = tmp_path / "session.mcap"
    log = tmp_path / "recorder.log"
    with (
        log.open("w") as sink,
        RecorderProcess.start(config, out, keys=[*topic_paths(), "misc/**"], log=sink),
    ):
        publish_all(config, session_payloads()[: len(session_payloads()) // 3])
    records = list(read_records(out))
    problems = [p for r in records if (p := check_record(r)) is not None]
    assert problems == []
    derived = sum(1 for r in records if r.topic.startswith("/"))
    bus = len(records) - derived  # the log says which is which (it said neither)
    assert (
        f"recorder stopped: {bus} messages from the bus (and {derived} derived "
        f"for Foxglove) in {out}"
    ) in log.read_text()
    channels = {(r.topic, r.schema) for r in records}
    key = f"{NAMESPACE}/".__add__
    assert (key("plan/trajectory"), "Trajectory") in channels
    assert (key("plan/trajectory"), "json") in channels  # the malformed one
    assert (key("bridge/state"), "RawPayload") in channels
    assert (key("fit/model/update"), "json") in channels
    assert (key("misc/note"), "json") in channels
    counts: dict[str, int] = {}
    for r in records:
        counts[r.topic] = counts.get(r.topic, 0) + 1
    n = len(trajectory().times)
    assert counts[ROBOT_DESCRIPTION_TOPIC] == 1
    assert counts[PLANNED_TF_TOPIC] == n
    assert counts[EXECUTED_TF_TOPIC] == n
    assert counts[DECISION_TOPIC] == 2
    arm = load_arm(Side.RIGHT)
    planned = [r for r in records if r.topic == PLANNED_TF_TOPIC]
    for r, row in zip(planned, trajectory().positions, strict=True):
        hand = arm.fk(np.array(row)).hand
        assert np.abs(chain_poses(r.data)["r_gripper"][1] - hand).max() < 1e-9


def test_a_recorder_process_names_the_frames_with_the_prefixes_it_is_given(
    config: BusConfig, tmp_path: Path
) -> None:
    """The frame prefixes of RecorderOptions reach the recorder's process (its
    command line dropped them: the defaults were used whatever was asked)."""
    out = tmp_path / "session.mcap"
    options = RecorderOptions(
        planned_prefix="p/", executed_prefix="e/", commanded_prefix="c/"
    )
    with RecorderProcess.start(config, out, keys=topic_paths(), options=options):
        publish_all(config, [(k, m.to_json().encode()) for k, m in session_messages()])
    children = {
        r.topic: {t["child_frame_id"] for t in r.data["transforms"]}
        for r in read_records(out, topics=[PLANNED_TF_TOPIC, EXECUTED_TF_TOPIC])
    }
    assert "p/r_gripper" in children[PLANNED_TF_TOPIC]
    assert "e/r_gripper" in children[EXECUTED_TF_TOPIC]
    assert "--commanded-prefix=c/" in recorder_command(config, options)


#: JSON objects a json channel may not hold (its readers take UTF-8 only),
#: then one it may: an escaped surrogate is UTF-8 JSON text.
NOT_UTF8_JSON = [
    ("misc/note", '{"hello": "utf16"}'.encode("utf-16")),
    ("misc/note", '{"hello": "utf16"}'.encode("utf-16-le")),  # no BOM either
    ("misc/note", '{"hello": "utf32"}'.encode("utf-32")),
    ("plan/request", b'\xef\xbb\xbf{"hello": "bom"}'),
    ("misc/note", b'{"x": "\xed\xa0\x80"}'),  # an encoded surrogate
    ("misc/note", b'{"x": "\\ud800"}'),
]


def test_only_utf8_json_goes_to_json_channels(
    config: BusConfig, tmp_path: Path
) -> None:
    """JSON in UTF-16 or UTF-32, with a byte order mark, or with an encoded
    surrogate is kept as a RawPayload (UTF-16 was stored on the json channel
    as is, which Foxglove cannot read), and replays byte for byte."""
    out = tmp_path / "odd.mcap"
    with RecorderProcess.start(config, out, keys=["plan/request", "misc/**"]):
        publish_all(config, NOT_UTF8_JSON)
    records = [r for r in read_records(out) if not r.topic.startswith("/")]
    assert [r.schema for r in records] == ["RawPayload"] * 5 + ["json"]
    assert [check_record(r) for r in records] == [None] * 6
    assert recorded(out) == NOT_UTF8_JSON


def test_log_time_is_the_zenoh_timestamp_and_publish_time_the_receipt(
    config: BusConfig, tmp_path: Path
) -> None:
    """Log times come from the router's timestamps, close to the receipt times."""
    out = tmp_path / "times.mcap"
    before = time.time_ns()
    with RecorderProcess.start(config, out, keys=["plan/request"]):
        publish_all(config, session_payloads()[:1] * 20)
    after = time.time_ns()
    records = [r for r in read_records(out) if not r.topic.startswith("/")]
    assert len(records) == 20
    for r in records:
        assert before <= r.log_time <= r.publish_time + 1_000_000
        assert r.publish_time <= after
        assert r.log_time != r.publish_time  # a Zenoh timestamp, not the receipt
        assert r.publish_time - r.log_time < 500_000_000
    logs = [r.log_time for r in records]
    assert logs == sorted(logs)


def test_in_process_recorder_announces_itself_after_subscribing(
    config: BusConfig, tmp_path: Path
) -> None:
    """The liveliness token 'recorder' appears with the recorder and goes with it."""
    out = tmp_path / "inproc.mcap"
    with Bus.connect(config) as bus:
        with Recorder(bus, RecorderOptions(output=out, keys=("misc/*",))):
            with Bus.connect(config) as client:
                assert client.wait_alive(["recorder"], 5.0) == []
            publish_all(config, [("misc/a", b'{"a":1}'), ("misc/b", b'{"b":2}')])
        with Bus.connect(config) as client:
            deadline = time.monotonic() + 5.0
            while "recorder" in client.alive() and time.monotonic() < deadline:
                time.sleep(0.05)
            assert "recorder" not in client.alive()
    assert recorded(out) == [("misc/a", b'{"a":1}'), ("misc/b", b'{"b":2}')]


def test_overlapping_key_expressions_record_each_message_once(
    config: BusConfig, tmp_path: Path
) -> None:
    """misc/** and misc/a both match misc/a: one copy in the file."""
    out = tmp_path / "overlap.mcap"
    options = RecorderOptions(output=out, keys=("misc/**", "misc/a"))
    with Bus.connect(config) as bus, Recorder(bus, options):
        publish_all(config, [("misc/a", b'{"a":1}')] * 3)
    assert recorded(out) == [("misc/a", b'{"a":1}')] * 3


def test_rotation_by_size_splits_a_live_session(
    config: BusConfig, tmp_path: Path
) -> None:
    """With --rotate-size, numbered files, each whole, together every message."""
    out = tmp_path / "rot.mcap"
    options = RecorderOptions(rotation=RotationPolicy(max_bytes=20_000))
    payloads = session_payloads()
    with RecorderProcess.start(config, out, options=options) as recorder:
        publish_all(config, payloads)
    paths = recorder.paths
    assert len(paths) > 1
    assert [p.name for p in paths][:2] == ["rot-0001.mcap", "rot-0002.mcap"]
    items = replay_items(paths)  # the parts together, offsets running on
    registered = set(topic_paths())
    assert [(i.path, i.payload) for i in items] == [
        (k, v) for k, v in payloads if k in registered
    ]
    offsets = [i.offset for i in items]
    assert offsets[0] == 0.0
    assert offsets == sorted(offsets)
    for p in paths:
        topics = [r.topic for r in read_records(p)]  # whole: no recover needed
        assert topics[0] == ROBOT_DESCRIPTION_TOPIC


def test_bad_keys_and_unwritable_files_are_clear_errors(
    config: BusConfig, tmp_path: Path
) -> None:
    """An invalid key expression or output folder: typed error, exit code 1."""
    bad = RecorderOptions(output=tmp_path / "x.mcap", keys=("a//b",))
    with (
        Bus.connect(config) as bus,
        pytest.raises(InvalidInputError, match="not a Zenoh key expression"),
    ):
        Recorder(bus, bad)
    with pytest.raises(RecordingError, match="did not start"):
        RecorderProcess.start(config, tmp_path / "missing" / "x.mcap", timeout=20)
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "services.recorder",
            "-o",
            str(tmp_path / "missing" / "x.mcap"),
            "--connect",
            config.endpoint,
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert out.returncode == 1
    assert "cannot create" in out.stderr
    assert "Traceback" not in out.stderr


def test_armplan_record_cli_records_for_a_duration(
    config: BusConfig, tmp_path: Path
) -> None:
    """`armplan record --duration` records, closes and reports the counts."""
    out = tmp_path / "cli.mcap"
    process = start_recording(record_command(config, out, "--duration", "4"))
    try:
        publish_all(
            config, [("misc/x", json.dumps({"i": i}).encode()) for i in range(5)]
        )
        stdout, stderr = process.communicate(timeout=60)
    finally:
        process.kill()
        process.wait(30)
    assert process.returncode == 0, stderr
    assert "armplan record: 5 messages (and 1 derived for Foxglove) in" in stdout
    assert len(recorded(out)) == 5
    # the two counts add up to what `armplan inspect` finds in the file (it
    # once said 5 where inspect said 6: the robot description)
    from shared.recording.inventory import take_inventory

    assert take_inventory(out).count == 6
