"""``play.py`` as a program on the simulated NAO: stops, deadlines, options.

Every test writes the script with ``armplan``'s exporter and runs it as its
own process against a simulated NAO process over libqi (or a silent TCP
listener). It used to ignore Ctrl-C until the trajectory had played to its
end (then a raw traceback, exit -2), to hang forever on a port that never
answered, and to move the arm for ``play.py URL --help``.
"""

from __future__ import annotations

import argparse
import glob
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from bridge.address import check_robot_url
from bridge.frames import frames_from_trajectory
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.play_runner import MARGIN, STOP_WAIT
from bridge.python_export import write_python
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.errors import InvalidInputError
from shared.libqi import qi
from shared.robot.postures import forward, rest

#: The reach every test plays: 4 s, RWristYaw 0.7 rad.
REACH = np.array([-0.6, -0.3, -0.4, 0.5, 0.7])
#: Longest a started script takes to import qi and connect here [s].
STARTUP = 10.0


def script(tmp_path: Path, duration: float = 4.0, name: str = "play.py") -> Path:
    """The exported script of a ``duration`` [s] reach from rest."""
    start = rest("right")
    reach = minimum_jerk_trajectory("right", [start, start + REACH], [duration])
    return write_python(frames_from_trajectory(reach), tmp_path / name)


def reach(entry: dict[str, Any]) -> bool:
    """Whether a sim log entry is the reach's call (not the move to its start,
    which from the sim's rest, the reach's start, lasts 0.5 s)."""
    if entry["event"] != "call" or entry["method"] != "angleInterpolation":
        return False
    return bool(entry["times"][0][-1] > 1)


def start(path: Path, *args: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, str(path), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def run(path: Path, *args: str, timeout: float = 30.0) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(path), *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


def logged(sim: SimProcess, found: Callable[[dict[str, Any]], bool]) -> dict:
    """The first sim log entry ``found`` accepts, waited for (at most STARTUP)."""
    assert sim.log_path is not None
    deadline = time.monotonic() + STARTUP
    while time.monotonic() < deadline:
        hits = [e for e in read_log(sim.log_path) if found(e)]
        if hits:
            return hits[0]
        time.sleep(0.01)
    raise AssertionError("not in the sim's log in time")


def calls(sim: SimProcess, method: str | None = None) -> list[dict[str, Any]]:
    assert sim.log_path is not None
    return [
        e
        for e in read_log(sim.log_path)
        if e["event"] == "call" and method in (None, e["method"])
    ]


def monotonic(sim: SimProcess, entry: dict[str, Any]) -> float:
    """The monotonic time [s] of a sim log entry (the log's origin added)."""
    assert sim.log_path is not None
    return float(entry["t"]) + read_log(sim.log_path)[0]["origin"]


def angles(sim: SimProcess, sensors: bool = True) -> np.ndarray:
    """The right arm's angles now [rad], shape (5,)."""
    session = qi.Session()
    session.connect(sim.url)
    try:
        names = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll"]
        motion = session.service("ALMotion")
        return np.array(motion.getAngles([*names, "RWristYaw"], sensors))
    finally:
        session.close()


def ended(process: subprocess.Popen[str], timeout: float) -> tuple[int, str]:
    """Exit code and stderr of ``process``, which must end within ``timeout`` [s]."""
    try:
        _, err = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        raise AssertionError(f"still running {timeout} s later") from None
    return process.returncode, err


@pytest.fixture
def logged_sim(tmp_path: Path) -> Iterator[SimProcess]:
    with SimProcess(log_path=tmp_path / "sim.jsonl") as sim:
        try:
            yield sim
        finally:
            os.kill(sim.pid, signal.SIGCONT)  # a test that paused it


def test_ctrl_c_during_the_trajectory_stops_the_arm_where_it_is(
    tmp_path: Path, logged_sim: SimProcess
) -> None:
    """SIGINT 1 s into the 4 s reach: killTasksUsingResources on its joints
    within 0.5 s, the arm held short of the last key, exit 130 and one line.
    It used to play to the end, then print a KeyboardInterrupt traceback."""
    sim = logged_sim
    play = start(script(tmp_path), sim.url)
    logged(sim, reach)
    time.sleep(1.0)
    play.send_signal(signal.SIGINT)
    sent = time.monotonic()
    code, err = ended(play, STOP_WAIT + 5.0)
    assert (code, err) == (
        130,
        "play.py: interrupted; the arm was stopped where it is\n",
    )
    kill = logged(sim, lambda e: e.get("method") == "killTasksUsingResources")
    assert kill["joints"][0] == "RShoulderPitch" and len(kill["joints"]) == 5
    assert monotonic(sim, kill) - sent < 0.5
    events = [e["event"] for e in read_log(sim.log_path or "")]
    assert "interrupted" in events
    done = [
        e
        for e in read_log(sim.log_path or "")
        if e["event"] == "done" and e["method"] == "angleInterpolation"
    ]
    assert len(done) == 1  # the move to the start, not the reach
    last = rest("right") + REACH
    here = angles(sim)
    assert np.abs(here - last).max() > 0.3  # far from the end
    time.sleep(0.3)
    np.testing.assert_allclose(angles(sim), here, atol=1e-3)  # and it holds


def test_sigterm_during_the_move_to_the_start_stops_it(
    tmp_path: Path, logged_sim: SimProcess
) -> None:
    """The arm held forward, far from the start: SIGTERM while it moves there
    within 20 % of the limits ends that move (exit 143); the trajectory is
    never sent."""
    sim = logged_sim
    session = qi.Session()
    session.connect(sim.url)
    names = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]
    session.service("ALMotion").angleInterpolationWithSpeed(
        names, forward("right").tolist(), 0.5
    )
    session.close()
    play = start(script(tmp_path), sim.url)
    logged(sim, lambda e: e.get("method") == "angleInterpolation")
    time.sleep(0.5)
    play.send_signal(signal.SIGTERM)
    code, err = ended(play, STOP_WAIT + 5.0)
    assert (code, err) == (
        143,
        "play.py: terminated; the arm was stopped where it is\n",
    )
    assert calls(sim, "killTasksUsingResources")
    assert len(calls(sim, "angleInterpolation")) == 1  # the move, not the reach
    here = angles(sim)
    assert np.abs(here - rest("right")).max() > 0.1  # short of the start


