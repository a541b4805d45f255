"""Choregraphe behavior files: the keys read back are the trajectory's angles."""

from __future__ import annotations

import re
import threading
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import pytest
from logged_motion import logged_peaks

from bridge.bezier_auto import auto_handles
from bridge.choregraphe import (
    NAMESPACE,
    behavior_xml,
    read_behavior,
    timeline_fps,
    timeline_from_xml,
    write_behavior,
)
from bridge.frames import frame_velocities, frames_from_trajectory
from bridge.interpolation import positions_at
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from bridge.timeline_keys import END_MARGIN
from services.planner.pipeline import plan
from shared.errors import InvalidInputError
from shared.libqi import qi
from shared.messages import CommandFrames, PlanRequest, Trajectory
from shared.robot import load_arm
from shared.robot.body import MARGIN, closest
from shared.robot.other_arm import with_other_arm
from shared.robot.postures import forward, rest
from tests.limp_arm_run import let_go
from tests.test_planner_other_arm import LEFT_ACROSS, START, TARGET


def script_box(xml: str, session: Any, on_stopped: Callable[[], None]) -> Any:
    """The behavior's script box, loaded as Choregraphe's runtime loads one:
    ``MyClass`` on the runtime's ``GeneratedClass``, ``ALProxy`` from
    ``session``; its ``onStopped`` output calls ``on_stopped``."""

    class GeneratedClass:  # what Choregraphe's runtime gives a box
        def __init__(self) -> None:
            pass

        def onStopped(self) -> None:
            on_stopped()

    runtime: dict[str, Any] = {
        "GeneratedClass": GeneratedClass,
        "ALProxy": lambda name: session.service(name),
    }
    exec(script_of(xml), runtime)
    box = runtime["MyClass"]()
    box.onLoad()
    return box


def xml_of(trajectory: Trajectory, frames: CommandFrames) -> str:
    """The behavior of ``frames``, its tangents ``trajectory``'s velocities."""
    return behavior_xml(frames, velocities=frame_velocities(trajectory, frames))


@pytest.mark.parametrize("side", ["right", "left"])
def test_keys_round_trip_within_0_05_degree(
    side: str, rng: np.random.Generator, tmp_path: Path
) -> None:
    """Reading the file's keys back gives the trajectory's angles at the times
    the runtime plays them within 0.05 degrees (in fact within the 1e-6
    degree written): the start at 0 s, frame k at k / 25 s, then the last
    posture held."""
    limits = load_arm(side).limits
    targets = rng.uniform(
        limits.lower + 0.1 * limits.span, limits.upper - 0.1 * limits.span, (2, 5)
    )
    trajectory = minimum_jerk_trajectory(
        side, [rest(side), *targets, rest(side)], [0.9, 0.7, 1.1]
    )
    frames = frames_from_trajectory(trajectory)
    velocities = frame_velocities(trajectory, frames)
    path = write_behavior(frames, tmp_path / "behavior.xar", velocities=velocities)
    keys = read_behavior(path)
    assert keys.fps == 25 and keys.start_frame == 1
    assert keys.names == list(trajectory.joint_names)
    m = len(frames.times)
    for j, name in enumerate(keys.names):
        times = keys.times(name)
        expected = np.degrees(positions_at(trajectory, times)[:, j])
        error = np.abs(np.degrees(keys.angles(name)) - expected)
        assert error.max() < 0.05
        assert error.max() <= 0.5e-6 + 1e-9
        assert times[0] == 0.0
        np.testing.assert_allclose(times[1 : m + 1], frames.times, rtol=0, atol=1e-12)
        assert times[m + 1 :].min() > frames.duration


