"""The planner and its stage services as real processes behind a real router."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import IO, Any

import numpy as np
import pytest
import zenoh
from test_planner_given_path import NOISY_SAMPLES, NOISY_TIMES, leaving_the_reach

from armplan.launch import Launcher, free_endpoint
from services.planner import service as planner_service
from services.planner.path_reach import check_path_within_reach
from services.planner.pipeline import plan
from services.planner.stages import LocalStages
from services.planner.wrist_path import reach_path
from shared.bus import Bus, Route, load_config
from shared.bus.deadline import Due, serving_until
from shared.bus.routes import DECIDE, IK_PATH, PLAN, TIMING, TRAJECTORY_TOPIC
from shared.bus.topics import JOINT_PATH_TOPIC, PLAN_REQUEST_TOPIC, find_topic
from shared.demos.nao_grid import nao_grid
from shared.errors import (
    InvalidInputError,
    PayloadTooLargeError,
    RequestTimeoutError,
    ServiceUnavailableError,
    UnreachableTargetError,
)
from shared.messages import (
    DecideRequest,
    Decision,
    Method,
    PathIKRequest,
    PlanRequest,
    WristPath,
    parse,
)
from shared.messages.request_id import with_request_id
from shared.robot import load_arm
from shared.robot.postures import rest

#: The payload limit these tests configure [bytes].
LIMIT = 262144
NAMESPACE = "test-plan"
CONFIG = """{{
  mode: "router",
  listen: {{ endpoints: ["{endpoint}"] }},
  scouting: {{ multicast: {{ enabled: false }} }},
  metadata: {{ armplan: {{ namespace: "{namespace}", max_payload: {limit},
                          timeout: 60.0 }} }},
}}"""
REACH = PlanRequest.model_validate({"targets": [{"position": (0.12, -0.10, 0.05)}]})


def timed_path() -> WristPath:
    """A 1.2 s timed wrist path from rest towards a target (right arm)."""
    arm = load_arm("right")
    goal = np.array((0.12, -0.10, 0.05))
    path = reach_path(arm, rest(arm.side), goal, 1.2)
    return WristPath(
        arm=arm.side,
        times=path.times.tolist(),
        positions=[tuple(p) for p in path.positions.tolist()],
    )


CASES = {
    "reach": REACH,
    "left-palm": PlanRequest.model_validate(
        {
            "arm": "left",
            "targets": [{"position": (0.12, 0.10, 0.05), "palm": (0, 0, -1)}],
        }
    ),
    "least-norm": REACH.model_copy(update={"method": Method.LEAST_NORM}),
    "single": REACH.model_copy(update={"method": Method.SINGLE}),
    "fastest": REACH.model_copy(update={"fastest": True}),
    "two-targets-dwell": PlanRequest.model_validate(
        {
            "targets": [
                {"position": (0.12, -0.10, 0.05), "dwell": 0.5},
                {"position": (0.10, -0.14, 0.0)},
            ],
            "rate": 50.0,
        }
    ),
    "wrist-path": PlanRequest(wrist_path=timed_path()),
    # tracked on the even grid, 0.11 mm out of the reach between samples 0-1
    "noisy-wrist-path": PlanRequest(
        wrist_path=WristPath(times=list(NOISY_TIMES), positions=list(NOISY_SAMPLES))
    ),
    "palm-weights": PlanRequest.model_validate(
        {
            "targets": [{"position": (0.12, -0.10, 0.05), "palm": (0, 0, 1)}],
            "measures": {"omega": 0.0, "mu": 0.3},
        }
    ),
}


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Iterator[IO[str]]:
    with (tmp_path_factory.mktemp("logs") / "children.log").open("w") as file:
        yield file


@pytest.fixture(scope="module")
def stack(tmp_path_factory: pytest.TempPathFactory, log: IO[str]) -> Iterator[Launcher]:
    """The router and every service, from a config file with a small limit."""
    path = tmp_path_factory.mktemp("plan") / "zenoh.json5"
    path.write_text(
        CONFIG.format(endpoint=free_endpoint(), namespace=NAMESPACE, limit=LIMIT)
    )
    with Launcher(load_config(path), log=log) as launcher:
        yield launcher


@pytest.fixture(scope="module")
def bus(stack: Launcher) -> Iterator[Bus]:
    with Bus.connect(stack.config) as bus:
        yield bus


def in_process(request: PlanRequest) -> str:
    return plan(request).trajectory.to_json()


@pytest.mark.parametrize("request_", CASES.values(), ids=CASES.keys())
def test_remote_and_in_process_plans_agree_byte_for_byte(
    bus: Bus, request_: PlanRequest
) -> None:
    """The planner's trajectory JSON is the in-process one, byte for byte."""
    assert bus.call(PLAN, request_).to_json() == in_process(request_)


