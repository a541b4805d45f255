"""The unsecured router's log under normal use: no warnings for a caller's
own timeout, and no colour codes in a file.

A caller that gave up on a slow answer (its own timeout, which it is told
of) made the router log three Zenoh warnings ("Didn't receive final reply
for query", "Route reply: Query not found!"), each with terminal colour
codes written into the log file: about 70 lines an hour in a soak with
short client timeouts.
"""

from __future__ import annotations

import pathlib
import time

import zenoh
from native_processes import Native

from armplan.launch import catalog, free_endpoint
from shared.bus import Bus, load_config

#: How long the slow queryable takes to answer [s], and the caller waits [s].
SLOW, IMPATIENT = 0.5, 0.05
#: How long the router's log is watched for a line [s].
LOG_WAIT = 30.0


def test_a_callers_own_timeout_leaves_no_warning_in_the_routers_log(
    tmp_path: pathlib.Path,
) -> None:
    endpoint = free_endpoint()
    log = tmp_path / "router.log"
    router = Native(
        "router", ["python", "-m", catalog.ROUTER_MODULE, "--listen", endpoint], log
    )
    try:
        deadline = time.monotonic() + LOG_WAIT
        while "router listening" not in log.read_text(errors="replace"):
            assert router.running() and time.monotonic() < deadline, log.read_text()
            time.sleep(0.1)
        config = load_config(endpoints=(endpoint,))
        with Bus.connect(config) as server, Bus.connect(config) as client:

            def answer_late(query: zenoh.Query) -> None:
                time.sleep(SLOW)
                with query:
                    query.reply(query.key_expr, b"late")

            slow = server.session.declare_queryable("armplan/slow", answer_late)
            time.sleep(0.3)  # the queryable reaches the router
            for _ in range(3):
                replies = list(client.session.get("armplan/slow", timeout=IMPATIENT))
                assert replies == [] or all(r.err for r in replies)
            time.sleep(SLOW + 0.5)  # the late answers reach the router
            slow.undeclare()  # type: ignore[no-untyped-call]
        # a warning that still is one: the router tells of a port in use
        busy = Native(
            "busy",
            ["python", "-m", catalog.ROUTER_MODULE, "--listen", endpoint],
            tmp_path / "busy.log",
        )
        busy.process.wait(30)
    finally:
        router.stop()
    text = log.read_text(errors="replace")
    assert "Query not found" not in text
    assert "Didn't receive final reply" not in text
    assert "\x1b[" not in text
    assert "\x1b[" not in (tmp_path / "busy.log").read_text(errors="replace")
    assert "WARN" in (tmp_path / "busy.log").read_text(errors="replace")