def test_a_port_that_never_answers_is_an_error_within_the_timeout(
    tmp_path: Path, busy_port: int
) -> None:
    """A listener that accepts and never answers: exit 1 after --timeout 1
    naming the address and the wait. The connect used to block for ever."""
    url = f"tcp://127.0.0.1:{busy_port}"
    began = time.monotonic()
    done = run(script(tmp_path), url, "--timeout", "1", timeout=STARTUP + 5.0)
    assert time.monotonic() - began < STARTUP
    assert done.returncode == 1
    assert done.stdout == ""  # libqi's "No Application was created" warning
    assert done.stderr == (
        f"play.py: error: cannot connect to {url}: no answer within 1 s "
        "(--timeout SECONDS); nothing was sent\n"
    )


def test_ctrl_c_while_it_waits_for_a_connection_ends_it(
    tmp_path: Path, busy_port: int
) -> None:
    """Ctrl-C during the connection's wait: exit 130 at once, nothing sent."""
    play = start(script(tmp_path), f"tcp://127.0.0.1:{busy_port}")
    time.sleep(3.0)  # importing qi, then waiting for the answer
    play.send_signal(signal.SIGINT)
    assert ended(play, 2.0) == (130, "play.py: interrupted; nothing was sent\n")


def paused_mid_reach(sim: SimProcess, play: subprocess.Popen[str]) -> None:
    """Pause the sim (SIGSTOP) 1 s into the reach ``play`` sent."""
    logged(sim, reach)
    time.sleep(1.0)
    os.kill(sim.pid, signal.SIGSTOP)


def test_ctrl_c_ends_the_script_of_a_stalled_robot(
    tmp_path: Path, logged_sim: SimProcess
) -> None:
    """The robot stalls mid-reach (SIGSTOP), then Ctrl-C: the stops go
    unanswered for STOP_WAIT, then exit 130 saying so. The script used to
    stay blocked in the call."""
    play = start(script(tmp_path), logged_sim.url)
    paused_mid_reach(logged_sim, play)
    play.send_signal(signal.SIGINT)
    code, err = ended(play, STOP_WAIT + 2.0)
    assert code == 130
    assert err == (
        "play.py: interrupted; the robot did not confirm the stop "
        f"(killTasksUsingResources) within {STOP_WAIT:g} s: the arm may still move\n"
    )


def test_a_call_that_overruns_its_duration_is_an_error(
    tmp_path: Path, logged_sim: SimProcess
) -> None:
    """The robot stalls mid-reach of 2 s: after 2 s and MARGIN the script
    says which call overran, tries to stop the arm, and exits 1."""
    play = start(script(tmp_path, duration=2.0), logged_sim.url)
    paused_mid_reach(logged_sim, play)
    code, err = ended(play, 2.0 + MARGIN + STOP_WAIT + 2.0)
    assert code == 1
    assert err.startswith(
        f"play.py: error: ALMotion.angleInterpolation did not end within "
        f"{2 + MARGIN:g} s (its 2 s and a {MARGIN:g} s margin): the robot stalled?; "
        "the robot did not confirm the stop"
    )
    assert err.count("\n") == 1


