"""``armplan up`` and ``armplan status`` as real processes on free loopback ports.

Every test stops what it started: the launcher by signal, and anything left
by SIGKILL in a ``finally``.
"""

from __future__ import annotations

import contextlib
import json
import os
import pathlib
import queue
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import IO

import pytest

from armplan.cli.commands.status import _rows as status_rows
from armplan.launch import SERVICES, free_endpoint
from armplan.launch.robot import RobotStack
from shared.bus import Bus, BusConfig, load_config
from shared.bus.routes import ROUTES
from shared.errors import (
    ArmplanError,
    RequestTimeoutError,
    RobotUnavailableError,
    ServiceUnavailableError,
)
from shared.stop_signals import StartInterrupted, StopRequest

#: Longest wait for `armplan up` to be ready, and for processes to exit [s].
READY_TIMEOUT, EXIT_TIMEOUT = 120.0, 30.0
PID_LINE = re.compile(r"^(\w+)\s+pid (\d+)")


def armplan(*args: str, timeout: float = 60.0) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


class Up:
    """A running `armplan up`: its process and the PIDs it printed."""

    def __init__(self, process: subprocess.Popen[str], lines: queue.Queue[str]) -> None:
        self.process = process
        self.lines = lines
        self.pids: dict[str, int] = {}
        self.reader: threading.Thread | None = None  # copies stdout to lines

    def wait_ready(self) -> list[str]:
        """Read its stdout until the ready line; returns the lines read."""
        seen: list[str] = []
        deadline = time.monotonic() + READY_TIMEOUT
        while time.monotonic() < deadline:
            try:
                line = self.lines.get(timeout=0.5)
            except queue.Empty:
                assert self.process.poll() is None, f"armplan up exited: {seen}"
                continue
            seen.append(line)
            if match := PID_LINE.match(line):
                self.pids[match.group(1)] = int(match.group(2))
            if line.startswith("armplan up: ready"):
                return seen
        raise AssertionError(f"armplan up not ready in {READY_TIMEOUT} s: {seen}")


@contextmanager
def armplan_up(*args: str, log: pathlib.Path) -> Iterator[Up]:
    """Start `armplan up ARGS`; kill whatever is left on the way out."""
    with log.open("w") as err:
        process = subprocess.Popen(
            [sys.executable, "-m", "armplan", "up", *args],
            stdout=subprocess.PIPE,
            stderr=err,
            text=True,
        )
    lines: queue.Queue[str] = queue.Queue()
    reader = threading.Thread(target=pump, args=(process.stdout, lines), daemon=True)
    reader.start()
    up = Up(process, lines)
    up.reader = reader
    try:
        yield up
    finally:
        for pid in [process.pid, *up.pids.values()]:
            if not gone(pid):
                os.kill(pid, signal.SIGKILL)
        process.wait(EXIT_TIMEOUT)
        reader.join(EXIT_TIMEOUT)


def pump(stream: IO[str], lines: queue.Queue[str]) -> None:
    """Copy ``stream``'s lines into ``lines`` until it closes."""
    for line in stream:
        lines.put(line.rstrip("\n"))


def gone(pid: int) -> bool:
    """Whether ``pid`` no longer runs (absent, or a zombie awaiting its reaper)."""
    try:
        stat = pathlib.Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return True
    return stat.rsplit(")", 1)[1].split()[0] in ("Z", "X")


def wait_gone(pids: list[int], timeout: float = EXIT_TIMEOUT) -> list[int]:
    """Wait until every PID is gone; returns those still running."""
    deadline = time.monotonic() + timeout
    while (alive := [p for p in pids if not gone(p)]) and time.monotonic() < deadline:
        time.sleep(0.1)
    return alive


def assert_every_route_answers(endpoint: str) -> None:
    """Every route's service answers an empty request: a reply or a typed error."""
    with Bus.connect(load_config(endpoints=(endpoint,))) as bus:
        for route in ROUTES:
            try:
                bus.call(route, b"{}", timeout=30.0)
            except (ServiceUnavailableError, RequestTimeoutError):
                raise
            except ArmplanError as error:
                assert error.kind != "internal_error", error.message


