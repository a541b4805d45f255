"""The secured router: TLS, a password per process, access control.

The first tests read the access rules (config/secure/router.json5) and check
them against the catalogue; the others run the real router with a bundle
from `armplan certs` on loopback, the stage services and the planner as
their own users, and show what is refused and what works.
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
import shutil
import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest
import zenoh
from native_processes import Native, stop_all

from armplan.cli.main import main
from armplan.launch import catalog, free_endpoint
from armplan.secure import (
    TEMPLATE,
    AccessControl,
    Bundle,
    SecureSetupError,
    write_bundle,
)
from bridge.claim import claim_key, sole_bridge
from services.recorder import RecorderOptions
from services.recorder.bridge_watch import LIVE_CHUNKS
from services.recorder.service import Recorder
from shared.bus import Bus, BusConfig, ServiceHost, load_config
from shared.bus.robot_routes import EXECUTE, STOP
from shared.bus.routes import FIT_MODEL, IK_SOLVE, PLAN, ROUTES, TRAJECTORY_TOPIC
from shared.bus.topics import BRIDGE_FRAMES_TOPIC, TOPICS
from shared.errors import (
    RequestTimeoutError,
    ServiceRunningError,
    ServiceUnavailableError,
)
from shared.messages import IKRequest, PlanRequest, StopRequest, Trajectory
from shared.recording import read_records

NS = "armplan"
ACL = AccessControl.from_file(TEMPLATE)
USERS = ACL.usernames()
#: Users that are armplan processes (not another machine's router).
PROCESS_USERS = [u for u in USERS if u != "router"]
ROUTE_KEYS = [f"{NS}/{r.path}" for r in (*ROUTES, EXECUTE, STOP)]
REACH = PlanRequest.model_validate({"targets": [{"position": (0.12, -0.10, 0.05)}]})
#: How long a refused message is waited for before concluding it never comes [s].
QUIET = 1.0


# ---- the rules, read from the file ------------------------------------------


def test_every_process_of_the_catalog_has_a_user() -> None:
    """Each Zenoh process (and the client) logs in as a user the rules know."""
    zenoh_processes = [s.name for s in catalog.PROCESSES if s.name != "sim"]
    assert sorted(PROCESS_USERS) == sorted([*zenoh_processes, "client"])


@pytest.mark.parametrize("route", [*ROUTES, EXECUTE, STOP], ids=lambda r: r.path)
def test_each_route_is_served_by_its_service_only(route: Any) -> None:
    """Only the route's service may declare its queryable and answer on it."""
    key = route.key(NS)
    for user in PROCESS_USERS:
        serves = user == route.service
        assert ACL.allows(user, "declare_queryable", "ingress", key) is serves, user
        assert ACL.allows(user, "reply", "ingress", key) is serves, user
        assert ACL.allows(user, "query", "egress", key) is serves, user


@pytest.mark.parametrize("topic", TOPICS, ids=lambda t: t.path)
def test_each_topic_is_published_by_its_publisher_only(topic: Any) -> None:
    """Only the topic's publisher may put on it; the recorder receives it."""
    key = topic.key(NS)
    for user in PROCESS_USERS:
        assert ACL.allows(user, "put", "ingress", key) is (user == topic.publisher)
    assert ACL.allows("recorder", "put", "egress", key)


def test_only_the_planner_may_publish_trajectories() -> None:
    """No user but the planner may put (or delete) on armplan/plan/trajectory."""
    key = f"{NS}/{TRAJECTORY_TOPIC}"
    for user in PROCESS_USERS:
        assert ACL.allows(user, "put", "ingress", key) is (user == "planner")
        assert not ACL.allows(user, "delete", "ingress", key)


def test_only_the_bridge_is_on_the_robot_keys() -> None:
    """No user but the bridge may publish, answer or ask on armplan/bridge/**."""
    keys = [EXECUTE.key(NS), f"{NS}/{BRIDGE_FRAMES_TOPIC}", f"{NS}/bridge/other"]
    for user in PROCESS_USERS:
        for key in keys:
            for message in ("put", "delete", "declare_queryable", "reply", "query"):
                allowed = ACL.allows(user, message, "ingress", key)
                assert allowed is (
                    user == "bridge" and message != "delete" and (message != "query")
                ), (user, message, key)