def test_a_plan_publishes_request_decision_joint_path_and_trajectory(
    bus: Bus,
) -> None:
    """Each part goes out on its registered topic (so the recorder keeps it
    on a typed channel), in order, the trajectory equal to the reply; the
    decision after it, on its clock."""
    got: list[tuple[str, bytes]] = []
    lock = threading.Lock()

    def keep(sample: zenoh.Sample) -> None:
        with lock:
            got.append((str(sample.key_expr), sample.payload.to_bytes()))

    subscriber = bus.session.declare_subscriber(f"{NAMESPACE}/plan/**", keep)
    try:
        time.sleep(0.5)  # let the router learn of the subscriber
        reply = bus.call(PLAN, REACH)
        deadline = time.monotonic() + 10.0
        while len(got) < 4 and time.monotonic() < deadline:
            time.sleep(0.05)
    finally:
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    paths = [key.removeprefix(f"{NAMESPACE}/") for key, _ in got]
    assert paths == [
        "plan/request",
        "plan/joint_path",
        "plan/trajectory",
        "plan/decision",
    ]
    parts = []
    for path, (_, payload) in zip(paths, got, strict=True):
        topic = find_topic(path)
        assert topic is not None and topic.message is not None
        parts.append(parse(topic.message, payload))
    assert got[0][1] == REACH.to_json().encode()
    assert got[2][1] == reply.to_json().encode()
    decision = parts[3]
    assert isinstance(decision, Decision) and decision.trajectory_times is not None
    assert decision.trajectory_times[-1] == pytest.approx(reply.duration)


def test_a_repeated_request_id_is_planned_and_published_once(bus: Bus) -> None:
    """Asked twice with one id: one trajectory published, the same answer twice;
    the id reused for another task is refused, naming the field."""
    trajectories: list[bytes] = []

    def keep(sample: zenoh.Sample) -> None:
        trajectories.append(sample.payload.to_bytes())

    request = with_request_id(REACH)
    assert request.request_id and with_request_id(request) is request
    subscriber = bus.session.declare_subscriber(f"{NAMESPACE}/{TRAJECTORY_TOPIC}", keep)
    try:
        time.sleep(0.5)  # let the router learn of the subscriber
        first = bus.call(PLAN, request, repeat=True)
        again = bus.call(PLAN, request, repeat=True)
        time.sleep(0.5)  # a second publication would have come by now
    finally:
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert again == first
    assert trajectories == [first.to_json().encode()]
    other = CASES["fastest"].model_copy(update={"request_id": request.request_id})
    with pytest.raises(InvalidInputError, match="request_id"):
        bus.call(PLAN, other)