def test_up_starts_everything_status_lists_it_sigterm_stops_it(
    tmp_path: pathlib.Path,
) -> None:
    """Every service comes alive, status lists them, SIGTERM leaves no process."""
    endpoint = free_endpoint()
    with armplan_up("--listen", endpoint, log=tmp_path / "up.log") as up:
        lines = up.wait_ready()
        assert f"listening on {endpoint}" in lines[0]
        assert set(up.pids) == {"router", *(s.name for s in SERVICES)}
        status = armplan("status", "--connect", endpoint, "--json", "--require", "ik")
        assert status.returncode == 0, status.stderr
        services = json.loads(status.stdout)["services"]
        assert {s["service"]: s["state"] for s in services} == {
            s.name: "alive" for s in SERVICES
        }
        assert {
            "service": "planner",
            "state": "alive",
            "keys": ["armplan/plan"],
        } in services
        # a service required but not alive: one JSON document, with the error
        # (it was the table, then the error: two documents, unreadable)
        short = armplan("status", "--connect", endpoint, "--json", "--require", "sim")
        assert short.returncode == 1
        document = json.loads(short.stdout)
        assert document["error"]["kind"] == "service_unavailable"
        assert len(document["services"]) == len(SERVICES)
        assert_every_route_answers(endpoint)
        up.process.send_signal(signal.SIGTERM)
        assert up.process.wait(EXIT_TIMEOUT) == 0
        assert wait_gone(list(up.pids.values()), timeout=1.0) == []


def test_sigint_stops_everything(tmp_path: pathlib.Path) -> None:
    """Ctrl-C (SIGINT) to the launcher stops the router and the services."""
    with armplan_up(
        "--listen", free_endpoint(), "--only", "ik", log=tmp_path / "up.log"
    ) as up:
        up.wait_ready()
        up.process.send_signal(signal.SIGINT)
        assert up.process.wait(EXIT_TIMEOUT) == 0
        assert wait_gone(list(up.pids.values()), timeout=1.0) == []


def test_a_killed_launcher_takes_its_children_along(tmp_path: pathlib.Path) -> None:
    """SIGKILL to the launcher: the children notice and exit on their own."""
    with armplan_up(
        "--listen", free_endpoint(), "--only", "ik", log=tmp_path / "up.log"
    ) as up:
        up.wait_ready()
        up.process.kill()
        up.process.wait(EXIT_TIMEOUT)
        assert wait_gone(list(up.pids.values())) == []


def test_status_without_a_router_names_the_endpoint() -> None:
    """No router: exit 1 and an error naming where it looked."""
    endpoint = free_endpoint()
    out = armplan("status", "--connect", endpoint)
    assert out.returncode == 1
    assert (
        f"service 'router' is unavailable: no Zenoh router answers at {endpoint}"
        in (out.stderr)
    )
    assert "or give the router's address with --connect" in out.stderr


def test_a_port_in_use_is_reported(tmp_path: pathlib.Path, busy_port: int) -> None:
    """The router cannot listen: armplan up exits 1 naming the router, and
    points at its output above (on the terminal, there is no log file: it
    said "see its log"), which says why."""
    out = armplan("up", "--listen", f"tcp/127.0.0.1:{busy_port}", "--only", "ik")
    assert out.returncode == 1
    last = out.stderr.splitlines()[-1]
    assert last.startswith("armplan: error: service 'router' is unavailable")
    assert last.endswith("exited with code 1 while starting (see its output above)")
    above = out.stderr[: out.stderr.index(last)]
    assert "Address already in use" in above


def test_a_second_up_on_the_same_port_fails_and_leaves_the_first_alone(
    tmp_path: pathlib.Path,
) -> None:
    """A router already answers on the port: the second armplan up's router
    cannot listen, and the second up exits 1 naming it, instead of starting
    its services on the first one's router (where its fit replaced the
    first's model)."""
    endpoint = free_endpoint()
    with armplan_up("--listen", endpoint, "--only", "ik", log=tmp_path / "a.log") as up:
        up.wait_ready()
        second = armplan("up", "--listen", endpoint, "--only", "ik")
        assert second.returncode == 1
        assert "armplan up: ready" not in second.stdout
        assert "service 'router' is unavailable" in second.stderr
        assert "Address already in use" in second.stderr
        assert up.process.poll() is None
        status = armplan("status", "--connect", endpoint, "--json")
        alive = [
            s for s in json.loads(status.stdout)["services"] if s["state"] == "alive"
        ]
        assert [s["service"] for s in alive] == ["ik"]  # one ik: the first up's