def test_every_login_that_may_publish_to_a_bridge_may_watch_for_one() -> None:
    """A replay of every key stops when a bridge comes alive: it watches the
    bridge's token (``services.recorder.service_watch``). A login that may put
    a ``plan/*`` or ``bridge/*`` key but not see that token would see no
    bridge, and send a whole recording to a live robot."""
    token = f"{NS}/alive/bridge"
    paths = [t.path for t in TOPICS if t.path.split("/")[0] in LIVE_CHUNKS]
    publishers = {
        u for u in USERS for p in paths if ACL.allows(u, "put", "ingress", f"{NS}/{p}")
    }
    assert "planner" in publishers and "bridge" in publishers
    for user in sorted(publishers):
        for message in ("liveliness_query", "declare_liveliness_subscriber"):
            assert ACL.allows(user, message, "ingress", token), (user, message)


def test_only_the_client_may_ask_the_bridge_to_stop() -> None:
    """armplan/bridge/stop: the client (the operator) asks, the bridge answers;
    no other user asks it, and nobody asks armplan/bridge/execute."""
    for user in PROCESS_USERS:
        asks = ACL.allows(user, "query", "ingress", STOP.key(NS))
        assert asks is (user == "client"), user
        answered = ACL.allows(user, "reply", "egress", STOP.key(NS))
        assert answered is (user == "client"), user
        assert not ACL.allows(user, "query", "ingress", EXECUTE.key(NS)), user
    assert ACL.allows("bridge", "query", "egress", STOP.key(NS))
    assert ACL.allows("bridge", "reply", "ingress", STOP.key(NS))


def test_clients_may_only_ask_for_plans_and_stops_and_read_results() -> None:
    """The client asks armplan/plan and armplan/bridge/stop only, publishes
    nothing, reads results."""
    asks = [k for k in ROUTE_KEYS if ACL.allows("client", "query", "ingress", k)]
    assert asks == [PLAN.key(NS), STOP.key(NS)]
    for key in [*ROUTE_KEYS, *(t.key(NS) for t in TOPICS)]:
        assert not ACL.allows("client", "put", "ingress", key)
        assert not ACL.allows("client", "declare_queryable", "ingress", key)
    assert ACL.allows("client", "put", "egress", f"{NS}/{TRAJECTORY_TOPIC}")
    assert ACL.allows("client", "put", "egress", f"{NS}/bridge/report")
    assert not ACL.allows("client", "put", "egress", f"{NS}/fit/model/update")


def test_the_recorder_asks_only_for_the_served_model() -> None:
    """The recorder may ask armplan/fit/model (once, at its start) and be
    answered; no other route, the robot's included."""
    asks = [k for k in ROUTE_KEYS if ACL.allows("recorder", "query", "ingress", k)]
    assert asks == [FIT_MODEL.key(NS)]
    assert ACL.allows("recorder", "reply", "egress", FIT_MODEL.key(NS))
    assert not ACL.allows("recorder", "reply", "egress", PLAN.key(NS))


def test_each_process_holds_only_its_own_token() -> None:
    """A process may declare armplan/alive/<its name> and no other token."""
    for user in PROCESS_USERS:
        for other in PROCESS_USERS:
            key = f"{NS}/alive/{other}"
            mine = user == other and user != "client"
            assert ACL.allows(user, "liveliness_token", "ingress", key) is mine


def test_every_session_holds_a_caller_token_the_planner_and_bridge_watch() -> None:
    """armplan/caller/<session id>: any login may hold one (each Bus does);
    only the planner and the bridge may watch them go (they publish no plan,
    and start no movement, for a caller whose session ended)."""
    key = f"{NS}/caller/8f3a09"
    for user in PROCESS_USERS:
        assert ACL.allows(user, "liveliness_token", "ingress", key)
        watches = ACL.allows(user, "declare_liveliness_subscriber", "ingress", key)
        assert watches is (user in ("planner", "bridge")), user


