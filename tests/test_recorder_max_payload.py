"""A payload over the bus's ``max_payload`` is recorded raw, unread.

The recorder parsed every payload it received, whatever its size: a 200 MB
publication on ``plan/trajectory`` took it to 7 GB (and behind by half a
minute), though no service reads one that large (``payload_too_large``,
the follower drops it). Such a payload is now kept byte for byte as a
``RawPayload``, neither parsed nor derived for Foxglove; one within the
limit is recorded as before. A real router, a recorder in this process, a
real MCAP file.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from test_recorder import publish_all, recorded, trajectory

from armplan.launch import free_endpoint
from services.recorder import RecorderOptions
from services.recorder.routing import Incoming, route
from services.recorder.service import Recorder
from shared.bus import Bus, BusConfig, open_router
from shared.recording import read_records

NS = "armplan"
SMALL, LARGE = trajectory(10).to_json().encode(), trajectory(200).to_json().encode()
#: Between the two payloads' sizes [bytes].
LIMIT = (len(SMALL) + len(LARGE)) // 2


def test_routing_keeps_a_payload_over_the_limit_raw() -> None:
    def schema(payload: bytes, limit: int | None) -> str:
        sample = Incoming(f"{NS}/plan/trajectory", payload, "application/json", 1, 2)
        return route(sample, NS, limit).schema_name

    assert schema(LARGE, LIMIT) == "RawPayload"
    assert schema(SMALL, LIMIT) == "Trajectory"
    assert schema(LARGE, None) == "Trajectory"  # no limit: read, as before
    assert schema(LARGE, len(LARGE)) == "Trajectory"  # at the limit: read


def test_a_recorder_keeps_an_oversized_publication_byte_for_byte(
    tmp_path: Path,
) -> None:
    config = dataclasses.replace(
        BusConfig(endpoints=(free_endpoint(),), namespace=NS), max_payload=LIMIT
    )
    out = tmp_path / "large.mcap"
    options = RecorderOptions(output=out, keys=("plan/trajectory",))
    with open_router(config), Bus.connect(config) as bus, Recorder(bus, options):
        publish_all(config, [("plan/trajectory", LARGE), ("plan/trajectory", SMALL)])
    records = [r for r in read_records(out) if r.topic == f"{NS}/plan/trajectory"]
    assert [r.schema for r in records] == ["RawPayload", "Trajectory"]
    assert recorded(out) == [("plan/trajectory", LARGE), ("plan/trajectory", SMALL)]
    planned = [r for r in read_records(out) if r.topic.startswith("/tf/planned")]
    assert planned  # the one within the limit is still derived for Foxglove