def test_the_sim_serves_where_asked(tmp_path: pathlib.Path) -> None:
    """--with-sim --sim-listen tcp://127.0.0.1:0: the sim on a free port (a
    NAO's 9559 may be taken), named on the sim's line, the bridge on it."""
    endpoint = free_endpoint()
    with armplan_up(
        "--listen",
        endpoint,
        "--only",
        "ik",
        "--with-sim",
        "--sim-listen",
        "tcp://127.0.0.1:0",
        log=tmp_path / "up.log",
    ) as up:
        lines = up.wait_ready()
        sim = next(line for line in lines if line.startswith("sim "))
        url = sim.rsplit(" ", 1)[1]
        assert url.startswith("tcp://127.0.0.1:") and url != "tcp://127.0.0.1:0"
        assert any(line.endswith(f"-> robot {url}") for line in lines)
        up.process.send_signal(signal.SIGINT)
        assert up.process.wait(EXIT_TIMEOUT) == 0


@pytest.mark.parametrize(
    "bad",
    [
        "--listen=127.0.0.1:7447",
        "--only=everything",
        "--with-sim --sim-listen=9559",
    ],
)
def test_bad_options_are_refused_before_starting(bad: str) -> None:
    """A malformed endpoint or unknown service: an error, nothing started."""
    out = armplan("up", *bad.split())
    assert out.returncode in (1, 2) and "error" in out.stderr
    assert "ready" not in out.stdout


def test_status_names_the_keys_of_the_bridge_started_on_request() -> None:
    """The bridge is no service of ``up``'s, yet status lists what it answers."""
    rows = status_rows([*(s.name for s in SERVICES), "bridge", "recorder", "x"], "ns")
    extra = {name: (state, keys) for name, state, keys in rows[len(SERVICES) :]}
    assert extra == {
        "bridge": ("alive", ["ns/bridge/execute", "ns/bridge/stop"]),
        "recorder": ("alive", []),
        "x": ("alive", []),
    }
    assert all(keys for _, _, keys in rows[: len(SERVICES)])


def test_a_misspelt_service_is_said_to_be_no_process_of_ours() -> None:
    """`status --require brige` or `replay --wait-for brige` used to read like a
    bridge that did not start; the message now says no process has the name."""
    from armplan.launch.catalog import unknown_hint

    assert unknown_hint(["brige", "ik"]) == (
        " (no armplan process is called 'brige'; ours: fit, decide, ik, timing, "
        "planner, recorder, bridge)"
    )
    assert unknown_hint(["bridge", "recorder", "planner"]) == ""
    assert unknown_hint(["sim"]) == (
        " ('sim' holds no liveliness token (it speaks NAOqi, not Zenoh))"
    )


def test_a_robot_and_the_sim_together_are_refused_before_anything_starts() -> None:
    """`up --with-sim --robot URL` started the router and all five services
    (about 5 s) before refusing the pair; now nothing starts."""
    endpoint = free_endpoint()
    out = armplan(
        "up", "--listen", endpoint, "--with-sim", "--robot", "tcp://127.0.0.1:9"
    )
    assert out.returncode == 1
    assert "were both asked for: choose one" in out.stderr
    assert "listening" not in out.stdout + out.stderr
    assert "ready" not in out.stdout + out.stderr


def test_a_secured_configuration_is_refused_before_anything_starts() -> None:
    """`up --config config/secure/router.json5` started its router, then its
    services waited a minute to log in and failed as if no router answered;
    `up` runs only the unsecured set, and now says so at once."""
    from shared.bus.config_file import REPO_CONFIG

    out = armplan("up", "--config", str(REPO_CONFIG.parent / "secure" / "router.json5"))
    assert out.returncode == 1
    assert "is a secured configuration (listen/endpoints, " in out.stderr
    assert "listening" not in out.stdout + out.stderr