def test_only_the_bridge_claims_the_robot() -> None:
    """Only the bridge may hold and look up a bridge's claim (bridge/claim.py)."""
    key = claim_key(NS, 1, "0a")
    for user in PROCESS_USERS:
        mine = user == "bridge"
        assert ACL.allows(user, "liveliness_token", "ingress", key) is mine
        assert ACL.allows(user, "liveliness_query", "ingress", key) is mine


def test_the_evaluator_can_say_no() -> None:
    """Deny wins over allow, unknown users get the default permission."""
    section = {
        "enabled": True,
        "default_permission": "deny",
        "rules": [
            {
                "id": "a",
                "messages": ["put"],
                "permission": "allow",
                "key_exprs": ["x/**"],
            },
            {
                "id": "d",
                "messages": ["put"],
                "permission": "deny",
                "key_exprs": ["x/y"],
            },
        ],
        "subjects": [{"id": "s", "usernames": ["u"]}],
        "policies": [{"rules": ["a", "d"], "subjects": ["s"]}],
    }
    acl = AccessControl(section)
    assert acl.allows("u", "put", "ingress", "x/z")
    assert not acl.allows("u", "put", "ingress", "x/y")
    assert not acl.allows("nobody", "put", "ingress", "x/z")


# ---- the command --------------------------------------------------------------