def test_help_says_what_it_plays_and_connects_nothing(
    tmp_path: Path, logged_sim: SimProcess
) -> None:
    """``play.py URL --help``: the usage, the arm and the duration, exit 0,
    nothing sent. Everything after the URL used to be dropped: it moved."""
    done = run(script(tmp_path), logged_sim.url, "--help")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("usage: play.py [-h] [--timeout SECONDS] [URL]")
    assert "right arm's trajectory (100 frames at 25 fps, 4.000 s;" in done.stdout
    assert "Ctrl-C" in done.stdout
    time.sleep(0.5)
    assert calls(logged_sim) == []


@pytest.mark.parametrize("extra", [["--bogus"], ["tcp://127.0.0.1:1"]])
def test_an_unknown_argument_is_refused_before_connecting(
    tmp_path: Path, logged_sim: SimProcess, extra: list[str]
) -> None:
    """An unknown option or a second address: exit 2 with the usage, nothing
    sent; the script's own file name in the message."""
    done = run(script(tmp_path, name="wave.py"), logged_sim.url, *extra)
    assert done.returncode == 2
    lines = done.stderr.splitlines()
    assert lines[0].startswith("usage: wave.py")
    assert lines[-1] == f"wave.py: error: unrecognized arguments: {extra[0]}"
    time.sleep(0.5)
    assert calls(logged_sim) == []


#: Robot addresses both checks accept.
GOOD_URLS = [
    "tcp://127.0.0.1:9559",
    "tcps://nao.local:9503",
    "tcp://my_nao-2.lab:1",
    "tcp://h:65535",
    "tcp://h:00080",
]
#: Robot addresses both checks refuse.
BAD_URLS = [
    "127.0.0.1",
    "127.0.0.1:9559",
    "tcp://127.0.0.1",
    "tcp://:9559",
    "tcp://h:0",
    "tcp://h:65536",
    "tcp://h:123456",
    "tcp://h:95a9",
    "tcp://h:+955",
    "tcp://h:-1",
    "udp://h:9559",
    "TCP://h:9559",
    "tcp://h:9559/",
    "tcp://h:9559\n",
    "tcp://[::1]:9559",
    "tcp://h :9559",
    "tcp://a://b:1",
    "tcp://h:\u0669\u0665\u0665\u0669",  # 9559 in Arabic-Indic digits
    "tcp://h:\uff19\uff15\uff15\uff19",  # 9559 in fullwidth digits
    "",
]


def accepted_by_the_bridge(url: str) -> bool:
    try:
        check_robot_url(url)
    except InvalidInputError:
        return False
    return True


def accepted_by_the_script(check: Callable[[str], str], url: str) -> bool:
    try:
        check(url)
    except argparse.ArgumentTypeError:
        return False
    return True


def test_the_scripts_address_check_agrees_with_the_bridges(tmp_path: Path) -> None:
    """play.py copies bridge/address.py's check (it imports no ``re``): the
    two accept and refuse the same addresses."""
    names: dict[str, Any] = {"__name__": "play"}
    exec(script(tmp_path).read_text(), names)  # defines, runs nothing
    check = names["_robot_url"]
    urls = GOOD_URLS + BAD_URLS
    bridge = [accepted_by_the_bridge(url) for url in urls]
    assert bridge == [url in GOOD_URLS for url in urls]
    assert [accepted_by_the_script(check, url) for url in urls] == bridge


def test_a_malformed_address_is_refused_before_connecting(tmp_path: Path) -> None:
    """``play.py 127.0.0.1`` tried to connect (``cannot connect to 127.0.0.1:
    Connect error: 111``); now it is refused at once in the bridge's words."""
    done = run(script(tmp_path), "127.0.0.1")
    assert done.returncode == 2
    with pytest.raises(InvalidInputError) as bridge:
        check_robot_url("127.0.0.1")
    lines = done.stderr.splitlines()
    assert lines[0].startswith("usage: play.py")
    assert lines[-1] == f"play.py: error: argument URL: {bridge.value.message}"
    assert done.stdout == ""


def test_a_play_says_what_it_played(tmp_path: Path, logged_sim: SimProcess) -> None:
    """A successful play printed nothing; now one line on stdout, exit 0."""
    done = run(script(tmp_path, duration=1.0), logged_sim.url)
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"played 25 frames (1.000 s) on {logged_sim.url}\n"
    assert len(calls(logged_sim, "angleInterpolation")) == 2  # approach, trajectory


def python2() -> str | None:
    """A Python 2.7 interpreter on this machine, or None."""
    home = os.path.expanduser("~/.pyenv/versions/2.7*/bin/python2.7")
    for exe in [shutil.which("python2.7"), *sorted(glob.glob(home))]:
        if (
            exe
            and subprocess.run([exe, "-c", "pass"], capture_output=True).returncode == 0
        ):
            return exe
    return None