def test_the_file_is_a_start_box_then_a_timeline_box() -> None:
    """A xar_version 3 project whose root diagram runs a Python script box
    (moving the arm to the start at 20 % of its speed limits), then a keyed
    Timeline box: fps 25, start_frame 1, one degree-unit curve per joint,
    keys 1 (the start), 2..14 (frames 1..13), 15..17 (the last posture held)."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") - [0.3, 0.3, 0.3, -0.3, 0.3]], [0.5]
    )
    frames = frames_from_trajectory(trajectory)
    root = ET.fromstring(xml_of(trajectory, frames))
    ns = {"c": NAMESPACE}
    assert root.tag == f"{{{NAMESPACE}}}ChoregrapheProject"
    assert root.attrib["xar_version"] == "3"
    diagram = root.find(
        "c:Box/c:Timeline/c:BehaviorLayer/c:BehaviorKeyframe/c:Diagram", ns
    )
    assert diagram is not None
    start_box, timeline_box = diagram.findall("c:Box", ns)
    script = (start_box.findtext("c:script/c:content", namespaces=ns) or "").strip()
    assert script.startswith("class MyClass(GeneratedClass):")
    compile(script, "start box", "exec")  # valid Python
    assert "self.joint_names, now, self.first_key, 0.2" in script
    assert "self.motion.angleInterpolation(self.joint_names, keys, times, True)" in (
        script
    )
    assert start_box.find("c:Timeline", ns) is None
    timeline = timeline_box.find("c:Timeline", ns)
    assert timeline is not None
    assert timeline.attrib["fps"] == "25" and timeline.attrib["start_frame"] == "1"
    assert timeline.attrib["size"] == "17"
    curves = timeline.findall("c:ActuatorList/c:ActuatorCurve", ns)
    assert [c.attrib["actuator"] for c in curves] == list(trajectory.joint_names)
    assert {c.attrib["unit"] for c in curves} == {"0"}
    frames_written = [int(k.attrib["frame"]) for k in curves[0].findall("c:Key", ns)]
    assert frames_written == list(range(1, 18))
    chain = {
        (link.attrib["outputowner"], link.attrib["indexofoutput"]): (
            link.attrib["inputowner"],
            link.attrib["indexofinput"],
        )
        for link in diagram.findall("c:Link", ns)
    }
    start_id, timeline_id = start_box.attrib["id"], timeline_box.attrib["id"]
    assert chain == {
        ("0", "2"): (start_id, "2"),  # the behavior's onStart -> the script
        (start_id, "4"): (timeline_id, "2"),  # at the start -> the timeline
        (timeline_id, "4"): ("0", "4"),  # the timeline's end -> onStopped
    }


def test_frames_off_the_timeline_grid_are_refused() -> None:
    """A frame that is not on a whole frame of the timeline cannot be written."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + 0.1], [0.5]
    )
    frames = frames_from_trajectory(trajectory)
    frames = frames.model_copy(update={"times": [0.05, *frames.times[1:]]})
    with pytest.raises(
        InvalidInputError, match=r"frame 1 at t = 0\.050000 s is not on a frame"
    ):
        xml_of(trajectory, frames)


def test_reading_something_else_is_a_clear_error() -> None:
    """Not XML, or XML without a keyed timeline: InvalidInputError."""
    with pytest.raises(InvalidInputError, match="not a Choregraphe behavior"):
        timeline_from_xml("<ChoregrapheProject")
    with pytest.raises(InvalidInputError, match="no Timeline with an ActuatorList"):
        timeline_from_xml("<ChoregrapheProject xar_version='3'/>")


def test_a_fractional_frame_rate_is_refused_naming_it() -> None:
    """Choregraphe's runtime holds fps as an int: frames at 12.5 fps were
    written as fps="12.5" (read as 12 or not at all); now refused, the rate
    shown as given, with the whole rates on either side."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + 0.1], [0.8]
    )
    frames = frames_from_trajectory(trajectory, 12.5)
    with pytest.raises(InvalidInputError) as caught:
        xml_of(trajectory, frames)
    assert caught.value.field == "rate"
    assert "got 12.5: use 12 or 13 fps" in caught.value.message
    with pytest.raises(InvalidInputError, match="whole number"):
        timeline_fps(29.97)
    assert timeline_fps(30.0) == 30


def test_the_reader_reads_fps_as_the_runtime_does() -> None:
    """A file with fps="12.5" is refused by the reader, not read as 12.5."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + 0.1], [0.8]
    )
    frames = frames_from_trajectory(trajectory)
    text = xml_of(trajectory, frames).replace('fps="25"', 'fps="12.5"')
    with pytest.raises(InvalidInputError, match=r"fps '12\.5' is not a whole number"):
        timeline_from_xml(text)