def test_a_robot_side_process_that_exits_is_reported_with_its_code(
    tmp_path: pathlib.Path,
) -> None:
    """A service that exits is reported 'exited with code N'; the sim and the
    bridge were reported without one ('bridge (pid N) exited'). Stopped,
    `up` exits 1 naming it (it exited 0: a supervisor could not tell)."""
    log = tmp_path / "up.log"
    sim_at = f"tcp://127.0.0.1:{free_endpoint().rsplit(':', 1)[1]}"
    args = ("--listen", free_endpoint(), "--only", "ik", "--with-sim")
    with armplan_up(*args, "--sim-listen", sim_at, log=log) as up:
        up.wait_ready()
        os.kill(up.pids["sim"], signal.SIGKILL)
        deadline = time.monotonic() + 10.0
        wanted = f"armplan up: sim (pid {up.pids['sim']}) exited with code -9"
        while wanted not in log.read_text() and time.monotonic() < deadline:
            time.sleep(0.1)
        assert wanted in log.read_text()
        up.process.send_signal(signal.SIGTERM)
        assert up.process.wait(EXIT_TIMEOUT) == 1
        assert last_line(up) == (
            "armplan up: stopped every process; exited while running: "
            f"sim (pid {up.pids['sim']}) with code -9"
        )


def last_line(up: Up) -> str:
    """The last line `up` printed on stdout, once it has exited."""
    assert up.reader is not None
    up.reader.join(EXIT_TIMEOUT)  # its stdout closed: every line is queued
    lines = [up.lines.get_nowait() for _ in range(up.lines.qsize())]
    return lines[-1]


def test_a_router_that_dies_makes_up_exit_1(tmp_path: pathlib.Path) -> None:
    """The router killed while `up` ran: `up` ran on and exited 0 at its stop,
    so a supervisor (systemd Restart=on-failure, docker) never knew. It now
    exits 1 and names the router on its last line; nothing is restarted."""
    args = ("--listen", free_endpoint(), "--only", "ik")
    with armplan_up(*args, log=tmp_path / "up.log") as up:
        up.wait_ready()
        router = up.pids["router"]
        os.kill(router, signal.SIGKILL)
        deadline = time.monotonic() + 10.0
        wanted = f"armplan up: router (pid {router}) exited with code -9"
        while wanted not in (tmp_path / "up.log").read_text():
            assert time.monotonic() < deadline, "the router's end was not reported"
            time.sleep(0.1)
        up.process.send_signal(signal.SIGTERM)
        assert up.process.wait(EXIT_TIMEOUT) == 1
        assert last_line(up) == (
            "armplan up: stopped every process; exited while running: "
            f"router (pid {router}) with code -9"
        )
        assert wait_gone(list(up.pids.values()), timeout=1.0) == []


def test_up_passes_allow_not_awake_to_the_bridge(tmp_path: pathlib.Path) -> None:
    """`up --robot URL --allow-not-awake`: the option was the bridge's alone
    (`python -m bridge.serve`), and `up` refused it as unknown; now its
    bridge plays on a robot at rest. Without a bridge to give it to, it is
    refused before anything starts."""
    from bridge.minimum_jerk import minimum_jerk_trajectory
    from bridge.sim import SimProcess
    from shared.bus.robot_routes import EXECUTE
    from shared.libqi import qi
    from shared.messages import ExecuteRequest
    from shared.robot.postures import forward, rest

    out = armplan("up", "--listen", free_endpoint(), "--allow-not-awake")
    assert out.returncode in (1, 2) and "--allow-not-awake" in out.stderr
    assert "ready" not in out.stdout
    endpoint = free_endpoint()
    with SimProcess() as sim:
        session = qi.Session()
        session.connect(sim.url)
        session.service("ALMotion").rest()
        session.close()
        with armplan_up(
            "--listen",
            endpoint,
            "--only",
            "ik",
            "--robot",
            sim.url,
            "--allow-not-awake",
            log=tmp_path / "up.log",
        ) as up:
            up.wait_ready()
            reach = minimum_jerk_trajectory(
                "right", [rest("right"), forward("right")], [1.0]
            )
            with Bus.connect(load_config(endpoints=(endpoint,))) as bus:
                reply = bus.call(EXECUTE, ExecuteRequest(trajectory=reach), timeout=30)
            assert reply.frames > 0
            up.process.send_signal(signal.SIGINT)
            assert up.process.wait(EXIT_TIMEOUT) == 0


