"""The service latency benchmark runs end to end (figures are not asserted)."""

from __future__ import annotations

import numpy as np
import pytest

from armplan.bench import service_latency


def test_the_benchmark_reports_every_load_beside_in_process() -> None:
    """One row in-process, one per concurrency level, each with p50, p99, rate
    and ratio; the work is a one-second reach of about 100 path points; each
    stage timed here and through its service; the progress callback runs once
    per timed call (3 plans in-process, 10 per client through the services,
    3 rounds of 3 stages at each place)."""
    calls: list[None] = []
    result = service_latency.run(n=3, clients=(1, 2), after=lambda: calls.append(None))
    assert len(calls) == service_latency.steps(3, (1, 2)) == 3 + 10 + 20 + 18
    assert list(result.hops) == ["decide", "ik", "timing"]
    for hop in result.hops.values():
        assert len(hop.here.samples) == len(hop.service.samples) == 3
        assert len(hop.handle.samples) == len(hop.inside.samples) == 3  # no warm-up
        assert np.all(hop.handle.samples < hop.inside.samples)
        assert np.all(hop.inside.samples < hop.service.samples)  # per call
    assert len(result.in_process.samples) == 3
    assert [load.clients for load in result.loads] == [1, 2]
    assert [len(load.latency.samples) for load in result.loads] == [10, 20]
    assert result.duration == pytest.approx(1.0, abs=0.1)
    assert 90 <= result.path_points <= 110
    rows = result.table()
    assert [row[0] for row in rows] == [
        "in-process",
        "services, 1 client",
        "services, 2 clients",
    ]
    assert np.all(np.isfinite(np.array([row[1:] for row in rows])))
    figures = result.figures()
    assert {"in_process_p50_ms", "services_1_p99_ms", "services_2_ratio"} <= set(
        figures
    )
    assert figures["services_2_per_s"] == rows[2][3]
    assert figures["services_2_ratio"] == pytest.approx(
        figures["services_2_p50_ms"] / figures["in_process_p50_ms"]
    )
    assert figures["services_plans"] == 3.0
    assert figures["cpus"] >= 1 and len(result.load_average) == 2
