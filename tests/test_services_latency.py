"""The service latency benchmark runs end to end (figures are not asserted)."""

from __future__ import annotations

import numpy as np

from armplan.bench import service_latency


def test_the_benchmark_reports_every_load_beside_in_process() -> None:
    """One row in-process, one per concurrency level, each with p50, p99 and rate."""
    result = service_latency.run(n=4, clients=(1, 2))
    assert len(result.in_process.samples) == 4
    assert [load.clients for load in result.loads] == [1, 2]
    assert all(len(load.latency.samples) == 4 for load in result.loads)
    rows = result.table()
    assert [row[0] for row in rows] == [
        "in-process",
        "remote, 1 clients",
        "remote, 2 clients",
    ]
    assert np.all(np.isfinite(np.array([row[1:] for row in rows])))
