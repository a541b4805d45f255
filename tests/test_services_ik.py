"""The IK service as a real process behind a real router on a free loopback port."""

from __future__ import annotations

import os
import pathlib
import signal
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from typing import IO

import numpy as np
import pytest

from armplan.launch import Launcher, free_endpoint
from services.ik import solve_request
from shared.bus import Bus, load_config
from shared.bus.routes import IK_SOLVE
from shared.errors import (
    InvalidInputError,
    PayloadTooLargeError,
    ServiceUnavailableError,
    UnreachableTargetError,
)
from shared.messages import IKRequest
from shared.robot import load_arm
from tests.clear_draws import clear_target

#: The payload limit these tests configure [bytes].
LIMIT = 4096
CONFIG = """{{
  mode: "router",
  listen: {{ endpoints: ["{endpoint}"] }},
  scouting: {{ multicast: {{ enabled: false }} }},
  metadata: {{ armplan: {{ namespace: "test-ik", max_payload: {limit} }} }},
}}"""
REACH = IKRequest(target=(0.12, -0.13, 0.05))


def write_config(tmp: pathlib.Path) -> pathlib.Path:
    path = tmp / "zenoh.json5"
    path.write_text(CONFIG.format(endpoint=free_endpoint(), limit=LIMIT))
    return path


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Iterator[IO[str]]:
    with (tmp_path_factory.mktemp("logs") / "children.log").open("w") as file:
        yield file


@pytest.fixture(scope="module")
def stack(tmp_path_factory: pytest.TempPathFactory, log: IO[str]) -> Iterator[Launcher]:
    """Router and IK service processes, from a config file with a small limit."""
    config = load_config(write_config(tmp_path_factory.mktemp("ik")))
    with Launcher(config, ["ik"], log=log) as launcher:
        yield launcher


@pytest.fixture(scope="module")
def bus(stack: Launcher) -> Iterator[Bus]:
    with Bus.connect(stack.config) as bus:
        yield bus


def in_process(request: IKRequest) -> dict[str, object]:
    return solve_request(load_arm(request.arm), request).model_dump(mode="json")


@pytest.mark.parametrize(
    "request_",
    [
        REACH,
        IKRequest(arm="left", target=(0.12, 0.13, 0.05)),
        IKRequest(target=(0.12, -0.13, 0.05), primitive="S_R E_PR W_P"),
        IKRequest(target=(0.12, -0.13, 0.05), method="least-norm"),
        IKRequest(target=(0.12, -0.13, 0.05), method="single"),
        IKRequest(target=(0.12, -0.13, 0.05), palm=(0, 0, -1)),
    ],
    ids=["reach", "left", "primitive", "least-norm", "single", "palm"],
)
def test_remote_and_in_process_agree(bus: Bus, request_: IKRequest) -> None:
    """The service's reply has exactly the in-process JSON fields and values."""
    remote = bus.call(IK_SOLVE, request_).model_dump(mode="json")
    assert remote == in_process(request_)


def test_an_arm_in_any_case_is_read_as_the_cli_reads_it(bus: Bus) -> None:
    """``{"arm": "LEFT"}`` over the wire is the left arm, as ``--arm LEFT``
    and a wrist path's arm are (it was invalid_input)."""
    payload = b'{"arm": "LEFT", "target": [0.12, 0.13, 0.05]}'
    left = IKRequest(arm="left", target=(0.12, 0.13, 0.05))
    assert bus.call(IK_SOLVE, payload).model_dump(mode="json") == in_process(left)


def test_an_unreachable_target_comes_back_with_its_evidence(bus: Bus) -> None:
    """The solver's typed error is rebuilt on the caller's side."""
    with pytest.raises(UnreachableTargetError) as caught:
        bus.call(IK_SOLVE, IKRequest(target=(0.5, -0.12, 0.05)))
    assert caught.value.evidence["arm"] == "right"
    assert "0.5030 m from the right shoulder" in caught.value.message


