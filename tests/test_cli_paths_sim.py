"""``armplan sim``: an address it cannot listen at, a log it cannot write.

Run as real processes (``armplan sim`` becomes ``python -m bridge.sim``).
Each is refused with one line naming the address or the path and the
reason, exit code 1, no traceback, and no simulated NAO started.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from armplan.launch import free_endpoint
from bridge.address import check_listen_url
from bridge.sim import READY
from bridge.sim.cycle import ControlCycle
from bridge.sim.log import SimLog
from bridge.sim.robot import SimRobot
from bridge.sim.server import rest_posture
from shared.errors import InvalidInputError

#: An address of TEST-NET-1 (RFC 5737): never one of this machine's.
NOT_LOCAL = "tcp://192.0.2.1:9559"


def run(*args: str) -> subprocess.CompletedProcess[str]:
    """Run ``python ARGS`` with closed stdin; a sim that starts ends at the timeout."""
    return subprocess.run(
        [sys.executable, *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        stdin=subprocess.DEVNULL,
    )


def armplan_sim(*args: str) -> subprocess.CompletedProcess[str]:
    return run("-m", "armplan", "sim", *args)


def assert_refused(done: subprocess.CompletedProcess[str], stderr: str) -> None:
    """Exit 1, exactly ``stderr``, and the sim never served."""
    assert done.returncode == 1
    assert done.stderr == stderr
    assert READY not in done.stdout


@pytest.fixture
def busy_url(busy_port: int) -> str:
    """A NAOqi address on 127.0.0.1 whose port another socket listens on."""
    return f"tcp://127.0.0.1:{busy_port}"


def test_a_busy_port_is_refused_naming_the_address(busy_url: str) -> None:
    """The port in use is one line, not a bind traceback and a second one
    ("cannot join thread before it is started") from the cleanup."""
    assert_refused(
        armplan_sim("--listen", busy_url),
        f"armplan: error: cannot listen at {busy_url}: Address already in use\n",
    )


def test_an_address_of_another_machine_is_refused() -> None:
    """The sim can only listen on this machine's addresses."""
    assert_refused(
        armplan_sim("--listen", NOT_LOCAL),
        f"armplan: error: cannot listen at {NOT_LOCAL}: "
        "Cannot assign requested address\n",
    )


#: The unspecified addresses, built so the repository scan for them
#: (tests/test_bus_safety.py) finds none written out.
ANY_V4, ANY_V6 = ".".join("0" * 4), "[" + "::" + "]"
#: Each spelling of "every interface", as a NAOqi address.
EVERY_INTERFACE = [
    f"tcp://{ANY_V4}:9559",
    f"tcp://{ANY_V6}:9559",
    "tcp://:::9559",
    "tcp://0:9559",  # the resolver reads 0, 0.0 and 0x0 as the IPv4 one
    "tcp://0x0:0",
]


@pytest.mark.parametrize("url", EVERY_INTERFACE)
def test_every_interface_is_no_address_to_listen_at(url: str) -> None:
    """The sim took commands on every network the machine is on; router
    endpoints refuse that address, and now the sim's does too."""
    with pytest.raises(InvalidInputError) as caught:
        check_listen_url(url)
    assert caught.value.message == (
        f"listen address {url!r} names every interface: give the address of "
        "the one the bridge reaches (127.0.0.1 on one machine)"
    )
    assert check_listen_url("tcp://192.0.2.1:9559")  # one interface's
    assert check_listen_url("tcp://nao-sim.local:9559")  # a name


def test_every_command_starting_a_sim_refuses_every_interface() -> None:
    """`armplan sim --listen`, `python -m bridge.sim --listen`, `armplan up
    --with-sim --sim-listen`: refused, nothing started. Each also has a bad
    option checked after the address, so that a sim never listens on every
    interface, even if the address check were lost."""
    url = f"tcp://{ANY_V4}:0"
    said = (
        f"listen address {url!r} names every interface: give the address of "
        "the one the bridge reaches (127.0.0.1 on one machine)\n"
    )
    assert_refused(
        armplan_sim("--listen", url, "--period", "0"), f"armplan: error: {said}"
    )
    done = run("-m", "bridge.sim", "--listen", url, "--period", "0")
    assert (done.returncode, READY in done.stdout) == (2, False)
    assert done.stderr.endswith(f"python -m bridge.sim: error: {said}")
    up = run(
        *("-m", "armplan", "up", "--listen", free_endpoint(), "--only", "fit"),
        *("--with-sim", "--sim-listen", url, "--model", "missing-model.json"),
    )
    assert (up.returncode, up.stdout, up.stderr) == (1, "", f"armplan: error: {said}")