def test_armplan_certs_writes_the_compose_bundle(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`armplan certs --compose`: the template unchanged, secrets owner-only."""
    assert main(["certs", "--out", str(tmp_path), "--compose"]) == 0
    assert (tmp_path / "router.json5").read_text() == TEMPLATE.read_text()
    client = load_config(tmp_path / "client.json5")
    assert client.endpoints == ("tls/router:7447",)
    settings = dict(client.client_settings)
    assert settings["transport/auth/usrpwd/user"] == '"client"'
    ca_inside = settings["transport/link/tls/root_ca_certificate"]
    assert ca_inside == '"/run/armplan/secure/ca.pem"'
    secrets = ["ca.key", "router.key", "passwords.txt", "router.json5"]
    secrets += [f"{user}.json5" for user in PROCESS_USERS]
    modes = {name: (tmp_path / name).stat().st_mode & 0o777 for name in secrets}
    assert modes == dict.fromkeys(secrets, 0o600)
    assert "client.json5" in capsys.readouterr().out


def test_armplan_certs_refuses_a_plain_endpoint(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A tcp/ endpoint is a typed error, and nothing is written."""
    argv = ["certs", "--out", str(tmp_path / "out"), "--endpoint", "tcp/10.0.0.1:7447"]
    assert main(argv) == 1
    assert capsys.readouterr().err == (
        "armplan: error: endpoint 'tcp/10.0.0.1:7447' must use tls/, "
        "e.g. tls/127.0.0.1:7447\n"
    )
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("days", ["0", "-5", "1000000000"])
def test_armplan_certs_refuses_a_validity_out_of_range(
    days: str, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--days outside 1..36500 is a typed error naming the range (openssl's own
    message for 1e9 days was just "-----"), and nothing is written."""
    assert main(["certs", "--out", str(tmp_path / "out"), "--days", days]) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: certificates must be valid 1..36500 days, got {days}\n"
    )
    assert not (tmp_path / "out").exists()


def test_passwords_are_kept_and_a_bad_line_is_named(tmp_path: pathlib.Path) -> None:
    """A second bundle in the same folder keeps the users' passwords."""
    first = write_bundle(tmp_path, endpoint="tls/127.0.0.1:7447")
    before = (tmp_path / "passwords.txt").read_text()
    again = write_bundle(tmp_path, endpoint="tls/127.0.0.1:7447")
    assert (tmp_path / "passwords.txt").read_text() == before
    assert first.authority_created and not again.authority_created
    (tmp_path / "passwords.txt").write_text(before + "no password here\n")
    with pytest.raises(SecureSetupError) as raised:
        write_bundle(tmp_path)
    assert raised.value.message == (
        f"{tmp_path / 'passwords.txt'} line {len(USERS) + 1} is not user:password"
    )


# ---- the real router ---------------------------------------------------------


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Bundle:
    """A bundle from `armplan certs` for a router on a free loopback TLS port."""
    port = free_endpoint().rsplit(":", 1)[1]
    folder = tmp_path_factory.mktemp("secure")
    return write_bundle(folder, endpoint=f"tls/127.0.0.1:{port}")


def user_config(bundle: Bundle, user: str, **settings: str) -> BusConfig:
    """The user's client configuration, with some client settings replaced."""
    config = load_config(bundle.clients[user])
    given = dict(config.client_settings)
    given.update({k: json.dumps(v) for k, v in settings.items()})
    return dataclasses.replace(config, client_settings=tuple(given.items()))


@pytest.fixture(scope="module")
def secured(
    bundle: Bundle, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[Bundle]:
    """The secured router and the planner's services, each logged in as itself."""
    logs = tmp_path_factory.mktemp("logs")
    started: list[Native] = []
    try:
        router = ["python", "-m", catalog.ROUTER_MODULE]
        router += ["--config", str(bundle.router_config)]
        started.append(Native("router", router, logs / "router.log"))
        for spec in catalog.SERVICES:
            argv = ["python", "-m", spec.module, "--wait", "30"]
            argv += ["--config", str(bundle.clients[spec.name])]
            started.append(Native(spec.name, argv, logs / f"{spec.name}.log"))
        with Bus.connect(load_config(bundle.clients["client"]), wait=30) as bus:
            missing = bus.wait_alive([s.name for s in catalog.SERVICES], 120)
        assert not missing, [p.output() for p in started]
        yield bundle
        for process in started:
            assert process.running(), f"{process.name} died: {process.output()}"
    finally:
        stop_all(started)


class Inbox:
    """The payloads a session receives on a key."""

    def __init__(self, bus: Bus, key: str) -> None:
        self.payloads: list[bytes] = []
        self._arrived = threading.Condition()
        self._subscriber = bus.session.declare_subscriber(key, self._on_sample)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        with self._arrived:
            self.payloads.append(sample.payload.to_bytes())
            self._arrived.notify_all()

    def wait_for(self, payload: bytes, timeout: float) -> bool:
        with self._arrived:
            return self._arrived.wait_for(lambda: payload in self.payloads, timeout)

    def wait_for_route(self, sender: Bus, key: str, timeout: float) -> bool:
        """Put numbered payloads from ``sender`` until one arrives here."""
        deadline = time.monotonic() + timeout
        number = 0
        while time.monotonic() < deadline:
            number += 1
            payload = f"route probe {number}".encode()
            sender.session.put(key, payload)
            if self.wait_for(payload, 0.2):
                return True
        return False


def refused_to_open(config: BusConfig) -> bool:
    try:
        Bus.connect(config).close()
    except ServiceUnavailableError:
        return True
    return False


def test_a_wrong_password_is_refused(secured: Bundle) -> None:
    """Wrong password, unknown user, no login: no session at all. The error
    names a refused login beside a missing router (it said only 'no Zenoh
    router answers ... start one with armplan up', with one running)."""
    password = "transport/auth/usrpwd/password"
    wrong = user_config(secured, "client", **{password: "wrong"})
    assert refused_to_open(wrong)
    with pytest.raises(ServiceUnavailableError) as caught:
        Bus.connect(wrong)
    assert "refuses this client: check the user, password" in caught.value.message
    assert refused_to_open(
        user_config(secured, "client", **{"transport/auth/usrpwd/user": "intruder"})
    )
    anonymous = dataclasses.replace(
        load_config(secured.clients["client"]),
        client_settings=(
            ("transport/link/tls/root_ca_certificate", json.dumps(str(ca(secured)))),
        ),
    )
    assert refused_to_open(anonymous)


def ca(bundle: Bundle) -> pathlib.Path:
    return bundle.directory / "ca.pem"


def test_plain_tcp_and_untrusted_tls_are_refused(secured: Bundle) -> None:
    """The router speaks TLS only, with a certificate the client must trust."""
    config = load_config(secured.clients["client"])
    plain = config.with_endpoints((config.endpoint.replace("tls/", "tcp/", 1),), "test")
    assert refused_to_open(plain)
    other_ca = write_bundle(secured.directory / "other", endpoint=config.endpoint)
    assert refused_to_open(
        user_config(
            secured,
            "client",
            **{"transport/link/tls/root_ca_certificate": str(ca(other_ca))},
        )
    )


def test_an_authorised_client_plans_over_tls(secured: Bundle) -> None:
    """The client gets a trajectory; the recorder sees the planner publish it."""
    with (
        Bus.connect(load_config(secured.clients["recorder"])) as recorder,
        Bus.connect(load_config(secured.clients["client"])) as client,
    ):
        inbox = Inbox(recorder, f"{NS}/{TRAJECTORY_TOPIC}")
        trajectory = client.call(PLAN, REACH, timeout=60.0)
        assert isinstance(trajectory, Trajectory) and trajectory.times[-1] > 0.3
        assert inbox.wait_for(trajectory.to_json().encode(), 10.0)


def test_a_client_cannot_publish_a_trajectory(secured: Bundle) -> None:
    """A client's trajectory never reaches the recorder; the planner's does."""
    key = f"{NS}/{TRAJECTORY_TOPIC}"
    with (
        Bus.connect(load_config(secured.clients["recorder"])) as recorder,
        Bus.connect(load_config(secured.clients["client"])) as client,
        Bus.connect(load_config(secured.clients["planner"])) as planner,
    ):
        inbox = Inbox(recorder, key)
        # The recorder's subscription reaches the router a moment after it is
        # declared: the planner publishes until it is heard, so the route
        # exists when the client tries (a forgery lost for want of a route
        # would prove nothing).
        deadline = time.monotonic() + 10.0
        planner.session.put(key, b"from the planner")
        while not inbox.wait_for(b"from the planner", 0.2):
            assert time.monotonic() < deadline, "the planner's trajectory never came"
            planner.session.put(key, b"from the planner")
        client.session.put(key, b"forged by the client")
        assert not inbox.wait_for(b"forged by the client", QUIET)


def test_a_client_cannot_reach_the_robot_keys(secured: Bundle) -> None:
    """A client can neither publish frames nor ask the bridge to execute."""
    frames = f"{NS}/{BRIDGE_FRAMES_TOPIC}"
    asked: list[str] = []
    with (
        Bus.connect(load_config(secured.clients["recorder"])) as recorder,
        Bus.connect(load_config(secured.clients["client"])) as client,
        Bus.connect(load_config(secured.clients["bridge"])) as bridge,
    ):
        inbox = Inbox(recorder, frames)
        queryable = bridge.session.declare_queryable(
            EXECUTE.key(NS), lambda query: asked.append(str(query.key_expr))
        )
        time.sleep(0.3)
        client.session.put(frames, b"forged frames")
        bridge.session.put(frames, b"the bridge's frames")
        assert inbox.wait_for(b"the bridge's frames", 10.0)
        assert not inbox.wait_for(b"forged frames", QUIET)
        replies = list(
            client.session.get(EXECUTE.key(NS), payload=b"{}", timeout=QUIET)
        )
        assert replies == [] and asked == []
        queryable.undeclare()  # type: ignore[no-untyped-call]


def test_a_secured_recording_holds_the_model_served_at_its_start(
    secured: Bundle, tmp_path: pathlib.Path
) -> None:
    """Logged in as the recorder, a recording started after the fit service
    asks it for its model and records it (the rules let the query through)."""
    out = tmp_path / "secured.mcap"
    with Bus.connect(load_config(secured.clients["recorder"])) as bus:
        recorder = Recorder(bus, RecorderOptions(output=out)).start()
        assert recorder.model_at_start is not None
        recorder.model_at_start.join(30.0)
        time.sleep(0.3)  # the answer reaches the writer
        recorder.stop()
    assert recorder.model_at_start.recorded
    topics = [(r.topic, r.schema) for r in read_records(out)]
    assert (FIT_MODEL.key(NS), "MotionModel") in topics


def test_a_client_may_stop_the_arm_but_not_move_it(secured: Bundle) -> None:
    """The client's bridge/stop reaches the bridge and is answered (the
    operator's stop); its bridge/execute never arrives."""
    from bridge.naoqi_client import NaoqiClient
    from bridge.robot_bridge import RobotBridge
    from bridge.service import BridgeService

    robot = NaoqiClient(f"tcp://127.0.0.1:{free_endpoint().rsplit(':', 1)[1]}")
    with (
        Bus.connect(load_config(secured.clients["bridge"])) as served,
        Bus.connect(load_config(secured.clients["client"])) as client,
    ):
        service = BridgeService(served, RobotBridge(robot))
        with ServiceHost(served, "bridge", service.endpoints()):
            assert not client.wait_alive(["bridge"], 10.0)
            reply = client.call(STOP, StopRequest(reason="secured"), timeout=5.0)
            assert (reply.playing, reply.stopped, reply.reason) == (
                False,
                False,
                "secured",
            )
            started = time.monotonic()
            with pytest.raises((ServiceUnavailableError, RequestTimeoutError)):
                client.call(EXECUTE, b"{}", timeout=2.0)
            assert time.monotonic() - started < 3.0
    robot.close()


def test_a_client_cannot_ask_the_stage_services(secured: Bundle) -> None:
    """The client's query to ik never arrives: a typed error, fast."""
    request = IKRequest.model_validate({"target": (0.12, -0.13, 0.05)})
    with Bus.connect(load_config(secured.clients["client"])) as client:
        started = time.monotonic()
        with pytest.raises((ServiceUnavailableError, RequestTimeoutError)):
            client.call(IK_SOLVE, request, timeout=2.0)
        assert time.monotonic() - started < 3.0


def test_nobody_impersonates_the_planner(secured: Bundle) -> None:
    """A client's queryable on armplan/plan gets no query; the real planner answers."""
    impostor: list[str] = []
    with (
        Bus.connect(load_config(secured.clients["client"])) as client,
        Bus.connect(load_config(secured.clients["client"])) as other,
    ):
        queryable = other.session.declare_queryable(
            PLAN.key(NS), lambda query: impostor.append(str(query.key_expr))
        )
        time.sleep(0.3)
        assert isinstance(client.call(PLAN, REACH, timeout=60.0), Trajectory)
        queryable.undeclare()  # type: ignore[no-untyped-call]
    assert impostor == []


def test_of_two_bridges_claiming_at_once_one_gives_way(secured: Bundle) -> None:
    """Logged in as the bridge, two sessions claim the robot at once: the
    access rules let the claims through, so one gives way (were they
    denied, both would see none and both would run)."""
    outcomes: dict[int, str] = {}
    together = threading.Barrier(2)

    def claim(number: int) -> None:
        with Bus.connect(load_config(secured.clients["bridge"])) as bus:
            together.wait(30.0)
            try:
                with sole_bridge(bus, threading.Event()):
                    outcomes[number] = "runs"
                    time.sleep(1.0)  # held while the other looks
            except ServiceRunningError:
                outcomes[number] = "gave way"

    threads = [threading.Thread(target=claim, args=(n,)) for n in (0, 1)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(60.0)
    assert sorted(outcomes.values()) == ["gave way", "runs"]


def test_a_service_holds_no_other_token(secured: Bundle) -> None:
    """ik cannot declare the planner's liveliness token (or the bridge's)."""
    with (
        Bus.connect(load_config(secured.clients["ik"])) as ik,
        Bus.connect(load_config(secured.clients["client"])) as client,
    ):
        token = ik.session.liveliness().declare_token(f"{NS}/alive/bridge")
        time.sleep(QUIET)
        assert "bridge" not in client.alive()
        assert "planner" in client.alive()
        token.undeclare()  # type: ignore[no-untyped-call]


def test_the_planner_sees_a_callers_session_end(secured: Bundle) -> None:
    """A client's caller token goes when its session closes: a session
    logged in as the planner sees it go; one logged in as ik may not watch."""
    with (
        Bus.connect(load_config(secured.clients["planner"])) as planner,
        Bus.connect(load_config(secured.clients["ik"])) as ik,
    ):
        planner.caller_gone(None)  # the watches start
        ik.caller_gone(None)
        time.sleep(QUIET)
        client = Bus.connect(load_config(secured.clients["client"]))
        caller = str(client.session.zid())
        time.sleep(QUIET)
        assert not planner.caller_gone(caller)
        client.close()
        deadline = time.monotonic() + 10.0
        while not planner.caller_gone(caller) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert planner.caller_gone(caller)
        assert not ik.caller_gone(caller)


# ---- a second machine's router ----------------------------------------------


@pytest.fixture(scope="module")
def second_router(
    secured: Bundle, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[Bundle]:
    """Router B on another loopback port, connected to the secured router A.

    B's bundle is made the documented way: A's authority and password file
    copied into B's folder, then `armplan certs --connect A's endpoint`.
    """
    folder = tmp_path_factory.mktemp("secure-b")
    for name in ("ca.pem", "ca.key", "passwords.txt"):
        shutil.copy2(secured.directory / name, folder / name)
    port = free_endpoint().rsplit(":", 1)[1]
    endpoint_a = load_config(secured.router_config).endpoint
    bundle_b = write_bundle(
        folder, endpoint=f"tls/127.0.0.1:{port}", connect=[endpoint_a]
    )
    argv = ["python", "-m", catalog.ROUTER_MODULE]
    router = Native(
        "router-b",
        [*argv, "--config", str(bundle_b.router_config)],
        folder / "router-b.log",
    )
    try:
        with Bus.connect(load_config(bundle_b.clients["client"]), wait=30) as bus:
            missing = bus.wait_alive(["planner"], 30)
        assert not missing, router.output()
        yield bundle_b
        assert router.running(), router.output()
    finally:
        stop_all([router])


def test_a_client_on_a_second_machine_plans_through_both_routers(
    secured: Bundle, second_router: Bundle
) -> None:
    """B's client asks A's planner; B's recorder gets the trajectory A published."""
    key = f"{NS}/{TRAJECTORY_TOPIC}"
    with (
        Bus.connect(load_config(second_router.clients["recorder"])) as recorder_b,
        Bus.connect(load_config(secured.clients["planner"])) as planner_a,
        Bus.connect(load_config(second_router.clients["client"])) as client_b,
    ):
        inbox = Inbox(recorder_b, key)
        assert inbox.wait_for_route(planner_a, key, 20.0)
        trajectory = client_b.call(PLAN, REACH, timeout=60.0)
        assert isinstance(trajectory, Trajectory)
        assert inbox.wait_for(trajectory.to_json().encode(), 10.0)


def test_a_second_machine_relays_only_what_its_users_may_send(
    secured: Bundle, second_router: Bundle
) -> None:
    """A trajectory put on B reaches A from B's planner, never from B's client."""
    key = f"{NS}/{TRAJECTORY_TOPIC}"
    with (
        Bus.connect(load_config(secured.clients["recorder"])) as recorder_a,
        Bus.connect(load_config(second_router.clients["planner"])) as planner_b,
        Bus.connect(load_config(second_router.clients["client"])) as client_b,
    ):
        inbox = Inbox(recorder_a, key)
        assert inbox.wait_for_route(planner_b, key, 20.0)
        client_b.session.put(key, b"forged on machine B")
        planner_b.session.put(key, b"planned on machine B")
        assert inbox.wait_for(b"planned on machine B", 10.0)
        assert not inbox.wait_for(b"forged on machine B", QUIET)