def script_of(xml: str, box: int = 0) -> str:
    """The Python of the ``box``-th box of a behavior's root diagram."""
    ns = {"c": NAMESPACE}
    diagram = ET.fromstring(xml).find(
        "c:Box/c:Timeline/c:BehaviorLayer/c:BehaviorKeyframe/c:Diagram", ns
    )
    assert diagram is not None
    boxes = diagram.findall("c:Box", ns)
    return (boxes[box].findtext("c:script/c:content", namespaces=ns) or "").strip()


def test_the_start_box_brings_the_arm_to_the_start_on_the_simulated_nao(
    tmp_path: Path,
) -> None:
    """The behavior played from NAO's rest posture: its script box, run as
    Choregraphe runs a box (``MyClass`` on the runtime's ``GeneratedClass``,
    ``ALProxy``) against the simulated NAO over libqi, moves the arm to the
    timeline's first key within 20 % of the speed, acceleration and jerk
    limits, and only then fires ``onStopped`` (which starts the timeline).
    Its move used ``angleInterpolationWithSpeed`` (a straight line, its
    speed stepping at once): at a 5 ms cycle 2.6 times the bridge's
    acceleration limit and 28 times its jerk limit."""
    start = forward("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.2], [0.6])
    xml = xml_of(trajectory, frames_from_trajectory(trajectory))
    first_key = [
        timeline_from_xml(xml).angles(name)[0] for name in trajectory.joint_names
    ]
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log, period=0.005) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        at_rest = motion.getAngles(trajectory.joint_names, False)
        stopped: list[list[float]] = []

        box = script_box(
            xml,
            session,
            lambda: stopped.append(motion.getAngles(trajectory.joint_names, False)),
        )
        box.onInput_onStart()
        session.close()
    assert np.abs(np.subtract(at_rest, start)).max() > 0.5  # it had to move
    assert len(stopped) == 1
    np.testing.assert_allclose(stopped[0], first_key, atol=1e-6)
    calls = [e for e in read_log(log) if e["event"] == "call"]
    assert [c["method"] for c in calls] == [
        "stiffnessInterpolation",
        "angleInterpolation",
    ]
    names = list(trajectory.joint_names)
    peaks = logged_peaks(read_log(log), names, calls[1]["t"], float("inf"))
    net = FrameLimits.for_arm("right")
    share = peaks / np.array([net.velocity, net.acceleration, net.jerk])
    assert share[0].max() > 0.15 and share.max() < 0.25
    assert [e["event"] for e in read_log(log)].count("refused") == 0


class RunningBox(NamedTuple):
    """A script box started on its own thread, and what it did.

    Attributes:
        box: The box.
        runner: The thread running its ``onInput_onStart``.
        stopped: One ``True`` per ``onStopped`` it fired (the timeline's start).
        failed: What its ``onInput_onStart`` raised, if anything.
    """

    box: Any
    runner: threading.Thread
    stopped: list[bool]
    failed: list[BaseException]


def start_box_moving(xml: str, session: Any, log: Path) -> RunningBox:
    """The box of ``xml`` started; returned 0.3 s after its move to the start
    took effect on the simulated NAO logging to ``log``."""
    stopped: list[bool] = []
    failed: list[BaseException] = []
    box = script_box(xml, session, lambda: stopped.append(True))

    def start_box() -> None:
        try:
            box.onInput_onStart()
        except BaseException as error:  # the caller checks it
            failed.append(error)

    runner = threading.Thread(target=start_box)
    runner.start()
    deadline = time.monotonic() + 5.0
    while not [e for e in read_log(log) if e["event"] == "motion"][1:]:
        assert time.monotonic() < deadline, "the move never took effect"
        time.sleep(0.01)
    time.sleep(0.3)
    return RunningBox(box, runner, stopped, failed)


