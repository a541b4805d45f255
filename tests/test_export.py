"""Exports: the angleInterpolation call, the Python script, the CLI command."""

from __future__ import annotations

import contextlib
import io
import json
import re
import resource
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from armplan.cli.main import main
from bridge.almotion import angle_interpolation_call
from bridge.bezier_curve import CurvePeaks, check_played_curve, played_curve
from bridge.checks import check_frames
from bridge.choregraphe import (
    behavior_frames,
    behavior_xml,
    read_behavior,
    timeline_from_xml,
)
from bridge.frames import frame_velocities, frames_from_trajectory
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.python_export import python_script, write_python
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.libqi import qi
from shared.messages import CommandFrames, Trajectory
from shared.robot.postures import forward, rest
from tests.limp_arm_run import let_go
from tests.narrowed_sim import narrowed_sim


def trajectory() -> Trajectory:
    start = rest("right")
    return minimum_jerk_trajectory(
        "right", [start, start + np.array([-0.6, -0.3, -0.4, 0.5, 0.7])], [0.6]
    )


def script_lists(text: str) -> dict[str, list]:
    """Run the script's list block (not its runner) and return its lists."""
    block = text.split("\n\ndef main", 1)[0]
    namespace: dict[str, list] = {}
    exec(block, namespace)
    return namespace


def test_the_call_has_one_key_list_per_joint() -> None:
    """angleInterpolation(names, angleLists, timeLists, True): n lists of m keys."""
    frames = frames_from_trajectory(trajectory())
    call = angle_interpolation_call(frames)
    names, angles, times, absolute = call
    assert names == frames.joint_names and absolute is True
    assert len(angles) == len(times) == 5
    assert all(t == frames.times for t in times)
    assert np.allclose(np.array(angles).T, frames.positions)
    assert call.duration == pytest.approx(0.6)


def test_the_script_holds_choregraphes_names_times_keys() -> None:
    """names/times/keys appended per joint, as Choregraphe exports them."""
    frames = frames_from_trajectory(trajectory())
    text = python_script(frames)
    assert text.startswith("# Choregraphe simplified export in Python.")
    assert "motion.angleInterpolation(names, keys, times, True)" in text
    lists = script_lists(text)
    assert lists["names"] == frames.joint_names
    assert lists["times"] == [frames.times] * 5  # exactly: what was checked
    np.testing.assert_array_equal(np.array(lists["keys"]).T, frames.positions)
    assert lists["start"] == frames.start


def test_the_script_plays_on_the_simulated_nao(tmp_path: Path) -> None:
    """Run as a program against the simulated NAO, the script's keys arrive."""
    frames = frames_from_trajectory(trajectory())
    script = write_python(frames, tmp_path / "play.py")
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log) as sim:
        run = subprocess.run(
            [sys.executable, str(script), sim.url],
            capture_output=True,
            text=True,
            timeout=30,
            check=False,
        )
        assert run.returncode == 0, run.stdout + run.stderr
    entries = read_log(log)
    calls = [
        e
        for e in entries
        if e["event"] == "call" and e["method"] == "angleInterpolation"
    ]
    assert len(calls) == 2  # the move to the start, then the keys
    assert np.allclose(np.array(calls[1]["angles"]).T, frames.positions, atol=1e-7)
    done = [
        e
        for e in entries
        if e["event"] == "done" and e["method"] == "angleInterpolation"
    ]
    assert len(done) == 2


