"""Start the router and the services, wait until all are alive, stop them all.

Start order: the router (ready once a client session opens on it), then the
services (ready once each one's liveliness token is seen); a service with
services to follow (``ServiceSpec.after``, e.g. decide after fit) that are
part of the launch is started once those are alive, the others at once. Stop order: the
services, then the router; each gets SIGTERM, then SIGKILL after the grace
period. A child that exits during start aborts the start with an error
naming it. Children end themselves if this process dies; on Linux that is
tied to the thread that started them, so start them from a thread that
outlives them (the main thread). Example::

    with Launcher(load_config(endpoints=(free_endpoint(),)), ["ik"]) as stack:
        with Bus.connect(stack.config) as bus:
            bus.call(IK_SOLVE, request)
"""

from __future__ import annotations

import secrets
import threading
import time
from collections.abc import Mapping, Sequence
from typing import IO

from armplan.launch.bus_args import bus_args
from armplan.launch.catalog import (
    ROUTER_MODULE,
    SERVICES,
    ServiceSpec,
    service_spec,
    service_specs,
)
from armplan.launch.child import Child, stop_all
from armplan.launch.quoted_log import log_pointer
from shared.bus import Bus, BusConfig
from shared.errors import ServiceUnavailableError
from shared.lifecycle import StartStop
from shared.stop_signals import StartInterrupted

#: Longest wait for the router, then for all services to be alive [s].
START_TIMEOUT = 60.0
#: Time the children get to exit after SIGTERM before SIGKILL [s].
GRACE = 5.0
#: Pause between liveliness checks while starting [s].
POLL = 0.1


def new_router_id() -> str:
    """A random Zenoh id: 32 hex digits, the first not 0 (Zenoh refuses that)."""
    return secrets.choice("123456789abcdef") + secrets.token_hex(16)[1:]