def test_a_service_named_twice_is_refused_before_anything_starts() -> None:
    """`up --only ik ik` started two ik processes and tracked one: the banner
    printed one PID twice, and SIGTERM said "stopped every process" with the
    other still running. Now the names are refused, nothing started."""
    out = armplan("up", "--listen", free_endpoint(), "--only", "ik", "timing", "ik")
    assert (out.returncode, out.stdout) == (1, "")
    assert out.stderr == (
        "armplan: error: service 'ik' named more than once: name each service "
        "once (each runs as one process)\n"
    )


def test_the_launcher_refuses_a_service_named_twice() -> None:
    """The API's guard: nothing is started, the error lists each name once."""
    from armplan.launch import Launcher
    from shared.errors import InvalidInputError

    config = load_config(endpoints=(free_endpoint(),))
    with pytest.raises(InvalidInputError) as caught:
        Launcher(config, ["fit", "ik", "fit", "ik", "fit"])
    assert caught.value.message.startswith("services 'fit', 'ik' named more than once")
    assert caught.value.evidence["services"] == ["fit", "ik"]


def children_of(pid: int) -> dict[int, str]:
    """The command lines of ``pid``'s child processes, by PID."""
    found = {}
    for stat in pathlib.Path("/proc").glob("[0-9]*/stat"):
        try:
            ppid = int(stat.read_text().rsplit(")", 1)[1].split()[1])
            command = (stat.parent / "cmdline").read_bytes()
        except (OSError, IndexError, ValueError):
            continue
        if ppid == pid:
            found[int(stat.parent.name)] = command.replace(b"\0", b" ").decode()
    return found


def hold_fit_at_start(up: subprocess.Popen[str], model: pathlib.Path) -> int:
    """Wait until `up`'s fit process reads its --model FIFO; our end of it.

    The fit process then waits for a model that never comes (the returned
    write end is kept open), and `up` waits for fit to come alive: it is
    starting for as long as the test wants.
    """
    deadline = time.monotonic() + READY_TIMEOUT
    while time.monotonic() < deadline:
        assert up.poll() is None, "armplan up exited while starting"
        # `up` read the model before it started anything: once fit runs, the
        # only reader can be fit; the open fails (ENXIO) until it reads
        if any("services.fit" in c for c in children_of(up.pid).values()):
            with contextlib.suppress(OSError):
                return os.open(model, os.O_WRONLY | os.O_NONBLOCK)
        time.sleep(0.05)
    raise AssertionError("the fit process never opened its model")