def test_the_script_holds_a_limp_arm_where_it_hangs(tmp_path: Path) -> None:
    """The arm held at ``forward`` is let go and sags (RShoulderPitch 0.3 rad
    toward rest), then play.py runs: it stiffened the arm in one step and
    RShoulderPitch snapped back 0.3 rad at 97 % of its speed limit. Now its
    command is moved to where it hangs first, the stiffness ramps, and the
    approach brings it back at 20 % of the speed limits."""
    there = np.array(forward("right"))
    frames = frames_from_trajectory(
        minimum_jerk_trajectory("right", [there, there], [0.5])
    )
    names = list(frames.joint_names)
    script = write_python(frames, tmp_path / "play.py")
    with SimProcess(log_path=tmp_path / "sim.jsonl", limp_sag=0.3) as sim:
        session = qi.Session()
        session.connect(sim.url)
        arm = let_go(session, names, there)
        run = arm.sampled(
            lambda: subprocess.run(
                [sys.executable, str(script), sim.url],
                capture_output=True,
                text=True,
                timeout=30,
                check=False,
            )
        )
        arrived = np.array(arm.motion.getAngles(names, True))
        session.close()
    assert run.returncode == 0, run.stdout + run.stderr
    assert np.abs(arm.hangs - there).max() > 0.29  # it sagged
    np.testing.assert_allclose(arrived, there, atol=1e-3)
    share = arm.fastest() / np.asarray(FrameLimits.for_arm("right").velocity)
    print("\nfastest share of the speed limits:", share.round(3))
    assert share.max() < 0.3  # the approach's 20 %, not the motors' 100 %


def test_the_script_refuses_a_robot_not_awake(tmp_path: Path) -> None:
    """After rest() play.py stiffened the arm alone and played on a resting
    robot (the bridge refuses one). Now it prints why and exits 1, having
    sent nothing."""
    frames = frames_from_trajectory(trajectory())
    script = write_python(frames, tmp_path / "play.py")
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log) as sim:
        session = qi.Session()
        session.connect(sim.url)
        session.service("ALMotion").rest()
        session.close()
        before = len(read_log(log))
        run = subprocess.run(
            [sys.executable, str(script), sim.url],
            capture_output=True,
            text=True,
            timeout=30,
            check=False,
        )
        sent = [e for e in read_log(log)[before:] if e["event"] == "call"]
    assert run.returncode == 1
    assert "play.py: error: the robot is not awake" in run.stderr
    assert "nothing was sent" in run.stderr
    assert sent == []


def test_the_script_refuses_a_limp_joint_without_a_speed_limit(
    tmp_path: Path,
) -> None:
    """A robot whose getLimits gives RElbowYaw speed 0: play.py divided by
    it to time the hold of the limp arm and died with ZeroDivisionError.
    Now it says which joint, exits 1, and the arm stays limp and unmoved."""
    frames = frames_from_trajectory(trajectory())
    names = list(frames.joint_names)
    speed = float(FrameLimits.for_arm("right").velocity[names.index("RElbowYaw")])
    script = write_python(frames, tmp_path / "play.py")
    with narrowed_sim("RElbowYaw", "velocity", speed) as url:
        session = qi.Session()
        session.connect(url)
        motion = session.service("ALMotion")
        motion.setStiffnesses("RArm", 0.0)
        commanded = motion.getAngles(names, False)
        run = subprocess.run(
            [sys.executable, str(script), url],
            capture_output=True,
            text=True,
            timeout=30,
            check=False,
        )
        stiffness = motion.getStiffnesses(names)
        after = motion.getAngles(names, False)
        session.close()
    assert run.returncode == 1, run.stderr
    assert "play.py: error: the robot gives RElbowYaw no speed limit" in run.stderr
    assert "nothing was sent" in run.stderr
    assert max(stiffness) == 0.0
    assert after == commanded