def test_errors_name_json_fields_not_cli_options(bus: Bus) -> None:
    """A client of the bus has no options: the service words its errors by
    the request's fields (it told "--swivel ... (give --primitive ...)"), and
    a payload at fault as a whole names the field ""."""
    for asked, field, words in (
        ({"swivel": 1.0}, "swivel", "(give primitive 'S_R E_P W_R')"),
        ({"swivel": 1.0, "method": "single"}, "swivel", "swivel is the goal"),
        ({"primitive": "S_R E_P W_R", "method": "single"}, "primitive", "mp' only"),
    ):
        request = IKRequest.model_validate({"target": (0.12, -0.13, 0.05)} | asked)
        with pytest.raises(InvalidInputError) as caught:
            bus.call(IK_SOLVE, request)
        assert "--" not in caught.value.message and words in caught.value.message
        assert caught.value.evidence["field"] == field
    with pytest.raises(InvalidInputError) as caught:
        bus.call(IK_SOLVE, b"[1, 2]")
    assert caught.value.evidence["field"] == ""


@pytest.mark.parametrize(
    "payload,error,words",
    [
        (b'{"target": [0.12, -0.13', InvalidInputError, "not valid JSON"),
        (b'{"targets": [{"position": [0.1, 0, 0]}]}', InvalidInputError, "target"),
        (b'{"target": "0.12 -0.13 0.05"}', InvalidInputError, "target"),
        (b'{"target": [NaN, -0.13, 0.05]}', InvalidInputError, "finite number"),
        (b'{"target": [1e999, 0, 0]}', InvalidInputError, "finite number"),
        (b" " * (LIMIT + 1), PayloadTooLargeError, f"limit of {LIMIT} bytes"),
    ],
    ids=["malformed", "wrong-schema", "wrong-type", "nan", "inf", "too-large"],
)
def test_bad_input_gets_a_typed_error_and_the_service_answers_on(
    stack: Launcher, bus: Bus, payload: bytes, error: type[Exception], words: str
) -> None:
    """A typed error for the bad request; the same process answers the next one."""
    pid = stack.services["ik"].pid
    with pytest.raises(error, match=words.replace("[", r"\[")):
        bus.call(IK_SOLVE, payload)
    assert bus.call(IK_SOLVE, REACH).model_dump(mode="json") == in_process(REACH)
    assert stack.services["ik"].pid == pid and stack.services["ik"].exit_code() is None


def test_fifty_concurrent_requests_all_succeed(bus: Bus) -> None:
    """50 threads of one client, each with its own target, all get their answer."""
    arm = load_arm("right")
    rng = np.random.default_rng(5)
    targets = [tuple(clear_target(arm, rng)) for _ in range(50)]
    requests = [IKRequest(target=t) for t in targets]
    with ThreadPoolExecutor(50) as pool:
        replies = list(
            pool.map(lambda r: bus.call(IK_SOLVE, r, timeout=120.0), requests)
        )
    for request, reply in zip(requests, replies, strict=True):
        assert reply.target == request.target
        assert reply.model_dump(mode="json") == in_process(request)


@pytest.mark.parametrize(
    "signum", [signal.SIGTERM, signal.SIGKILL], ids=["term", "kill"]
)
def test_a_stopped_service_is_named_fast_and_a_restart_heals(
    tmp_path: pathlib.Path, log: IO[str], signum: int
) -> None:
    """IK stopped: an error naming it within 2 s; restarted: calls work again."""
    config = load_config(write_config(tmp_path))
    with Launcher(config, ["ik"], log=log) as launcher, Bus.connect(config) as bus:
        router = launcher.router
        assert bus.call(IK_SOLVE, REACH).error < 1e-3
        launcher.services["ik"].signal(signum)
        launcher.services["ik"].process.wait(10.0)
        start = time.monotonic()
        with pytest.raises(ServiceUnavailableError) as caught:
            bus.call(IK_SOLVE, REACH, timeout=30.0)
        assert time.monotonic() - start < 2.0
        assert caught.value.service == "ik" and "'ik'" in caught.value.message
        launcher.start_service("ik")
        assert bus.wait_alive(["ik"], 60.0) == []
        assert bus.call(IK_SOLVE, REACH).model_dump(mode="json") == in_process(REACH)
        assert launcher.router is router and router is not None
        assert router.exit_code() is None and os.getpgid(router.pid) == router.pid
