"""The fault and load suite on the real processes, small and bounded.

One system (router, services, simulated NAO, bridge, recorder) is started
for the module on a free 127.0.0.1 port; each scenario of ``armplan
faults`` runs on it at a small size. Every scenario must lose no request
and crash no process, and must show that its fault really happened: the
killed process was named by the calls that needed it, then served again.
The 200 concurrent plans run at full size. The classification of answers
is checked first against an in-process service that answers each way.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from armplan.cli.commands.faults import HELP
from armplan.cli.main import main
from armplan.faults import Call, Outcome, Tally, passed, send
from armplan.faults.bad_input import bad_input_scenario, spoiled
from armplan.faults.burst import burst_scenario
from armplan.faults.kill_restart import _recovered, restart_scenario
from armplan.faults.outcome import Result
from armplan.faults.recorder_kill import recorder_scenario
from armplan.faults.requests import GoodRequests, good_requests
from armplan.faults.strategies import SPOILERS, locations, nested, replaced
from armplan.faults.suite import KILLED, QUERYABLES, SuiteOptions
from armplan.faults.system import FaultSystem
from armplan.faults.table import json_report
from armplan.faults.traffic import Traffic, cycle
from armplan.launch import free_endpoint
from shared.bus import Bus, BusConfig, Endpoint, Route, ServiceHost, open_router
from shared.bus.routes import PLAN
from shared.errors import InvalidInputError, RequestTimeoutError
from shared.messages import Message, parse

#: Requests per kill scenario in these tests (a third before, down, after).
REQUESTS = 9
#: Bad inputs of each kind per queryable in these tests.
EXAMPLES = 2
SEED = 20260


class Word(Message):
    word: str


def answer_as_told(request: Word) -> Word:
    """Answer each way a service can: a reply, typed, relayed timeout, bug, hang."""
    if request.word == "slow":
        time.sleep(1.5)
    if request.word == "relayed":
        raise RequestTimeoutError("stage", key="test/stage", timeout=0.1)
    if request.word == "bug":
        raise KeyError("boom")
    return Word(word=request.word)


ECHO = Route("echo", "test/echo", Word, Word)


@pytest.fixture(scope="module")
def echo_bus() -> Iterator[Bus]:
    config = BusConfig(endpoints=(free_endpoint(),), namespace="test")
    with (
        open_router(config),
        Bus.connect(config) as service_bus,
        ServiceHost(service_bus, "echo", [Endpoint(ECHO, answer_as_told)]),
        Bus.connect(config) as bus,
    ):
        assert bus.wait_alive(["echo"], 10.0) == []
        yield bus


@pytest.mark.parametrize(
    "payload,outcome,kind",
    [
        (Word(word="fine"), Outcome.SUCCEEDED, ""),
        (b'{"word": NaN}', Outcome.TYPED, "invalid_input"),
        (Word(word="relayed"), Outcome.TYPED, "request_timeout"),
        (Word(word="bug"), Outcome.UNCLEAR, "internal_error"),
        (Word(word="slow"), Outcome.LOST, "request_timeout"),
    ],
    ids=["reply", "typed", "relayed-timeout", "internal-error", "no-answer"],
)
def test_send_sorts_each_answer(
    echo_bus: Bus, payload: Message | bytes, outcome: Outcome, kind: str
) -> None:
    """Only this client's own wait running out is lost; a bug is unclear."""
    result = send(echo_bus, Call(ECHO, payload), timeout=0.5)
    assert (result.outcome, result.kind) == (outcome, kind)