def test_a_repeat_whose_answer_went_is_answered_not_published(
    bus: Bus, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The planner's own code, in this process, on the running stage services,
    keeping one sample's worth of answers: a second plan pushes the first
    answer out, yet a repeat of the first gets the same trajectory, and only
    the two plans are published (a following robot moves once for each)."""
    monkeypatch.setattr(planner_service, "KEPT_SAMPLES", 1)
    planner = planner_service.remote_planner(bus)
    published: list[bytes] = []

    def keep(sample: zenoh.Sample) -> None:
        published.append(sample.payload.to_bytes())

    first_request = with_request_id(REACH)
    subscriber = bus.session.declare_subscriber(f"{NAMESPACE}/{TRAJECTORY_TOPIC}", keep)
    try:
        time.sleep(0.5)  # let the router learn of the subscriber
        first = planner(first_request)
        second = planner(with_request_id(CASES["fastest"]))
        again = planner(first_request)
        time.sleep(0.5)  # a third publication would have come by now
    finally:
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert again == first != second
    assert published == [t.to_json().encode() for t in (first, second)]


def test_a_plan_its_caller_left_is_not_published(bus: Bus) -> None:
    """A 16-target task asked with a 50 ms timeout: the caller gets its
    timeout; the planner, finding its caller gone when the plan is done,
    publishes no trajectory (a following robot would move for no one). The
    same task asked patiently is published."""
    published: list[bytes] = []

    def keep(sample: zenoh.Sample) -> None:
        published.append(sample.payload.to_bytes())

    task = PlanRequest.model_validate(
        {"targets": [{"position": tuple(g.wrist)} for g in nao_grid("right")]}
    )
    subscriber = bus.session.declare_subscriber(f"{NAMESPACE}/{TRAJECTORY_TOPIC}", keep)
    try:
        time.sleep(0.5)  # let the router learn of the subscriber
        with pytest.raises(RequestTimeoutError):
            bus.call(PLAN, task, timeout=0.05)
        time.sleep(3.0)  # the plan takes well under a second on these services
        assert published == []
        reply = bus.call(PLAN, task)
        time.sleep(0.5)  # the publication follows the reply closely
    finally:
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert published == [reply.to_json().encode()]


def test_a_caller_gone_while_the_joint_paths_were_put_gets_no_trajectory(
    bus: Bus, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The planner's own code, in this process: a put waits up to 5 s for a
    subscriber that stopped reading (``Bus.publish``'s BLOCK), here 4 s on
    the joint path. The caller, due 3 s after asking (time for the plan
    itself on a loaded machine), had gone by the time the trajectory was
    put: it was published all the same, for no one."""
    planner = planner_service.remote_planner(bus)
    publish, published = bus.publish, []

    def put_waiting_for_room(path: str, message: Any) -> None:
        if path == JOINT_PATH_TOPIC:
            time.sleep(4.0)
        publish(path, message)

    monkeypatch.setattr(bus, "publish", put_waiting_for_room)
    subscriber = bus.session.declare_subscriber(
        f"{NAMESPACE}/{TRAJECTORY_TOPIC}",
        lambda sample: published.append(sample.payload.to_bytes()),
    )
    try:
        time.sleep(0.5)  # let the router learn of the subscriber
        with (
            serving_until(Due(at=time.monotonic() + 3.0, budget=3.0)),
            pytest.raises(RequestTimeoutError, match="while its joint paths"),
        ):
            planner(with_request_id(REACH))
        time.sleep(0.5)  # a publication would have come by now
    finally:
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert published == []


def test_callers_told_they_timed_out_get_no_published_plan(
    bus: Bus, rng: np.random.Generator
) -> None:
    """40 one-target plans asked with 10-100 ms budgets, about the plan's own
    time: each either answered and published once, or told request_timeout
    and not published. (Finished within 2 ms of the caller's deadline, 1 in
    10 timed-out plans was published: the deadline runs from the query's
    arrival, and the answer must still travel back.)"""
    published: list[bytes] = []
    subscriber = bus.session.declare_subscriber(
        f"{NAMESPACE}/{TRAJECTORY_TOPIC}",
        lambda sample: published.append(sample.payload.to_bytes()),
    )
    goals = [tuple(g.wrist) for g in nao_grid("right")]
    outcomes = []
    try:
        time.sleep(0.5)  # let the router learn of the subscriber
        for k in range(40):
            task = PlanRequest.model_validate(
                {"targets": [{"position": goals[k % len(goals)]}]}
            )
            before = len(published)
            try:
                bus.call(PLAN, task, timeout=float(rng.uniform(0.01, 0.1)))
                answered = True
            except RequestTimeoutError:
                answered = False
            time.sleep(0.25)  # a publication follows its plan within milliseconds
            outcomes.append((answered, len(published) - before))
    finally:
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert all(count == (1 if answered else 0) for answered, count in outcomes)
    assert any(answered for answered, _ in outcomes)


def test_a_repeat_still_waiting_gets_the_plan_its_first_caller_left(
    bus: Bus,
) -> None:
    """Asked with a 50 ms timeout, then again at once under the same id (the
    documented way to ask for a late answer): the repeat gets the plan, and
    it is published once, since a caller still waited for it."""
    published: list[bytes] = []

    def keep(sample: zenoh.Sample) -> None:
        published.append(sample.payload.to_bytes())

    task = with_request_id(
        PlanRequest.model_validate(
            {"targets": [{"position": tuple(g.wrist)} for g in nao_grid("right")]}
        )
    )
    subscriber = bus.session.declare_subscriber(f"{NAMESPACE}/{TRAJECTORY_TOPIC}", keep)
    try:
        time.sleep(0.5)  # let the router learn of the subscriber
        with pytest.raises(RequestTimeoutError):
            bus.call(PLAN, task, timeout=0.05, repeat=True)
        reply = bus.call(PLAN, task, timeout=60.0, repeat=True)
        time.sleep(0.5)  # the publication follows the reply closely
    finally:
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert published == [reply.to_json().encode()]


def test_an_unreachable_target_comes_back_typed(bus: Bus) -> None:
    """The planner's own typed error, with its evidence, through the service."""
    far = PlanRequest.model_validate({"targets": [{"position": (0.5, -0.12, 0.05)}]})
    with pytest.raises(UnreachableTargetError) as caught:
        bus.call(PLAN, far)
    assert caught.value.evidence["arm"] == "right"


def through_the_shoulder() -> WristPath:
    """``timed_path`` with its sample 40 (t = 0.4 s) moved onto the shoulder."""
    path = timed_path()
    shoulder = load_arm(path.arm).fk(rest(path.arm)).shoulder
    positions = list(path.positions)
    positions[40] = (float(shoulder[0]), float(shoulder[1]), float(shoulder[2]))
    return path.model_copy(update={"positions": positions})


def stage_request(stage: str, path: WristPath) -> tuple[Route[Any, Any], Any]:
    """The route and request of ``stage`` (decide, ik-mp, ik-least-norm) for
    ``path``; ik-mp with the decision of ``timed_path`` (the same times)."""
    if stage == "decide":
        return DECIDE, DecideRequest(path=path)
    if stage == "ik-least-norm":
        return IK_PATH, PathIKRequest(path=path, method=Method.LEAST_NORM)
    decision = LocalStages().decide(DecideRequest(path=timed_path()))
    return IK_PATH, PathIKRequest(path=path, decision=decision)


@pytest.mark.parametrize("stage", ["decide", "ik-mp", "ik-least-norm"])
def test_a_path_through_an_unreachable_sample_is_refused_naming_it(
    bus: Bus, stage: str
) -> None:
    """The decide and ik services refuse a wrist path whose sample 40 is the
    shoulder itself, naming the sample, with the message ``armplan decide
    --wrist-path`` and ``armplan plan`` give before asking them. (They
    answered: a primitive for each point, a joint path 51 mm off that
    sample.)"""
    path = through_the_shoulder()
    route, asked = stage_request(stage, path)
    with pytest.raises(UnreachableTargetError) as caught:
        check_path_within_reach(load_arm(path.arm), path)
    with pytest.raises(UnreachableTargetError) as remote:
        bus.call(route, asked)
    assert remote.value.message == caught.value.message
    assert remote.value.message.startswith("wrist-path sample 40 (t = 0.400 s): ")
    assert remote.value.evidence["distance"] == 0.0


def test_a_path_whose_curve_leaves_the_reach_is_named_as_in_process(
    bus: Bus,
) -> None:
    """The planner's even grid through four samples within reach passes
    11 mm inside the reach: the decide service refuses a point of that
    grid, and the planner names the gap between the caller's samples, as
    in-process, not a grid point the caller never gave."""
    request = PlanRequest(wrist_path=leaving_the_reach(load_arm("right")))
    with pytest.raises(UnreachableTargetError) as local:
        plan(request)
    with pytest.raises(UnreachableTargetError) as remote:
        bus.call(PLAN, request)
    assert remote.value.message == local.value.message
    assert "add samples between them" in remote.value.message


@pytest.mark.parametrize(
    "payload,error,words",
    [
        (b'{"targets": [{"position": [0.12, -0.1', InvalidInputError, "not valid JSON"),
        (b'{"target": [0.12, -0.10, 0.05]}', InvalidInputError, "target"),
        (b'{"targets": [{"position": "near"}]}', InvalidInputError, "position"),
        (
            b'{"targets": [{"position": [NaN, -0.10, 0.05]}]}',
            InvalidInputError,
            "finite number",
        ),
        (b'{"targets": [], "rate": 1e999}', InvalidInputError, "finite number"),
        (b" " * (LIMIT + 1), PayloadTooLargeError, f"limit of {LIMIT} bytes"),
    ],
    ids=["malformed", "wrong-schema", "wrong-type", "nan", "inf", "too-large"],
)
def test_bad_plan_requests_get_typed_errors_and_the_planner_answers_on(
    stack: Launcher, bus: Bus, payload: bytes, error: type[Exception], words: str
) -> None:
    """A typed error naming the problem; the same process plans the next one."""
    pid = stack.services["planner"].pid
    with pytest.raises(error, match=words):
        bus.call(PLAN, payload)
    assert bus.call(PLAN, REACH).to_json() == in_process(REACH)
    assert stack.services["planner"].pid == pid
    assert stack.services["planner"].exit_code() is None


@pytest.mark.parametrize("route", [DECIDE, IK_PATH, TIMING], ids=lambda r: r.path)
@pytest.mark.parametrize(
    "payload,words",
    [
        (b"{not json", "not valid JSON"),
        (b'{"targets": []}', r"invalid \w+Request: "),
        (b" " * (LIMIT + 1), f"limit of {LIMIT} bytes"),
    ],
    ids=["malformed", "wrong-schema", "too-large"],
)
def test_bad_stage_requests_get_typed_errors(
    bus: Bus, route: Route[Any, Any], payload: bytes, words: str
) -> None:
    """Each stage service refuses bad bytes with a typed error and plans go on."""
    with pytest.raises(InvalidInputError, match=words):
        bus.call(route, payload)
    assert bus.call(PLAN, REACH).to_json() == in_process(REACH)


@pytest.mark.parametrize(
    "route,key", [(PLAN, "wrist_path"), (DECIDE, "path")], ids=["plan", "decide"]
)
def test_a_one_sample_wrist_path_is_refused_over_the_bus(
    bus: Bus, route: Route[Any, Any], key: str
) -> None:
    """A path of one sample (no step: it was planned as a 0 s trajectory)
    sent as JSON: invalid_input naming its times, as ``armplan plan`` of a
    one-row CSV; the planner plans on."""
    body = f'{{"{key}": {{"times": [0], "positions": [[0.12, -0.13, 0.05]]}}}}'
    with pytest.raises(InvalidInputError) as refused:
        bus.call(route, body.encode())
    assert refused.value.field == f"{key}.times"
    assert "a wrist path needs at least 2 samples, this one has 1" in (
        refused.value.message
    )
    assert bus.call(PLAN, REACH).to_json() == in_process(REACH)


def test_a_nan_in_a_stage_request_is_named(bus: Bus) -> None:
    """A NaN inside a wrist path sent to decide: invalid_input naming the field."""
    body = b'{"path": {"arm": "right", "times": [0, 0.01], '
    body += b'"positions": [[0.1, -0.1, 0.0], [NaN, -0.1, 0.0]]}}'
    with pytest.raises(InvalidInputError, match=r"path\.positions\.1\.0"):
        bus.call(DECIDE, body)


def test_fifty_concurrent_plans_all_succeed(bus: Bus) -> None:
    """50 threads of one client plan 50 grid reaches; every reply is the
    in-process trajectory of its own request."""
    targets = [tuple(t.wrist) for t in nao_grid(load_arm("right").side)]
    requests = [
        PlanRequest.model_validate({"targets": [{"position": targets[k % 16]}]})
        for k in range(50)
    ]
    with ThreadPoolExecutor(50) as pool:
        replies = list(pool.map(lambda r: bus.call(PLAN, r, timeout=300.0), requests))
    expected = {k: in_process(requests[k]) for k in range(16)}
    for k, reply in enumerate(replies):
        assert reply.to_json() == expected[k % 16]


def test_a_stalled_stage_is_named_to_the_caller_in_its_time(
    stack: Launcher, bus: Bus
) -> None:
    """The timing service paused (SIGSTOP): a caller waiting 3 s was told
    that the planner did not answer, while the planner waited the bus's
    whole timeout (60 s here) for timing. Each stage now waits what the
    caller has left less a margin, so the caller gets the planner's answer
    naming timing, within its 3 s."""
    timing = stack.services["timing"]
    timing.signal(signal.SIGSTOP)
    try:
        start = time.monotonic()
        with pytest.raises(RequestTimeoutError) as caught:
            bus.call(PLAN, REACH, timeout=3.0)
        took = time.monotonic() - start
    finally:
        timing.signal(signal.SIGCONT)
    assert caught.value.service == "timing", caught.value.message
    assert "service 'timing' did not answer" in caught.value.message
    assert took < 3.0
    assert bus.call(PLAN, REACH, timeout=60.0).to_json() == in_process(REACH)


def test_a_stopped_fit_service_does_not_stop_planning(
    stack: Launcher, bus: Bus
) -> None:
    """Without fit, decide keeps the model it has and plans still work."""
    stack.services["fit"].signal(signal.SIGTERM)
    stack.services["fit"].process.wait(30.0)
    assert bus.call(PLAN, REACH).to_json() == in_process(REACH)
    stack.start_service("fit")
    assert bus.wait_alive(["fit"], 60.0) == []


@pytest.mark.parametrize("service", ["decide", "ik", "timing", "planner"])
def test_a_stopped_service_is_named_within_2_s_and_a_restart_heals(
    stack: Launcher, bus: Bus, service: str
) -> None:
    """One service killed: the remote plan fails within 2 s naming it; once it
    is restarted (nothing else is), planning works again."""
    others = {n: c.pid for n, c in stack.services.items() if n != service}
    stack.services[service].signal(signal.SIGKILL)
    stack.services[service].process.wait(30.0)
    start = time.monotonic()
    with pytest.raises(ServiceUnavailableError) as caught:
        bus.call(PLAN, REACH, timeout=30.0)
    assert time.monotonic() - start < 2.0
    assert caught.value.service == service
    assert f"service {service!r} is unavailable" in caught.value.message
    stack.start_service(service)
    assert bus.wait_alive([service], 60.0) == []
    assert bus.call(PLAN, REACH, timeout=60.0).to_json() == in_process(REACH)
    assert {n: c.pid for n, c in stack.services.items() if n != service} == others


def _abandoned(log: IO[str]) -> int:
    """How many plans the planner has stopped waiting for (its log in ``log``)."""
    said = "every caller's session ended while a stage was asked"
    return Path(log.name).read_text().count(said)


@pytest.mark.parametrize(
    ("stop", "code"),
    [(signal.SIGINT, 130), (signal.SIGKILL, -signal.SIGKILL)],
    ids=["ctrl-c", "killed"],
)
def test_a_plan_whose_caller_was_interrupted_is_not_published(
    stack: Launcher, bus: Bus, log: IO[str], stop: signal.Signals, code: int
) -> None:
    """``armplan plan --remote --timeout 60`` interrupted with Ctrl-C (or
    killed) while the planner waits for a stage (timing paused): its
    deadline had not passed, so the planner published the plan when timing
    came back, and a following bridge would have played it for no one. The
    client's caller token goes with its session: the plan is not published.
    Nor does the planner wait for the stage any longer (it held a worker up
    to STAGE_LIMIT, 60 s): it says so while timing is still paused. A plan
    asked afterwards by a caller still there is."""
    published: list[bytes] = []
    asked = threading.Event()
    key = f"{NAMESPACE}/{TRAJECTORY_TOPIC}"
    trajectories = bus.session.declare_subscriber(
        key, lambda sample: published.append(sample.payload.to_bytes())
    )
    requests = bus.session.declare_subscriber(
        f"{NAMESPACE}/{PLAN_REQUEST_TOPIC}", lambda _sample: asked.set()
    )
    timing = stack.services["timing"]
    abandoned = _abandoned(log)  # by the tests before
    try:
        time.sleep(0.5)  # the router learns of the subscribers
        timing.signal(signal.SIGSTOP)
        try:
            where = ["--connect", stack.config.endpoint, "--namespace", NAMESPACE]
            reach = ["--target", "0.12", "-0.10", "0.05", "--timeout", "60"]
            client = subprocess.Popen(
                [sys.executable, "-m", "armplan", "plan", "--remote", *where, *reach],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
            )
            assert asked.wait(30.0), "the planner never got the request"
            client.send_signal(stop)
            _, err = client.communicate(timeout=30.0)
            assert client.returncode == code, err
            deadline = time.monotonic() + 4.0  # timing paused < 10 s: its lease
            while _abandoned(log) == abandoned:
                assert time.monotonic() < deadline, "the planner still waits"
                time.sleep(0.1)
        finally:
            timing.signal(signal.SIGCONT)
        time.sleep(3.0)  # timing answers; the plan is done well within this
        assert published == []
        reply = bus.call(PLAN, REACH, timeout=60.0)
        time.sleep(0.5)  # the publication follows the reply closely
    finally:
        requests.undeclare()  # type: ignore[no-untyped-call]
        trajectories.undeclare()  # type: ignore[no-untyped-call]
    assert published == [reply.to_json().encode()]
