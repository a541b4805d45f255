"""Plans through every Zenoh service, beside the in-process plan, in the same run.

The work: a one-second reach, the paper's grid point 13 on NAO from the arm
at rest (method mp, human pace: a 1.0 s trajectory from a wrist path of
about 100 points). It is planned in-process (``services.planner.pipeline``)
and through a real router and the fit, decide, ik, timing and planner
processes on a free loopback port (client -> planner -> decide, ik, timing),
by 1, 8 and 50 concurrent clients: threads of this process sharing one Zenoh
session, each sending its share of the requests one after another. Per plan
the latency is the wall time from send to typed reply [s]; throughput is
plans over the wall time of the whole load [1/s]; the ratio is the remote
p50 over the in-process p50. With the services up, each stage's request is
also timed on its own, here and through its service (``stage_hops``), to show
where the time through the services goes. :func:`run` measures;
:meth:`ServiceLatency.figures` gives JSON-ready numbers and
:meth:`ServiceLatency.table` printable rows.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from pathlib import Path
from typing import NamedTuple

import numpy as np

from armplan.bench import stage_hops
from armplan.bench.stage_hops import StageHop
from armplan.bench.timer import Timing, time_calls
from armplan.launch import Launcher, free_endpoint
from armplan.launch.quoted_log import quoting_log
from services.planner.pipeline import plan
from shared.bus import Bus, BusConfig, load_config
from shared.bus.routes import PLAN
from shared.demos.nao_grid import nao_grid
from shared.messages import PlanRequest
from shared.robot import Side
from shared.text.counted import counted

#: Concurrent clients measured by default.
CLIENTS = (1, 8, 50)
#: The grid point whose reach from rest takes one second at human pace.
GRID_POINT = 13
#: Plans sent before measuring.
WARM_UP = 3
#: Plans per client at the least, so that the clients stay busy: 100 plans
#: over 50 clients (2 each) kept all 50 in flight only 47 % of the time.
PER_CLIENT = 10
#: The services a plan goes through.
SERVICES = ("fit", "decide", "ik", "timing", "planner")


class Load(NamedTuple):
    """One load level.

    Attributes:
        clients: Concurrent clients (threads).
        latency: Time per plan, send to reply [s], shape (plans,).
        wall: Wall time of the whole load [s].
    """

    clients: int
    latency: Timing
    wall: float

    @property
    def per_second(self) -> float:
        """Plans answered per second [1/s]."""
        return len(self.latency.samples) / self.wall


class ServiceLatency(NamedTuple):
    """The benchmark's figures.

    Attributes:
        in_process: Time per plan made in-process [s].
        loads: One entry per concurrency level.
        duration: Duration of the planned trajectory [s].
        path_points: Points of its wrist path.
        load_average: The machine's 1-minute load average at the start and
            the end of the run (runnable processes; compare with its CPUs:
            a busy machine delays every hop between processes).
        hops: Per stage (``stage_hops.STAGES``), its request timed here and
            through its service.
    """

    in_process: Timing
    loads: list[Load]
    duration: float
    path_points: int
    load_average: tuple[float, float]
    hops: dict[str, StageHop]

    def ratio(self, load: Load) -> float:
        """``load``'s p50 over the in-process p50."""
        return load.latency.percentile(50) / self.in_process.percentile(50)

    def table(self) -> list[tuple[str, float, float, float, float]]:
        """Rows (what, p50 [ms], p99 [ms], plans per second, p50 / in-process)."""
        ours = self.in_process
        rows = [("in-process", *_ms(ours), 1.0 / ours.mean, 1.0)]
        rows += [
            (
                f"services, {counted(x.clients, 'client')}",
                *_ms(x.latency),
                x.per_second,
                self.ratio(x),
            )
            for x in self.loads
        ]
        return rows

    def figures(self) -> dict[str, float]:
        """JSON-ready figures, e.g. ``services_8_p50_ms`` [ms], ``_per_s`` [1/s].

        Per row: ``<what>_p50_ms``, ``<what>_p99_ms``, ``<what>_per_s`` and,
        through the services, ``<what>_ratio`` (p50 over in-process p50);
        ``<what>`` is ``in_process`` or ``services_<clients>``.
        """
        out: dict[str, float] = {
            "services_reach_duration_s": self.duration,
            "services_path_points": float(self.path_points),
            "services_plans": float(len(self.in_process.samples)),
            "services_load_average_start": self.load_average[0],
            "services_load_average_end": self.load_average[1],
            "cpus": float(os.cpu_count() or 0),
        }
        for what, p50, p99, rate, ratio in self.table():
            # "services, 8 clients" / "services, 1 client" -> services_8 / _1
            name = what.replace("services, ", "services_")
            name = name.removesuffix(" clients").removesuffix(" client")
            name = name.replace("-", "_")
            out |= {
                f"{name}_plans": float(self._plans(what)),
                f"{name}_p50_ms": p50,
                f"{name}_p99_ms": p99,
                f"{name}_per_s": rate,
            }
            if name != "in_process":
                out[f"{name}_ratio"] = ratio
        return out | self._hop_figures()

    def _plans(self, what: str) -> int:
        """Plans timed in the row called ``what``."""
        if what == "in-process":
            return len(self.in_process.samples)
        return next(
            len(x.latency.samples)
            for x in self.loads
            if x.clients == int(what.split()[1])
        )

    def _hop_figures(self) -> dict[str, float]:
        """Per stage, medians [ms]: ``stage_<name>_<what>_ms``.

        ``what``: ``here``, ``service``, ``overhead``, ``handle``, ``inside``,
        ``trips`` (see ``stage_hops.StageHop``).
        """
        out: dict[str, float] = {}
        for name, hop in self.hops.items():
            out[f"stage_{name}_here_ms"] = hop.here.percentile(50) * 1e3
            out[f"stage_{name}_service_ms"] = hop.service.percentile(50) * 1e3
            out[f"stage_{name}_overhead_ms"] = hop.overhead * 1e3
            out[f"stage_{name}_handle_ms"] = hop.handle.percentile(50) * 1e3
            out[f"stage_{name}_inside_ms"] = hop.inside.percentile(50) * 1e3
            out[f"stage_{name}_trips_ms"] = hop.trips * 1e3
        return out