def test_a_dead_service_is_typed_not_lost() -> None:
    """No service holds the token: service_unavailable at once, a clear error."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace="test")
    with open_router(config), Bus.connect(config) as bus:
        result = send(bus, Call(ECHO, Word(word="x")), timeout=5.0)
    assert (result.outcome, result.kind) == (Outcome.TYPED, "service_unavailable")
    assert result.seconds < 2.0


def test_the_suite_fails_on_a_lost_request_or_a_crash() -> None:
    """The verdict: one lost request or one crash fails the whole table."""
    fine = Tally("a", results=[Result("plan", Outcome.SUCCEEDED)])
    lost = Tally("b", results=[Result("plan", Outcome.LOST, "request_timeout")])
    crashed = Tally("c", crashes=["ik (123)"])
    assert passed([fine])
    assert not passed([fine, lost]) and not passed([fine, crashed])
    report = json_report([fine, lost, crashed], (1.0, 2.0))
    assert report["total"]["lost"] == 1 and report["total"]["crashes"] == 1
    assert report["passed"] is False
    assert report["load_average"] == {"start": 1.0, "end": 2.0}


def test_a_process_left_unrecovered_fails_the_suite() -> None:
    """A restart after which calls still fail is a failed suite, not a note."""
    stuck = Tally("d", results=[Result("plan", Outcome.SUCCEEDED)])
    stuck.facts = {"recovered": False}
    assert not passed([stuck])


def test_overlapping_executes_refused_robot_busy_still_count_as_recovered() -> None:
    """One robot plays one trajectory at a time: an execute refused
    robot_busy beside one that played is a healthy answer; none that played,
    or a failed plan, is not."""
    played = Result("bridge/execute", Outcome.SUCCEEDED)
    busy = Result("bridge/execute", Outcome.TYPED, "robot_busy")
    plan_ok = Result("plan", Outcome.SUCCEEDED)
    assert _recovered([plan_ok, played, busy, busy])
    assert not _recovered([plan_ok, busy])
    assert not _recovered([played, Result("plan", Outcome.TYPED, "ik_failed")])


def test_a_kill_whose_down_calls_did_not_name_it_fails_the_suite() -> None:
    """A kill of ik where none of the calls sent while ik was down named ik
    passed: the verdict looked only at lost, unclear, crashes, recovered."""
    typed = Result("plan", Outcome.TYPED, "request_timeout", "", "stage timed out")
    ok = Result("plan", Outcome.SUCCEEDED)
    kill = Tally("kill, restart ik", 1, [ok] * 20 + [typed] * 20 + [ok] * 20)
    kill.facts = {"named": 0, "down_needing": 20, "recovered": True, "missing": []}
    assert not passed([kill])
    assert kill.unmet == ["only 0 of the 20 calls sent while down named it"]
    kill.facts |= {"named": 20}
    assert passed([kill])
    kill.facts |= {"down_needing": 0, "named": 0}
    assert not passed([kill]), "no call showed the fault"


def test_a_recorder_kill_that_lost_plans_or_recordings_fails_the_suite() -> None:
    """Plans failed, neither file holds a trajectory, the recorder is not
    back: each is a failed suite (it passed: no fact but recovered counted)."""
    ok = Result("plan", Outcome.SUCCEEDED)
    typed = Result("plan", Outcome.TYPED, "service_unavailable", "planner")
    rec = Tally("kill, restart recorder", 1, [ok] * 20 + [typed] * 40)
    rec.facts = {
        "all_planned": False,
        "killed_file": 0,
        "planned_before": 3,
        "flush_allowance_s": 1.0,
        "new_file": 0,
        "planned_after": 0,
        "missing": ["recorder"],
    }
    assert not passed([rec])
    assert rec.unmet == [
        "not every plan succeeded",
        "the killed recorder's file holds 0 of the scenario's trajectories, not "
        "the 3 planned 1 s or more before the kill",
        "the new recorder's file holds 0 trajectories, not the 1 planned after "
        "the restart",
        "still not alive: recorder",
    ]
    good = {"all_planned": True, "killed_file": 5, "new_file": 20}
    rec.facts = good | {"planned_after": 20, "missing": [], "recovered": True}
    rec.facts |= {"planned_before": 5, "flush_allowance_s": 1.0}
    assert passed([rec])
    rec.facts |= {"new_file": 19}
    assert not passed([rec]), "a plan made after the restart is not recorded"


def test_a_killed_recorder_file_missing_plans_made_before_the_kill_fails() -> None:
    """The killed file held 2 of the 5 plans answered a second before the
    kill: it passed (any one trajectory was enough, even an earlier
    scenario's); every plan answered before the flush allowance must be in."""
    ok = Result("plan", Outcome.SUCCEEDED)
    rec = Tally("kill, restart recorder", 1, [ok] * 15)
    rec.facts = {
        "all_planned": True,
        "killed_file": 2,
        "planned_before": 5,
        "flush_allowance_s": 1.0,
        "new_file": 5,
        "planned_after": 5,
        "recovered": True,
        "missing": [],
    }
    assert rec.unmet == [
        "the killed recorder's file holds 2 of the scenario's trajectories, not "
        "the 5 planned 1 s or more before the kill"
    ]
    rec.facts |= {"killed_file": 5}
    assert passed([rec])


def test_a_burst_with_plans_refused_busy_fails_the_suite() -> None:
    """400 at once: 285 planned, 115 refused service_busy (typed, so nothing
    lost or unclear) passed the suite; every plan of a burst must succeed."""
    ok = Result("plan", Outcome.SUCCEEDED)
    busy = Result("plan", Outcome.TYPED, "service_busy", "planner")
    burst = Tally("400 concurrent plans", 0, [ok] * 285 + [busy] * 115)
    burst.facts = {"burst": 400, "planned": 285, "wall_s": 9.0, "slowest_s": 8.0}
    assert not passed([burst])
    assert burst.unmet == ["only 285 of the 400 plans sent at once succeeded"]
    assert not json_report([burst], (0.0, 0.0))["passed"]
    burst.results = [ok] * 400
    burst.facts |= {"planned": 400}
    assert passed([burst])


QUEUE_LIMIT_SAID = (
    "more than the planner's queue limit (256 requests waiting): the extra "
    "plans would be refused service_busy"
)


def test_a_burst_above_the_queue_limit_is_refused_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--burst 400 ran and passed with 115 plans refused service_busy: now
    refused like bench's --clients, by the command and by SuiteOptions."""
    out = tmp_path / "run"
    command = ["faults", "--requests", "3", "--burst", "400", "--out", str(out)]
    assert main(command) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert (
        f"400 plans at once (--burst) are {QUEUE_LIMIT_SAID}; give --burst 0..256"
        in err
    )
    assert not out.exists()
    with pytest.raises(InvalidInputError) as error:
        SuiteOptions(burst=257)
    assert error.value.message == (
        f"257 plans at once are {QUEUE_LIMIT_SAID}; give burst 0..256"
    )
    assert error.value.field == "burst"
    assert SuiteOptions(burst=256).burst == 256


def test_bad_inputs_without_a_good_answer_next_fail_the_suite() -> None:
    """The good request after each bad one answered service_busy every time:
    the service did not answer next, a failed suite (it passed)."""
    rejected = Result("plan", Outcome.TYPED, "invalid_input")
    busy = Result("plan", Outcome.TYPED, "service_busy")
    bad = Tally("bad input: plan", 6, [rejected, busy] * 6)
    bad.facts = {"bad": 6, "typed": 6, "good_next": 0, "same_process": True}
    assert not passed([bad])
    assert bad.unmet == ["the good request right after one answered 0 of 6 times"]
    bad.facts |= {"good_next": 6, "same_process": False}
    assert bad.unmet == ["not the same process at the end"]
    bad.facts |= {"same_process": True}
    assert passed([bad])
    report = json_report([bad], (0.0, 0.0))
    assert report["passed"] and report["scenarios"][0]["unmet"] == []


@pytest.fixture(scope="module")
def good() -> GoodRequests:
    return good_requests()


def test_bad_inputs_come_in_every_kind_the_same_each_run(good: GoodRequests) -> None:
    """A fixed seed gives the same spoiled requests; every kind is there, and
    none is a valid plan request."""
    first = spoiled(good, PLAN, EXAMPLES, SEED)
    assert first == spoiled(good, PLAN, EXAMPLES, SEED)
    assert {b.kind for b in first} == set(SPOILERS)
    for bad in first:
        with pytest.raises(InvalidInputError, match="PlanRequest"):
            parse(PLAN.request, bad.payload)


def test_spoiling_copies_the_request_and_nests_as_deep_as_asked() -> None:
    """A spoiled copy changes one location and leaves the template alone."""
    template = {"a": [1, {"b": 2.0}]}
    assert locations(template) == [(), ("a",), ("a", 0), ("a", 1), ("a", 1, "b")]
    assert replaced(template, ("a", 1, "b"), None) == {"a": [1, {"b": None}]}
    assert replaced(template, ("c",), 3) == {"a": [1, {"b": 2.0}], "c": 3}
    assert template == {"a": [1, {"b": 2.0}]}
    assert nested(3, "[") == "[[[]]]" and nested(2, '{"a":') == '{"a":{"a":0}}'


@pytest.fixture(scope="module")
def system(tmp_path_factory: pytest.TempPathFactory) -> Iterator[FaultSystem]:
    with FaultSystem(tmp_path_factory.mktemp("faults")) as system:
        yield system


@pytest.fixture(scope="module")
def bus(system: FaultSystem) -> Iterator[Bus]:
    with Bus.connect(system.config) as bus:
        yield bus


@pytest.fixture(scope="module")
def traffic(bus: Bus) -> Iterator[Traffic]:
    with Traffic(bus, 3, 30.0) as traffic:
        yield traffic


def test_the_help_says_what_the_suite_hurts(system: FaultSystem) -> None:
    """It said it kills and feeds bad inputs to every process: the sim is
    never killed, and only the services and the bridge get bad inputs."""
    hurt = {*KILLED, "router", "recorder"}
    assert set(system.stack.processes()) - hurt == {"sim"}
    assert "kill and restart every process but the simulated NAO" in HELP
    assert {r.service for r in QUERYABLES} == set(KILLED)  # services, bridge
    assert "bad inputs to the services and the bridge" in HELP


def healthy(tally: Tally) -> None:
    """Nothing lost, nothing unclear, nothing crashed, no promise unmet: the
    suite's verdict passes this real run (with the evidence)."""
    row = tally.row()
    # which calls failed, how long they took [s], and why
    failed = [(r.route, r.kind, r.seconds, r.message) for r in tally.results if r.kind]
    assert (row["lost"], row["unclear"], row["crashes"]) == (0, 0, 0), (row, failed)
    assert row["unmet"] == [], (row, failed)
    assert passed([tally])


@pytest.mark.parametrize("name", [*KILLED, "router"])
def test_a_killed_process_is_named_while_down_and_serves_after_a_restart(
    system: FaultSystem, traffic: Traffic, good: GoodRequests, name: str
) -> None:
    """Killed in traffic: calls that need it fail naming it, none is lost;
    restarted, every process is alive and every later call succeeds."""
    tally = restart_scenario(system, traffic, good, name, REQUESTS)
    errors = [(r.route, r.message) for r in tally.results if r.kind]
    healthy(tally)
    assert tally.sent == REQUESTS
    assert tally.facts["down_needing"] >= 1
    assert tally.facts["named"] == tally.facts["down_needing"], errors
    assert tally.facts["recovered"], (tally.facts, errors)


def test_a_recorder_killed_mid_session_loses_no_plan(
    system: FaultSystem, traffic: Traffic, good: GoodRequests
) -> None:
    """Plans go on; the killed file is readable and holds the plans answered
    before the kill; the new recorder records. Plans made before the scenario
    are in the killed file too, and are not counted as its own (they were:
    the check passed with none of its own)."""
    earlier = traffic.run(cycle(good.plan_calls(), 2 * REQUESTS))
    assert all(r.outcome is Outcome.SUCCEEDED for r in earlier)
    tally = recorder_scenario(system, traffic, good, REQUESTS)
    healthy(tally)
    facts = tally.facts
    assert facts["all_planned"]
    # its own: at most the first third's, at least those answered long before
    assert 1 <= facts["planned_before"] <= facts["killed_file"] <= REQUESTS // 3
    assert facts["new_file"] >= facts["planned_after"] == REQUESTS // 3


def test_200_concurrent_plans_are_all_answered(
    system: FaultSystem, bus: Bus, good: GoodRequests
) -> None:
    """The full burst of the command: 200 plans at once, each one planned."""
    tally = burst_scenario(system, bus, good, 200, timeout=120.0)
    healthy(tally)
    assert tally.sent == 200
    assert tally.count(Outcome.SUCCEEDED) == tally.facts["planned"] == 200


@pytest.mark.parametrize("route", QUERYABLES, ids=lambda r: r.path)
def test_bad_inputs_get_typed_errors_and_the_service_answers_next(
    system: FaultSystem, bus: Bus, good: GoodRequests, route: Route[Any, Any]
) -> None:
    """Every spoiled request: a typed error (or, valid by chance, a result);
    the good request after each one is answered by the same process."""
    tally = bad_input_scenario(
        system, bus, good, route, examples=EXAMPLES, seed=SEED, timeout=30.0
    )
    healthy(tally)
    facts = tally.facts
    assert facts["typed"] + facts["accepted"] == facts["bad"] == 6 * EXAMPLES
    assert facts["typed"] >= 1
    assert facts["good_next"] == facts["bad"] and facts["same_process"]