def test_the_options_work_on_python_2(tmp_path: Path) -> None:
    """A NAO's own Python 2.7 reads the script: --help exits 0, an unknown
    argument 2, and without qi or naoqi one line and exit 1."""
    exe = python2()
    if exe is None:
        pytest.skip("no Python 2.7 here")
    path = script(tmp_path)
    ran = [
        subprocess.run([exe, str(path), *a], capture_output=True, text=True)
        for a in (["--help"], ["--bogus"], ["tcp://127.0.0.1:1"], ["127.0.0.1"])
    ]
    assert [r.returncode for r in ran] == [0, 2, 1, 2]
    assert "right arm's trajectory" in ran[0].stdout
    assert ran[2].stderr == (
        "play.py: error: neither the qi package nor NAOqi's naoqi module is installed\n"
    )


def test_the_docs_show_the_scripts_own_usage(tmp_path: Path) -> None:
    """docs/robot.md's usage line of play.py is the script's own."""
    usage = run(script(tmp_path), "--help").stdout.splitlines()[0]
    docs = Path(__file__).resolve().parents[1] / "docs" / "robot.md"
    assert f"    python {usage.removeprefix('usage: ')}\n" in docs.read_text()


def test_a_move_to_the_start_another_client_ends_sends_nothing_more(
    tmp_path: Path,
) -> None:
    """The arm held forward, far from the start; another client's killAll
    ends the move to the start half-way, and the robot's blocking call
    returns without an error, as NAOqi's may (the sim's
    ``killed_calls_return``). The script used to play the trajectory from
    there, its first key a step no check had passed; now it exits 1 naming
    the joint furthest from the start, and sends nothing more."""
    names = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log, killed_calls_return=True) as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        motion.angleInterpolationWithSpeed(names, forward("right").tolist(), 0.5)
        play = start(script(tmp_path), sim.url)
        logged(sim, lambda e: e.get("method") == "angleInterpolation")
        time.sleep(0.5)
        motion.killAll()
        code, err = ended(play, STOP_WAIT + 5.0)
        session.close()
        moves = calls(sim, "angleInterpolation")
    assert code == 1, err
    assert err.startswith("play.py: error: the move to the start ended with R")
    assert err.endswith(
        "(stopped by another client, or refused by the robot); nothing of the "
        "trajectory was sent\n"
    )
    assert len(moves) == 1  # the move to the start, not the reach


def test_a_trajectory_another_client_ends_is_not_reported_played(
    tmp_path: Path,
) -> None:
    """Another client's killAll 1 s into the 4 s reach, the robot's
    blocking call returning without an error, as NAOqi's may: the script
    printed ``played 100 frames`` and exited 0. Now it exits 1 saying the
    trajectory ended short of its last key."""
    with SimProcess(log_path=tmp_path / "sim.jsonl", killed_calls_return=True) as sim:
        play = start(script(tmp_path), sim.url)
        logged(sim, reach)
        time.sleep(1.0)
        session = qi.Session()
        session.connect(sim.url)
        session.service("ALMotion").killAll()
        session.close()
        code, err = ended(play, STOP_WAIT + 5.0)
    assert code == 1, err
    assert err.startswith("play.py: error: the trajectory ended with R")
    assert "from its last key" in err
    assert err.endswith(
        "(stopped by another client, or refused by the robot); it was not "
        "played to its end\n"
    )


def test_an_arm_another_client_moves_is_left_alone(tmp_path: Path) -> None:
    """Another client's 8 s angleInterpolation moves the arm as the script
    starts: the script waits up to 1 s for the arm to be free, then exits 1
    and sends nothing; the other movement plays to its end. Its move to
    the start used to cut that movement off, the arm stopped dead and
    turned within one control cycle on the simulated NAO (a NAO would have
    postponed it and started from elsewhere than it read)."""
    names = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]
    with SimProcess(log_path=tmp_path / "sim.jsonl") as sim:
        session = qi.Session()
        session.connect(sim.url)
        motion = session.service("ALMotion")
        other = motion.angleInterpolation(
            names, forward("right").tolist(), 8.0, True, _async=True
        )
        logged(sim, lambda e: e["event"] == "motion")
        code, err = ended(start(script(tmp_path), sim.url), STARTUP + 5.0)
        sent = calls(sim)
        other.wait(15000)
        assert not other.hasError(), other.error()
        session.close()
    assert code == 1, err
    assert err == (
        "play.py: error: the arm is moving, or held by another motion task "
        "(areResourcesAvailable is false), after 1 s; nothing was sent: let "
        "that movement end, or stop it, and run this again\n"
    )
    assert [c["method"] for c in sent] == ["angleInterpolation"]  # the other's