def test_cli_writes_both_exports(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """armplan export choregraphe|python TRAJ.json -o FILE writes checked frames."""
    source = tmp_path / "trajectory.json"
    source.write_text(trajectory().to_json())
    assert (
        main(
            [
                "export",
                "choregraphe",
                str(source),
                "-o",
                str(tmp_path / "b.xar"),
                "--json",
            ]
        )
        == 0
    )
    summary = json.loads(capsys.readouterr().out)
    assert summary["frames"] == 15 and summary["rate"] == 25.0
    assert read_behavior(tmp_path / "b.xar").names[0] == "RShoulderPitch"
    assert main(["export", "python", str(source), "-o", str(tmp_path / "p.py")]) == 0
    assert "wrote" in capsys.readouterr().out
    assert script_lists((tmp_path / "p.py").read_text())["names"][4] == "RWristYaw"


def test_cli_refuses_an_unsafe_trajectory(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A trajectory over a speed limit is not exported; exit code 1 and the reason."""
    fast = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") - [2.0, 0, 0, 0, 0]], [0.3]
    )
    source = tmp_path / "fast.json"
    source.write_text(fast.to_json())
    assert (
        main(["export", "choregraphe", str(source), "-o", str(tmp_path / "f.xar")]) == 1
    )
    err = capsys.readouterr().err
    assert "trajectory refused, nothing was written: RShoulderPitch speed" in err
    assert not (tmp_path / "f.xar").exists()
    assert (
        main(
            [
                "export",
                "python",
                str(tmp_path / "missing.json"),
                "-o",
                str(tmp_path / "x.py"),
            ]
        )
        == 1
    )


@pytest.fixture(scope="module")
def planned_json() -> str:
    """``armplan plan --target 0.15 -0.1 0.05 --json``: a 100 Hz reach."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["plan", "--target", "0.15", "-0.1", "0.05", "--json"]) == 0
    return out.getvalue()


@pytest.mark.parametrize("fmt", ["python", "choregraphe"])
@pytest.mark.parametrize(
    ("factor", "gap"), [(20.0, "2.7"), (1000.0, "143.8")], ids=["slowed", "ms"]
)
def test_cli_refuses_times_scaled_without_the_velocities(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    planned_json: str,
    fmt: str,
    factor: float,
    gap: str,
) -> None:
    """A planned reach, its times scaled with its velocities left (a plan
    slowed 20 times by its times alone; times in milliseconds): every limit
    and the frame rate passed, and both formats were written with keys 2.7
    and 144 degrees off the slowed plan. Now exit 1, naming the joint, the
    sample and the likely cause, and no file."""
    data = json.loads(planned_json)
    data["times"] = [factor * t for t in data["times"]]
    source = tmp_path / "scaled.json"
    source.write_text(json.dumps(data))
    out = tmp_path / f"out.{fmt}"
    assert main(["export", fmt, str(source), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(
        "armplan: error: trajectory refused, nothing was written: RShoulderPitch "
        f"velocity -2.607 rad/s at sample 37 (t = {0.37 * factor:.3f} s) "
        "disagrees with the positions"
    )
    assert f"strays at least {gap} deg both from the positions' own" in err
    assert "the times scaled without them?" in err
    assert not out.exists()


def _small_files() -> None:
    """In the child: files of at most 20 kB (``ulimit -f 20``), the signal
    ignored so that a longer write fails with EFBIG instead of killing it."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (20 * 1024, 20 * 1024))


@pytest.mark.parametrize(("fmt", "suffix"), [("choregraphe", "xar"), ("python", "py")])
def test_an_export_cut_short_leaves_the_older_file_whole(
    tmp_path: Path, fmt: str, suffix: str
) -> None:
    """`armplan export` over a good older export, in a process allowed 20 kB
    files (the new file is larger): exit 1 naming the file and the reason;
    the older file is as it was, and no partial file is left. It was written
    in place: a .xar of unclosed XML, the older one gone."""
    there, back = forward("right"), rest("right")
    swings = minimum_jerk_trajectory("right", [back, there] * 3, [2.0] * 5)
    source = tmp_path / "long.json"
    source.write_text(swings.to_json())
    out = tmp_path / f"keep.{suffix}"
    short = tmp_path / "short.json"
    short.write_text(trajectory().to_json())
    assert main(["export", fmt, str(short), "-o", str(out)]) == 0
    older = out.read_bytes()
    done = subprocess.run(
        [sys.executable, "-m", "armplan", "export", fmt, str(source), "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=_small_files,
    )
    assert done.returncode == 1
    assert done.stderr == f"armplan: error: cannot write {out}: File too large\n"
    assert out.read_bytes() == older
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [out.name, source.name, short.name]
    )


@pytest.mark.parametrize("rate", ["0.5", "1e-300", "2000"])
def test_cli_refuses_a_frame_rate_out_of_range(
    rate: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Frame rates outside [1, 1000] Hz are refused before anything is written
    (at 1e-300 fps the timeline would have lasted 1e300 s)."""
    source = tmp_path / "trajectory.json"
    source.write_text(trajectory().to_json())
    out = tmp_path / "b.xar"
    assert (
        main(["export", "choregraphe", str(source), "-o", str(out), "--rate", rate])
        == 1
    )
    assert "--rate must be in [1, 1000] Hz" in capsys.readouterr().err
    assert not out.exists()


def written_frames(path: Path, tmp_path: Path) -> CommandFrames:
    """What an export file holds, as frames: the behavior's keys read back
    (played at (frame - start_frame) / fps, degrees; the first key the
    start), or the script's lists."""
    start = json.loads((tmp_path / "plan.json").read_text())["positions"][0]
    if path.suffix == ".xar":
        keys = read_behavior(path)
        times = keys.times(keys.names[0])
        angles = np.column_stack([keys.angles(name) for name in keys.names])
        assert times[0] == 0.0
        np.testing.assert_allclose(angles[0], start, atol=1e-7)
        start, times, positions = angles[0].tolist(), times[1:], angles[1:]
        names, rate = keys.names, keys.fps
    else:
        lists = script_lists(path.read_text())
        names, times = lists["names"], np.array(lists["times"][0])
        positions = np.array(lists["keys"]).T
        rate = 1.0 / times[0]
    return CommandFrames(
        arm="right",
        rate=rate,
        joint_names=names,
        start=start,
        times=times.tolist(),
        positions=positions.tolist(),
    )


def test_what_a_fast_python_export_holds_keeps_the_limits(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The fastest reach at 900 fps: the script's own numbers, read back,
    keep every limit (times rounded to 1e-6 s made a jerk of 2.8 times the
    limit)."""
    plan = tmp_path / "plan.json"
    target = ["--target", "0.12", "-0.13", "0.05", "--fastest"]
    assert main(["plan", *target, "--rate", "900", "--json"]) == 0
    plan.write_text(capsys.readouterr().out)
    out = tmp_path / "p.py"
    assert main(["export", "python", str(plan), "-o", str(out), "--rate", "900"]) == 0
    written = written_frames(out, tmp_path)
    assert len(written.times) > 300
    check_frames(written, FrameLimits.for_arm("right"))


def test_a_fast_behavior_is_refused_with_a_rate_whose_file_keeps_the_limits(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The fastest reach at 1000 fps: its keys keep every limit, but keys a
    millisecond apart, held as the runtime holds them (32-bit degrees, steps
    of 1.3e-7 rad near 80 degrees), make the curve through them jerk over
    the limit. Refused, offering a whole rate; at that rate the file's own
    numbers, read back, keep every limit, on the keys and on the curve
    through them and their tangents."""
    plan = tmp_path / "plan.json"
    target = ["--target", "0.12", "-0.13", "0.05", "--fastest"]
    assert main(["plan", *target, "--rate", "1000", "--json"]) == 0
    plan.write_text(capsys.readouterr().out)
    out = tmp_path / "b.xar"
    export = ["export", "choregraphe", str(plan), "-o", str(out), "--rate"]
    assert main([*export, "1000"]) == 1
    err = capsys.readouterr().err
    assert "jerk" in err and "on the curve Choregraphe plays through the keys" in err
    offered = re.search(r"at (\d+) fps it would not", err)
    assert offered is not None, err
    assert not out.exists()
    assert main([*export, offered.group(1)]) == 0
    written = written_frames(out, tmp_path)
    limits = FrameLimits.for_arm("right")
    check_frames(written, limits)
    check_played_curve(played_curve(read_behavior(out)), limits)


def test_a_behavior_plays_the_planned_curve_at_the_bridges_own_limits(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A reach planned at the bridge's own acceleration and jerk limits, at
    25 fps: the curve Choregraphe played through its keys without tangents
    (BezierAuto) asked RShoulderRoll for 1.2 times its acceleration limit,
    and the behavior was refused. With the planned velocities as the keys'
    tangents the file, read back, plays the plan: its curve's speed and
    acceleration are the trajectory's within 0.05 of each limit, its jerk
    at most 0.05 over the trajectory's, and it keeps every limit."""
    limits = FrameLimits.for_arm("right")
    nets = [
        ["--max-acceleration", *(f"{0.9999 * a:.4f}" for a in limits.acceleration)],
        ["--max-jerk", *(f"{0.9999 * j:.3f}" for j in limits.jerk)],
    ]
    plan = tmp_path / "plan.json"
    target = ["--target", "0.02", "-0.10", "0.25", "--fastest", *nets[0], *nets[1]]
    assert main(["plan", *target, "--json"]) == 0
    plan.write_text(capsys.readouterr().out)
    out = tmp_path / "b.xar"
    assert main(["export", "choregraphe", str(plan), "-o", str(out)]) == 0
    curve = played_curve(read_behavior(out))
    check_played_curve(curve, limits)
    peaks = CurvePeaks(curve)
    reach = Trajectory.model_validate_json(plan.read_text())
    t = np.array(reach.times)
    planned = {
        "speed": np.abs(reach.velocities),
        "acceleration": np.abs(reach.accelerations),
        "jerk": np.abs(np.diff(reach.accelerations, axis=0) / np.diff(t)[:, None]),
    }
    for quantity, bound in (
        ("speed", limits.velocity),
        ("acceleration", limits.acceleration),
        ("jerk", limits.jerk),
    ):
        played = getattr(peaks, quantity).max(axis=0) / bound
        plan_peak = planned[quantity].max(axis=0) / bound
        assert (played <= plan_peak + 0.05).all(), quantity
        if quantity != "jerk":  # keys 40 ms apart smooth the jerk's steps
            np.testing.assert_allclose(played, plan_peak, atol=0.05)
    assert (peaks.speed.max(axis=0) / limits.velocity).max() > 0.95  # a fast reach


def test_a_behavior_whose_tangents_bend_its_curve_over_a_limit_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A trajectory whose velocities disagree with its positions (RShoulderPitch
    1 rad/s faster, then slower, at alternate 100 Hz samples): its frames, on
    the samples, keep every limit and the Python export is written; but the
    behavior's tangents are those velocities, and the curve through the keys
    bends over the acceleration limit: refused, naming the curve, nothing
    written."""
    reach = trajectory()
    velocities = np.array(reach.velocities)
    velocities[:, 0] += np.where(np.arange(len(velocities)) % 2 == 0, 1.0, -1.0)
    source = tmp_path / "plan.json"
    source.write_text(
        reach.model_copy(update={"velocities": velocities.tolist()}).to_json()
    )
    assert main(["export", "python", str(source), "-o", str(tmp_path / "p.py")]) == 0
    capsys.readouterr()
    out = tmp_path / "b.xar"
    assert main(["export", "choregraphe", str(source), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "RShoulderPitch acceleration" in err
    assert "on the curve Choregraphe plays through the keys exceeds its limit" in err
    assert not out.exists()


def test_a_behavior_holds_the_frames_as_rounded() -> None:
    """behavior_frames (what the checks see) is what the file reads back as:
    the start, the frames at k / fps, the last posture held, each rounded
    as written, then held in 32-bit floats as the runtime holds them."""
    reach = trajectory()
    frames = frames_from_trajectory(reach, 100.0)
    keys = timeline_from_xml(
        behavior_xml(frames, velocities=frame_velocities(reach, frames))
    )
    held = behavior_frames(frames)
    m = len(frames.times)
    for j, name in enumerate(frames.joint_names):
        angles = keys.angles(name)
        assert abs(held.start[j] - angles[0]) < 2e-7
        np.testing.assert_allclose(
            np.array(held.positions)[:, j], angles[1:], rtol=0, atol=2e-7
        )
    np.testing.assert_allclose(
        held.times, keys.times(keys.names[0])[1:], rtol=1e-7, atol=0
    )
    np.testing.assert_allclose(held.times[:m], frames.times, rtol=1e-7, atol=0)
    rounding = np.subtract(np.array(held.positions)[:m], frames.positions)
    assert 0 < np.abs(rounding).max() < 2e-7
    assert np.abs(np.subtract(held.start, frames.start)).max() < 2e-7