def _ms(timing: Timing) -> tuple[float, float]:
    return timing.percentile(50) * 1e3, timing.percentile(99) * 1e3


def one_second_reach() -> PlanRequest:
    """The benchmark's request: grid point 13 from rest, right arm, method mp."""
    point = next(p for p in nao_grid(Side.RIGHT) if p.point == GRID_POINT)
    position = tuple(float(v) for v in point.wrist)
    return PlanRequest.model_validate({"targets": [{"position": position}]})


def steps(n: int, clients: Sequence[int]) -> int:
    """How many timed calls ``run(n, clients)`` makes (for a progress bar)."""
    return n + sum(plans_for(n, k) for k in clients) + stage_hops.steps(n)


def plans_for(n: int, clients: int) -> int:
    """Plans timed with ``clients`` concurrent clients.

    ``n``, or ``PER_CLIENT`` each if that is more.
    """
    return max(n, PER_CLIENT * clients)


def run(
    n: int = 100,
    clients: Sequence[int] = CLIENTS,
    config: BusConfig | None = None,
    after: Callable[[], object] | None = None,
) -> ServiceLatency:
    """Measure in-process, then through the services at each concurrency level.

    Args:
        n: Plans per measurement.
        clients: Concurrency levels.
        config: Bus settings of running services to measure; ``None`` starts
            a router and the services on a free loopback port for the run,
            and stops them all before returning (or raising).
        after: Called after each timed plan, untimed (progress); through the
            services, from the clients' threads.
    """
    before = os.getloadavg()[0]
    request = one_second_reach()
    result = plan(request)
    in_process = time_calls([partial(plan, request) for _ in range(n)], after)
    if config is not None:
        loads, hops = _remote(config, request, n, clients, after)
    else:
        own = load_config(endpoints=(free_endpoint(),))
        with own_services(own):
            loads, hops = _remote(own, request, n, clients, after)
    return ServiceLatency(
        in_process,
        loads,
        result.trajectory.duration,
        len(result.wrist_paths[0].times),
        (before, os.getloadavg()[0]),
        hops,
    )


@contextlib.contextmanager
def own_services(config: BusConfig) -> Iterator[Launcher]:
    """The router and the services, started for the run, their output kept aside.

    Their output goes to a temporary file, gone after the run: a process
    that exits while starting is reported with what it printed last (the
    router: its port in use), not sent to a log that does not exist.
    """
    with tempfile.TemporaryDirectory(prefix="armplan-bench-") as folder:
        path = Path(folder) / "services.log"
        with path.open("a", encoding="utf-8") as log:
            launcher = Launcher(config, SERVICES, log=log)
            with quoting_log(path):
                launcher.start()
            try:
                yield launcher
            finally:
                launcher.stop()


def _remote(
    config: BusConfig,
    request: PlanRequest,
    n: int,
    clients: Sequence[int],
    after: Callable[[], object] | None,
) -> tuple[list[Load], dict[str, StageHop]]:
    with Bus.connect(config) as bus:
        for _ in range(WARM_UP):  # liveliness known, routes set, code loaded
            bus.call(PLAN, request, timeout=60.0)
        loads = [_load(bus, request, n, k, after) for k in clients]
        return loads, stage_hops.time_hops(bus, request, n, after)


def _load(
    bus: Bus,
    request: PlanRequest,
    n: int,
    clients: int,
    after: Callable[[], object] | None,
) -> Load:
    def timed(_: int) -> float:
        start = time.perf_counter()
        bus.call(PLAN, request, timeout=60.0)
        took = time.perf_counter() - start
        if after is not None:
            after()
        return took

    start = time.perf_counter()
    with ThreadPoolExecutor(clients) as pool:
        latency = list(pool.map(timed, range(plans_for(n, clients))))
    return Load(clients, Timing(np.array(latency)), time.perf_counter() - start)