class Launcher(StartStop):
    """The router and a set of services as child processes.

    Attributes:
        config: The bus settings every child gets.
        specs: The services started.
        router: The router process, once started.
        router_id: The router's Zenoh id (hex), to tell it from another
            router on the same port.
        services: The service processes by name, once started.
    """

    def __init__(
        self,
        config: BusConfig,
        names: Sequence[str] | None = None,
        *,
        log: IO[str] | int | None = None,
        stop: threading.Event | None = None,
        service_args: Mapping[str, Sequence[str]] | None = None,
    ) -> None:
        """Prepare (start nothing yet).

        Args:
            config: The bus settings (router endpoints, namespace, file).
            names: Services to start; ``None`` starts every one.
            log: Where the children's output goes: a file,
                ``subprocess.DEVNULL``, or ``None`` for stderr.
            stop: Set by a signal handler to abort a start in progress
                (``shared.stop_signals.stop_on_signals``).
            service_args: More command-line arguments for a service by name,
                e.g. ``{"fit": ["--model", "/abs/model.json"]}`` (also on a
                restart).

        Raises:
            InvalidInputError: an unknown service, or one named twice.
        """
        self.config = config
        self.specs = SERVICES if names is None else service_specs(names)
        self.router: Child | None = None
        self.router_id = new_router_id()
        self.services: dict[str, Child] = {}
        self._log = log
        self._stop = stop or threading.Event()
        self._service_args = dict(service_args or {})

    def start(self, timeout: float = START_TIMEOUT) -> Launcher:
        """Start the router and every service; return once all are alive.

        Args:
            timeout: Longest wait for the router and for the services [s].

        Raises:
            ServiceUnavailableError: naming the child that exited or did not
                come alive in time (everything started is stopped again).
            StartInterrupted: ``stop`` was set meanwhile (a ``KeyboardInterrupt``;
                everything started is stopped again).
        """
        try:
            self.start_router()
            with self._connect(timeout) as bus:
                deadline = time.monotonic() + timeout
                names = [spec.name for spec in self.specs]
                for spec in self._start_order():
                    first = [n for n in spec.after if n in names]
                    self._wait_alive(bus, first, deadline, timeout)
                    self.start_service(spec.name)
                self._wait_alive(bus, names, deadline, timeout)
        except BaseException:
            self.stop()
            raise
        return self

    def start_router(self) -> Child:
        """Start (or restart) the router on the configured endpoints; does not wait."""
        args = [] if self.config.file is None else ["--config", self.config.file]
        for endpoint in self.config.endpoints:
            args += ["--listen", endpoint]
        args += ["--id", self.router_id]
        self.router = Child.start("router", ROUTER_MODULE, args, self._log)
        return self.router

    def start_service(self, name: str) -> Child:
        """Start (or restart) service ``name`` in the namespace; does not wait."""
        spec = service_spec(name)
        args = [*bus_args(self.config), *self._service_args.get(spec.name, ())]
        child = Child.start(spec.name, spec.module, args, self._log)
        self.services[spec.name] = child
        return child

    def _connect(self, timeout: float) -> Bus:
        """A session on this launcher's own router, once it answers.

        A router answering on the endpoint is not enough: another one (a
        second ``armplan up``) may hold the port, and this one's router then
        exits, unable to listen, while the services would join the other.

        Raises:
            ServiceUnavailableError: the router exited, or only another
                router answered until ``timeout`` [s].
        """
        deadline = time.monotonic() + timeout
        while True:
            self._check_running()
            try:
                bus = Bus.connect(self.config)
            except ServiceUnavailableError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(POLL)
                continue
            if self._on_own_router(bus):
                return bus
            bus.close()
            if time.monotonic() > deadline:
                raise ServiceUnavailableError(
                    "router",
                    reason=f"another router answers on "
                    f"{', '.join(self.config.endpoints)}: is another armplan "
                    "running there? Choose another endpoint with --listen",
                )
            time.sleep(POLL)

    def _on_own_router(self, bus: Bus, wait: float = 1.0) -> bool:
        """Whether ``bus`` is connected to this launcher's router."""
        deadline = time.monotonic() + wait
        while True:
            routers = {str(zid) for zid in bus.session.info.routers_zid()}
            if routers or time.monotonic() > deadline:
                return self.router_id in routers
            time.sleep(0.01)

    def _start_order(self) -> list[ServiceSpec]:
        """``specs``, those that follow another one of them after the rest."""
        names = {spec.name for spec in self.specs}
        return sorted(self.specs, key=lambda s: any(n in names for n in s.after))

    def _wait_alive(
        self, bus: Bus, wanted: Sequence[str], deadline: float, timeout: float
    ) -> None:
        """Wait until ``wanted`` are alive; give up at ``deadline`` (monotonic).

        Raises:
            ServiceUnavailableError: one is not alive by then (``timeout``
                [s] is for the message), or a child exited.
            StartInterrupted: ``stop`` was set.
        """
        while missing := bus.wait_alive(wanted, POLL):
            self._check_running()
            if time.monotonic() > deadline:
                raise bus.not_alive(missing, timeout)

    def _check_running(self) -> None:
        if self._stop.is_set():
            raise StartInterrupted(getattr(self._stop, "signal", None))
        for child in self.children():
            code = child.exit_code()
            if code is not None:
                raise ServiceUnavailableError(
                    child.name,
                    reason=f"its process exited with code {code} while starting "
                    f"{log_pointer(self._log)}",
                )

    def children(self) -> list[Child]:
        """Every child started, the router first."""
        head = [] if self.router is None else [self.router]
        return head + list(self.services.values())

    def exited(self) -> list[Child]:
        """Children that have exited."""
        return [c for c in self.children() if c.exit_code() is not None]

    def stop(self, grace: float = GRACE) -> None:
        """Stop the services, then the router: SIGTERM, SIGKILL after ``grace`` [s]."""
        stop_all(list(self.services.values()), grace)
        if self.router is not None:
            stop_all([self.router], grace)