def test_the_start_box_stopped_on_the_way_ends_the_move_and_not_the_timeline(
    tmp_path: Path,
) -> None:
    """The behavior stopped while its script box still moves the arm from
    rest to the start (onInput_onStop 0.3 s after the move took effect on
    the simulated NAO): the move ends where the arm is (killTasksUsingResources
    on its joints), onInput_onStart returns without error, and onStopped,
    which starts the timeline, never fires. The box's onStop used to do
    nothing: the arm went on to the start and the timeline began."""
    start = forward("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.2], [0.6])
    xml = xml_of(trajectory, frames_from_trajectory(trajectory))
    names = list(trajectory.joint_names)
    first_key = [timeline_from_xml(xml).angles(name)[0] for name in names]
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        running = start_box_moving(xml, session, log)
        running.box.onInput_onStop()
        running.runner.join(5.0)
        held = motion.getAngles(names, False)
        time.sleep(0.2)
        still = motion.getAngles(names, False)
        session.close()
    assert not running.runner.is_alive()
    assert running.failed == [] and running.stopped == []
    assert np.abs(np.subtract(held, first_key)).max() > 0.3  # far from the start
    np.testing.assert_allclose(still, held, atol=1e-9)  # and holding there
    events = read_log(log)
    calls = [e["method"] for e in events if e["event"] == "call"]
    assert calls[:2] == ["stiffnessInterpolation", "angleInterpolation"]
    assert set(calls[2:]) == {"killTasksUsingResources"}
    assert not [e for e in events if e["event"] == "done"][1:]  # only stiffness


def test_the_start_box_holds_a_limp_arm_where_it_hangs(tmp_path: Path) -> None:
    """The arm held at the start is let go and sags (0.3 rad toward rest)
    before the behavior runs: the box stiffened it in one step and it
    snapped back at its motors' top speed. Now the box moves its command to
    where it hangs first, ramps the stiffness, then moves to the start at
    20 % of the speed limits."""
    start = forward("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.2], [0.6])
    xml = xml_of(trajectory, frames_from_trajectory(trajectory))
    names = list(trajectory.joint_names)
    stopped: list[bool] = []
    with SimProcess(log_path=tmp_path / "sim.jsonl", limp_sag=0.3) as sim:
        session = qi.Session()
        session.connect(sim.url)
        arm = let_go(session, names, start)
        box = script_box(xml, session, lambda: stopped.append(True))
        arm.sampled(box.onInput_onStart)
        session.close()
    assert stopped == [True]
    assert np.abs(arm.hangs - start).max() > 0.29  # it sagged
    share = arm.fastest() / np.asarray(load_arm("right").limits.velocity)
    print("\nfastest share of the speed limits:", share.round(3))
    assert share.max() < 0.3  # the move's 20 %, not the motors' 100 %


def test_the_start_box_refuses_a_robot_not_awake(tmp_path: Path) -> None:
    """After rest() the box stiffened the arm alone and started the timeline
    on a resting robot (the bridge refuses one). Now onInput_onStart raises
    saying why (the runtime reports the box's error), having sent nothing,
    and onStopped, which starts the timeline, never fires."""
    start = forward("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.2], [0.6])
    xml = xml_of(trajectory, frames_from_trajectory(trajectory))
    log = tmp_path / "sim.jsonl"
    stopped: list[bool] = []
    with SimProcess(log_path=log) as sim:
        session = qi.Session()
        session.connect(sim.url)
        session.service("ALMotion").rest()
        before = len(read_log(log))
        box = script_box(xml, session, lambda: stopped.append(True))
        with pytest.raises(RuntimeError, match="the robot is not awake"):
            box.onInput_onStart()
        session.close()
        sent = [e for e in read_log(log)[before:] if e["event"] == "call"]
    assert stopped == []
    assert sent == []


@pytest.mark.parametrize("fps", [25, 30, 900])
def test_the_timeline_ends_after_its_last_frame_is_played(fps: int) -> None:
    """The runtime steps a timeline every 1000 // fps whole milliseconds and
    stops the motion at its last key's frame: at 30 fps (33 ms steps) a
    timeline ending on the last frame stopped the arm 0.1 s early in a 10 s
    movement, at 900 fps (1 ms steps) a tenth of the way before its end. The
    last posture is held until that stop comes END_MARGIN after the last
    frame or later."""
    start = forward("right")
    trajectory = minimum_jerk_trajectory(
        "right", [start, start + 0.3, start], [5.0, 5.0]
    )
    frames = frames_from_trajectory(trajectory, fps)
    keys = timeline_from_xml(xml_of(trajectory, frames))
    steps = int(keys.frames[0][-1]) - keys.start_frame
    stop = steps * (1000 // fps) / 1000.0  # [s] after the keys were sent
    assert stop >= frames.duration + END_MARGIN - 1e-9
    assert stop < frames.duration + END_MARGIN + 2.0 / fps + 0.002
    held = np.column_stack([keys.angles(n) for n in keys.names])
    played = keys.times(keys.names[0])
    after = played > frames.duration + 1e-9
    np.testing.assert_allclose(held[after], held[~after][-1:].repeat(after.sum(), 0))


def test_every_key_holds_a_left_and_a_right_bezier_tangent() -> None:
    """Each Key holds two Tangent elements (the runtime takes 0 or 2), side
    left then right, interpType bezier, a third of a frame to either side
    (the first key's left and the last key's right, leading nowhere, (0, 0)),
    their ordinates opposite (one slope), in the key's degrees."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") - [0.3, 0.3, 0.3, -0.3, 0.3]], [0.5]
    )
    frames = frames_from_trajectory(trajectory)
    root = ET.fromstring(xml_of(trajectory, frames))
    ns = {"c": NAMESPACE}
    curves = root.findall(".//c:ActuatorCurve", ns)
    assert len(curves) == 5
    for curve in curves:
        keys = curve.findall("c:Key", ns)
        last = len(keys) - 1
        for i, key in enumerate(keys):
            tangents = key.findall("c:Tangent", ns)
            assert [t.attrib["side"] for t in tangents] == ["left", "right"]
            assert {t.attrib["interpType"] for t in tangents} == {"bezier"}
            x = [float(t.attrib["abscissaParam"]) for t in tangents]
            y = [float(t.attrib["ordinateParam"]) for t in tangents]
            assert x == [
                0.0 if i == 0 else -0.333333333,
                0.0 if i == last else 0.333333333,
            ]
            assert y[0] == (0.0 if i == 0 else -y[1])
            assert i != last or y == [0.0, 0.0]  # the held posture is level
        middle = keys[7].findall("c:Tangent", ns)[1]
        assert abs(float(middle.attrib["ordinateParam"])) > 0.5  # degrees, moving


@pytest.mark.parametrize("fps", [25, 50])
def test_a_keys_tangents_are_the_trajectorys_velocity_there(fps: int) -> None:
    """Read back, every frame's key has the slope of the planned curve on
    both sides: the trajectory's own velocity at that time (its samples,
    100 Hz, fall on the frames), to the 1e-9 written."""
    away = rest("right") + np.array([-0.4, -0.3, 0.4, 0.4, 0.5])
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), away, rest("right")], [0.8, 0.6]
    )
    frames = frames_from_trajectory(trajectory, fps)
    keys = timeline_from_xml(xml_of(trajectory, frames))
    step = 100 // fps
    planned = np.array(trajectory.velocities)[::step]  # at 0, 1 / fps, ...
    m = len(frames.times)
    assert len(planned) == m + 1
    for j, name in enumerate(keys.names):
        slopes = keys.slopes(name)
        np.testing.assert_allclose(slopes[1 : m + 1, 0], planned[1:, j], atol=1e-6)
        np.testing.assert_allclose(slopes[: m + 1, 1], planned[:, j], atol=1e-6)
        assert np.abs(planned[:, j]).max() > 0.1


def without_tangents(text: str, keep: int | None = None) -> str:
    """``text`` with every key's tangents taken out (but the ``keep``-th's)."""
    keys = text.split("</Key>")
    bare = [
        part if i == keep else re.sub(r"\s*<Tangent [^>]*/>", "", part)
        for i, part in enumerate(keys)
    ]
    return "</Key>".join(bare)


def test_keys_without_tangents_read_with_the_runtimes_bezier_auto_ones() -> None:
    """A file whose keys have no tangents (as armplan wrote them before) reads
    back with the handles the runtime computes for them (BezierAuto); in a
    file where one key kept its tangents, that key's are read as written."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + 0.3, rest("right")], [0.4, 0.4]
    )
    frames = frames_from_trajectory(trajectory)
    text = xml_of(trajectory, frames)
    written = timeline_from_xml(text)
    bare = timeline_from_xml(without_tangents(text))
    for j, name in enumerate(bare.names):
        left, right = auto_handles(bare.frames[j], bare.values[j][:, None])
        np.testing.assert_array_equal(bare.handles(name)[0], left[:, 0])
        np.testing.assert_array_equal(bare.handles(name)[1], right[:, 0])
    mixed = timeline_from_xml(without_tangents(text, keep=5))  # RShoulderPitch's
    left, right = mixed.handles("RShoulderPitch")
    np.testing.assert_array_equal(left[5], written.handles("RShoulderPitch")[0][5])
    np.testing.assert_array_equal(right[5], written.handles("RShoulderPitch")[1][5])
    assert not np.array_equal(right[5], bare.handles("RShoulderPitch")[1][5])
    np.testing.assert_array_equal(left[4], bare.handles("RShoulderPitch")[0][4])
    np.testing.assert_array_equal(
        mixed.handles("RElbowYaw")[1], bare.handles("RElbowYaw")[1]
    )


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (('side="left"', 'side="right"'), "a key has none, or one left and one right"),
        (('interpType="bezier"', 'interpType="linear"'), "Bezier tangents only"),
        (('ordinateParam="', 'ordinateParam="x'), "without a valid abscissa"),
    ],
)
def test_a_key_with_tangents_the_runtime_would_not_play_so_is_refused(
    change: tuple[str, str], words: str
) -> None:
    """Two right tangents, a linear one (another curve than checked) or an
    ordinate that is no number: the reader names the key and what is wrong."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + 0.1], [0.2]
    )
    text = xml_of(trajectory, frames_from_trajectory(trajectory))
    with pytest.raises(InvalidInputError) as caught:
        timeline_from_xml(text.replace(*change, 1))
    assert caught.value.field == "Tangent"
    assert "RShoulderPitch's key at frame 1" in caught.value.message
    assert words in caught.value.message


def test_the_start_box_whose_move_another_client_ends_starts_no_timeline(
    tmp_path: Path,
) -> None:
    """Another client's killAll 0.3 s into the script box's move from rest
    to the start, on a simulated NAO whose killed blocking calls return
    without an error, as NAOqi's may (``killed_calls_return``): the box
    raises, naming the joint furthest from the start, and onStopped, which
    starts the timeline, never fires. It used to fire, and the timeline
    played from wherever the arm had stopped."""
    start = forward("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.2], [0.6])
    xml = xml_of(trajectory, frames_from_trajectory(trajectory))
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log, killed_calls_return=True) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        running = start_box_moving(xml, session, log)
        motion.killAll()
        running.runner.join(5.0)
        session.close()
    failed = running.failed
    assert not running.runner.is_alive() and running.stopped == []
    assert len(failed) == 1 and isinstance(failed[0], RuntimeError)
    assert str(failed[0]).startswith("the move to the start ended with R")
    assert "nothing of the trajectory was sent" in str(failed[0])


def test_the_start_box_leaves_an_arm_another_client_moves_alone(
    tmp_path: Path,
) -> None:
    """Another client's 8 s angleInterpolation moves the arm as the box
    starts: the box raises after 1 s without sending anything, onStopped
    never fires, and the other movement plays to its end. The box's move
    used to cut it off, the arm stopped dead on the simulated NAO."""
    start = forward("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.2], [0.6])
    xml = xml_of(trajectory, frames_from_trajectory(trajectory))
    names = list(trajectory.joint_names)
    log = tmp_path / "sim.jsonl"
    stopped: list[bool] = []
    with SimProcess(log_path=log) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        other = motion.angleInterpolation(
            names, rest("right").tolist(), 8.0, True, _async=True
        )
        while not [e for e in read_log(log) if e["event"] == "motion"]:
            time.sleep(0.01)
        box = script_box(xml, session, lambda: stopped.append(True))
        with pytest.raises(RuntimeError) as caught:
            box.onInput_onStart()
        sent = [e["method"] for e in read_log(log) if e["event"] == "call"]
        other.wait(15000)
        assert not other.hasError(), other.error()
        session.close()
    assert stopped == []
    assert str(caught.value).startswith("the arm is moving, or held by another")
    assert sent == ["angleInterpolation"]  # the other client's


def test_the_start_box_refuses_a_move_into_the_other_arm(tmp_path: Path) -> None:
    """The simulated NAO holds its left arm across; a behavior whose first key
    puts the right arm within the margin of that arm (but clear of the body):
    the box raises naming the left arm, moves nothing and never fires
    ``onStopped``. With the left arm at rest the same box moves."""
    arm = load_arm("right")
    blind = plan(
        PlanRequest(arm="right", start=START, targets=[{"position": TARGET}])
    ).trajectory
    parts = with_other_arm("right", LEFT_ACROSS)
    near = closest(arm, blind.positions, parts)
    assert near.clearance < MARGIN and near.body_part.startswith("left ")
    key = np.array(blind.positions[near.sample])
    assert closest(arm, [key]).clearance >= MARGIN  # clear of the body alone
    trajectory = minimum_jerk_trajectory("right", [key, key], [0.6])
    xml = xml_of(trajectory, frames_from_trajectory(trajectory))
    refused = _beside_the_left_arm(xml, trajectory.joint_names, tmp_path)
    assert "the move to the start would bring the right" in refused


def test_the_start_box_refuses_a_timeline_through_the_other_arm(
    tmp_path: Path,
) -> None:
    """A plan made without ``other_arm`` passes through where the simulated
    NAO holds its left arm; its start is clear of that arm. Exported as a
    behavior, its start box raises naming the left arm and the timeline
    before anything moves, and never fires ``onStopped`` (the timeline's
    start). With the left arm at rest the same box moves to the start."""
    arm = load_arm("right")
    blind = plan(
        PlanRequest(arm="right", start=START, targets=[{"position": TARGET}])
    ).trajectory
    parts = with_other_arm("right", LEFT_ACROSS)
    assert closest(arm, blind.positions, parts).clearance < MARGIN
    assert closest(arm, blind.positions[:1], parts).clearance >= MARGIN
    xml = xml_of(blind, frames_from_trajectory(blind))
    refused = _beside_the_left_arm(xml, blind.joint_names, tmp_path)
    assert refused.startswith("the timeline would bring the right")
    assert "armplan plan --other-arm" in refused


def _beside_the_left_arm(xml: str, names: Sequence[str], tmp_path: Path) -> str:
    """Run the start box of ``xml`` (for the right arm's ``names``) on the
    simulated NAO with its left arm held across, then at rest.

    Asserts that the first box is refused naming the left arm with nothing
    sent, and that the second moves and fires ``onStopped``, alone of the
    two. Returns the refusal's message.
    """
    left = ["L" + name[1:] for name in names]
    log = tmp_path / "sim.jsonl"
    stopped: list[bool] = []
    with SimProcess(log_path=log) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        motion.angleInterpolationWithSpeed(left, LEFT_ACROSS, 0.5)
        moved = _moves(log)
        with pytest.raises(RuntimeError, match=r"NAO's left \w+") as refused:
            script_box(xml, session, lambda: stopped.append(True)).onInput_onStart()
        after_refusal = _moves(log)
        motion.angleInterpolationWithSpeed(left, rest("left").tolist(), 0.5)
        script_box(xml, session, lambda: stopped.append(True)).onInput_onStart()
        session.close()
    assert after_refusal == moved
    assert stopped == [True]  # only the second box reached the start
    assert _moves(log) > after_refusal
    return str(refused.value)


def _moves(log: Path) -> int:
    """angleInterpolation calls in the sim's log."""
    return sum(
        1
        for e in read_log(log)
        if e["event"] == "call" and e["method"] == "angleInterpolation"
    )