@pytest.mark.parametrize(
    ("signum", "code", "said"),
    [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")],
)
def test_a_signal_while_starting_is_reported_as_that_signal(
    signum: signal.Signals, code: int, said: str, tmp_path: pathlib.Path
) -> None:
    """Ctrl-C while `up` started exited 1, "service 'launcher' is unavailable:
    stopped by a signal while starting"; now 130 "interrupted" (SIGTERM: 143
    "terminated"), as `armplan demo`, with everything it started stopped.

    `up` is held starting for sure: fit's --model is a named pipe that `up`
    reads the model from once, and that the fit process then waits on."""
    model = tmp_path / "model.fifo"
    os.mkfifo(model)
    shipped = (pathlib.Path(__file__).parent.parent / "services" / "fit").joinpath(
        "default_model.json"
    )
    feeder = threading.Thread(
        target=lambda: model.write_text(shipped.read_text()), daemon=True
    )
    feeder.start()  # `up`'s own check of the model reads it
    argv = ["up", "--listen", free_endpoint(), "--only", "fit", "--model", str(model)]
    with (tmp_path / "up.log").open("w") as err:
        up = subprocess.Popen(
            [sys.executable, "-m", "armplan", *argv],
            stdout=subprocess.PIPE,
            stderr=err,
            text=True,
        )
    held = None
    try:
        held = hold_fit_at_start(up, model)
        children = list(children_of(up.pid))
        assert len(children) == 2  # the router and fit
        up.send_signal(signum)
        out, _ = up.communicate(timeout=EXIT_TIMEOUT)
        assert (up.returncode, out) == (code, "")
        assert (tmp_path / "up.log").read_text().endswith(f"\narmplan: {said}\n")
        assert wait_gone(children) == []
    finally:
        if held is not None:
            os.close(held)
        if up.poll() is None:
            up.kill()
            up.wait(EXIT_TIMEOUT)


def test_a_sim_ended_by_the_stop_asked_for_is_an_interrupted_start(
    busy_port: int,
) -> None:
    """A Ctrl-C to the terminal's group reaches a sim still starting: it dies
    and ``armplan up --with-sim`` exited 1, "robot unavailable", with the
    sim's traceback. With the stop asked for, the sim's end is that stop
    (StartInterrupted: 130); without, it is the robot's failure. The sim
    fails here on a port in use; nothing else needs starting."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace="simstop")
    listen = f"tcp://127.0.0.1:{busy_port}"
    with pytest.raises(RobotUnavailableError):
        RobotStack(config, sim=True, sim_listen=listen).start(timeout=60)
    stop = StopRequest()
    stop.request(signal.SIGINT)
    with pytest.raises(StartInterrupted) as interrupted:
        RobotStack(config, sim=True, sim_listen=listen, stop=stop).start(timeout=60)
    assert interrupted.value.signal == signal.SIGINT


@pytest.mark.parametrize("bridge", [(), ("--with-bridge",)])
def test_sim_listen_without_the_sim_is_refused(bridge: tuple[str, ...]) -> None:
    """`up --with-bridge --sim-listen URL` pointed the bridge at the default
    robot (127.0.0.1:9559), and `--sim-listen` alone started no sim; either
    was silent. Now the option is refused without --with-sim, nothing
    started."""
    sim_at = "tcp://127.0.0.1:0"
    argv = ("--listen", free_endpoint(), "--only", "ik", *bridge)
    out = armplan("up", *argv, "--sim-listen", sim_at, timeout=30.0)
    assert (out.returncode, out.stdout) == (1, "")
    assert out.stderr == (
        "armplan: error: --sim-listen is where the simulated NAO serves: add "
        "--with-sim to start it (a bridge to another robot: --robot URL)\n"
    )


def test_an_endpoint_given_twice_is_refused_before_anything_starts() -> None:
    """`up --listen E --listen E` started a router that clashed with itself
    ("Address already in use; is another router using it?"); now the
    endpoint is named as given twice, nothing started."""
    endpoint = free_endpoint()
    out = armplan("up", "--listen", endpoint, "--listen", endpoint, "--only", "ik")
    assert (out.returncode, out.stdout) == (1, "")
    assert out.stderr == (
        f"armplan: error: --listen {endpoint} given more than once: the router "
        "cannot listen twice on one endpoint; give each once\n"
    )


def test_an_endpoint_spelt_twice_is_refused_before_anything_starts() -> None:
    """`up --listen tcp/127.0.0.1:P --listen tcp/localhost:P` is one socket
    twice: the router clashed with itself and the error suggested another
    router on the port. Now both spellings are named, nothing started."""
    endpoint = free_endpoint()
    other = endpoint.replace("127.0.0.1", "localhost")
    out = armplan("up", "--listen", endpoint, "--listen", other, "--only", "ik")
    assert (out.returncode, out.stdout) == (1, "")
    assert out.stderr == (
        f"armplan: error: --listen {endpoint} and {other} are one socket (one "
        "transport, port and address): the router cannot listen twice on it; "
        "give one of them\n"
    )


def test_an_endpoint_without_a_protocol_is_said_to_be_malformed() -> None:
    """`up --listen 127.0.0.1:P` was refused as a protocol other than tcp/
    ("which 127.0.0.1:P/ is not"); its syntax is now checked first, as
    `status --connect` does."""
    endpoint = free_endpoint().removeprefix("tcp/")
    out = armplan("up", "--listen", endpoint, "--only", "ik")
    assert (out.returncode, out.stdout) == (1, "")
    assert out.stderr == (
        "armplan: error: Zenoh configuration --listen (endpoint): endpoint "
        f"'{endpoint}' must read PROTO/HOST:PORT, e.g. tcp/127.0.0.1:7447\n"
    )