def test_the_sim_process_itself_reports_a_busy_port_on_one_line(
    busy_url: str,
) -> None:
    """python -m bridge.sim, past every check, fails in libqi's listen: one
    line naming the address, exit 1, and the cleanup raises nothing more."""
    done = run("-m", "bridge.sim", "--listen", busy_url)
    assert done.returncode == 1
    assert "Traceback" not in done.stderr
    last = done.stderr.strip().splitlines()[-1]
    assert last == (
        f"python -m bridge.sim: error: cannot listen at {busy_url}: "
        "Address already in use"
    )


def test_the_sim_process_speaks_as_the_command_that_started_it(
    busy_url: str,
) -> None:
    """``armplan sim`` becomes ``python -m bridge.sim --prog armplan``: a port
    taken after armplan's own check is still armplan's error."""
    done = run("-m", "bridge.sim", "--listen", busy_url, "--prog", "armplan")
    assert done.returncode == 1
    assert done.stderr.strip().splitlines()[-1] == (
        f"armplan: error: cannot listen at {busy_url}: Address already in use"
    )


def test_a_cycle_that_never_started_stops_quietly() -> None:
    """stop() before start() (the listen failed) is no error."""
    cycle = ControlCycle(SimRobot(SimLog(), rest_posture()))
    cycle.stop()
    cycle.stop()


def test_a_folder_as_log_is_refused(tmp_path: Path) -> None:
    """--log DIR: the path and "Is a directory", before the sim starts."""
    assert_refused(
        armplan_sim("--listen", "tcp://127.0.0.1:0", "--log", str(tmp_path)),
        f"armplan: error: cannot write the sim log {tmp_path}: Is a directory\n",
    )


def test_a_log_in_a_missing_folder_is_refused(tmp_path: Path) -> None:
    """--log /missing/x.log: the path and "No such file or directory"."""
    log = tmp_path / "missing" / "x.log"
    assert_refused(
        armplan_sim("--listen", "tcp://127.0.0.1:0", "--log", str(log)),
        f"armplan: error: cannot write the sim log {log}: No such file or directory\n",
    )
    assert not log.parent.exists()


def test_an_empty_log_path_is_refused() -> None:
    """--log "" is refused rather than silently logging nowhere."""
    assert_refused(
        armplan_sim("--listen", "tcp://127.0.0.1:0", "--log", ""),
        "armplan: error: the sim log's path is empty\n",
    )


def test_the_sim_process_refuses_a_folder_as_log(tmp_path: Path) -> None:
    """python -m bridge.sim --log DIR is a usage error (exit 2) naming the path."""
    done = run(
        "-m", "bridge.sim", "--listen", "tcp://127.0.0.1:0", "--log", str(tmp_path)
    )
    assert done.returncode == 2
    assert done.stderr.endswith(
        f"python -m bridge.sim: error: cannot write the sim log {tmp_path}: "
        "Is a directory\n"
    )
    assert READY not in done.stdout


def test_a_sag_out_of_range_is_refused() -> None:
    """--limp-sag 20: armplan's one-line error, before the sim starts."""
    assert_refused(
        armplan_sim("--listen", "tcp://127.0.0.1:0", "--limp-sag", "20"),
        "armplan: error: --limp-sag must be 0..10 s, got 20.0\n",
    )


def test_the_sim_options_reach_the_sim() -> None:
    """``armplan sim --grip 0.3``: the hand closes on the object, 0.3 open
    (the options docs/robot.md lists were ``python -m bridge.sim``'s only)."""
    import qi

    command = [sys.executable, "-m", "armplan", "sim", "--listen", "tcp://127.0.0.1:0"]
    command += ["--grip", "0.3", "--limp-sag", "0.3", "--killed-calls-return"]
    process = subprocess.Popen(
        command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    try:
        assert process.stdout is not None
        line = next(x for x in process.stdout if x.startswith(READY))
        session = qi.Session()
        session.connect(line.split()[-1])
        try:
            motion = session.service("ALMotion")
            motion.angleInterpolation("RHand", 0.0, 0.5, True)
            assert motion.getAngles("RHand", True)[0] == pytest.approx(0.3)
        finally:
            session.close()
    finally:
        process.terminate()
        process.communicate(timeout=10)


def test_the_first_line_of_the_sims_output_is_its_ready_line() -> None:
    """libqi printed "[W] ... qi.path.sdklayout: No Application was created"
    on standard output before ``armplan-sim ready URL``; a script reading the
    first line for the address read the warning."""
    url = f"tcp://127.0.0.1:{free_endpoint().rsplit(':', 1)[1]}"
    child = subprocess.Popen(
        [sys.executable, "-m", "armplan", "sim", "--listen", url],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline() == f"{READY} {url}\n"
    finally:
        child.terminate()
        child.wait(30)
