"""Round trips to the IK service over Zenoh, beside the in-process IK, same run.

The same IK requests are solved in-process (``solve_request``) and through a
real router and IK service process on a free loopback port, by 1, 8 and 50
concurrent clients: threads of this process sharing one Zenoh session, each
sending its share of the requests one after another. Per request the latency
is the wall time from send to typed reply [s]; throughput is requests over
the wall time of the whole load [1/s]. The difference between the remote and
the in-process p50 is what the services cost.
"""

from __future__ import annotations

import subprocess
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import NamedTuple

import numpy as np

from armplan.bench.timer import Timing, time_calls
from armplan.launch import Launcher, free_endpoint
from services.ik import solve_request
from shared.bus import Bus, BusConfig, load_config
from shared.bus.routes import IK_SOLVE
from shared.messages import IKRequest
from shared.robot import load_arm

#: Concurrent clients measured by default.
CLIENTS = (1, 8, 50)


class Load(NamedTuple):
    """One load level.

    Attributes:
        clients: Concurrent clients (threads).
        latency: Time per request, send to reply [s], shape (requests,).
        wall: Wall time of the whole load [s].
    """

    clients: int
    latency: Timing
    wall: float

    @property
    def per_second(self) -> float:
        """Requests answered per second [1/s]."""
        return len(self.latency.samples) / self.wall


class ServiceLatency(NamedTuple):
    """The benchmark's figures.

    Attributes:
        in_process: Time per request solved in-process [s].
        loads: One entry per concurrency level.
    """

    in_process: Timing
    loads: list[Load]

    def table(self) -> list[tuple[str, float, float, float]]:
        """Rows (what, p50 [ms], p99 [ms], requests per second)."""
        ours = self.in_process
        rows = [("in-process", *_ms(ours), 1.0 / ours.mean)]
        rows += [
            (f"remote, {x.clients} clients", *_ms(x.latency), x.per_second)
            for x in self.loads
        ]
        return rows


def _ms(timing: Timing) -> tuple[float, float]:
    return timing.percentile(50) * 1e3, timing.percentile(99) * 1e3


def requests_for(n: int, seed: int) -> list[IKRequest]:
    """``n`` reachable right-arm targets (wrists of random postures)."""
    arm = load_arm("right")
    rng = np.random.default_rng(seed)
    wrists = [
        arm.fk(rng.uniform(arm.limits.lower, arm.limits.upper)).wrist for _ in range(n)
    ]
    return [IKRequest(target=(float(x), float(y), float(z))) for x, y, z in wrists]


def run(
    n: int = 100,
    seed: int = 7,
    clients: Sequence[int] = CLIENTS,
    config: BusConfig | None = None,
) -> ServiceLatency:
    """Measure in-process, then remote at each concurrency level.

    Args:
        n: Requests per measurement.
        seed: Random seed of the targets.
        clients: Concurrency levels.
        config: Bus settings of running services to measure; ``None`` starts
            a router and an IK service on a free loopback port for the run.
    """
    requests = requests_for(n, seed)
    arm = load_arm("right")
    in_process = time_calls([partial(solve_request, arm, r) for r in requests])
    if config is not None:
        return ServiceLatency(in_process, _remote(config, requests, clients))
    own = load_config(endpoints=(free_endpoint(),))
    with Launcher(own, ["ik"], log=subprocess.DEVNULL):
        return ServiceLatency(in_process, _remote(own, requests, clients))


def _remote(
    config: BusConfig, requests: list[IKRequest], clients: Sequence[int]
) -> list[Load]:
    with Bus.connect(config) as bus:
        bus.call(IK_SOLVE, requests[0])  # warm up: liveliness known, route set
        return [_load(bus, requests, k) for k in clients]


def _load(bus: Bus, requests: list[IKRequest], clients: int) -> Load:
    def timed(request: IKRequest) -> float:
        start = time.perf_counter()
        bus.call(IK_SOLVE, request)
        return time.perf_counter() - start

    start = time.perf_counter()
    with ThreadPoolExecutor(clients) as pool:
        latency = list(pool.map(timed, requests))
    return Load(clients, Timing(np.array(latency)), time.perf_counter() - start)
