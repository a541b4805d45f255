"""The main function of every service process (``python -m services.<name>``).

Usage: ``python -m services.ik [--config FILE] [--connect tcp/HOST:PORT]
[--namespace NS]``. It connects to the router (waiting up to ``--wait``
seconds for it), serves the service's endpoints under the namespace (the
config's, or ``--namespace``'s) until SIGTERM or SIGINT (then runs its
``stopped`` hook, before the session closes), and exits 0 (at once, also
while it still waits for the router); it exits 1 with the error on stderr
if the configuration is wrong (a malformed ``--namespace``, a login other
than the service's own user included), no router answers, or the service
is alive in the namespace already (:mod:`shared.bus.service_alone`).
"""

from __future__ import annotations

import argparse
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

from shared.bus.bus import Bus
from shared.bus.options import add_connect_options, add_router_wait_option
from shared.bus.process import (
    add_common_arguments,
    freeze_set_up,
    start_process,
    wait_for,
)
from shared.bus.process_config import process_config
from shared.bus.route import Endpoint
from shared.bus.service import ServiceHost
from shared.bus.service_alone import check_alone
from shared.command_line import ArgumentParser
from shared.errors import ArmplanError, ServiceUnavailableError

log = logging.getLogger("armplan.bus")


@dataclass(frozen=True)
class Served:
    """A service's endpoints and what to do once they are served.

    Attributes:
        endpoints: The routes it answers and their handlers.
        ready: Run once the queryables and the liveliness token are
            declared (``ServiceHost``), e.g. to publish a start state that a
            client seeing the token could also ask for; ``None``: nothing.
        stopped: Run once the service has stopped serving (its token and
            queryables withdrawn), before the bus's session closes, also
            when serving failed, e.g. to undeclare the service's own
            subscribers; ``None``: nothing.
    """

    endpoints: Sequence[Endpoint[Any, Any]]
    ready: Callable[[], None] | None = None
    stopped: Callable[[], None] | None = None


#: Builds a service's endpoints (and maybe its ``ready`` hook); gets the bus
#: to call other services with and to publish on.
EndpointsFactory = Callable[[Bus], Sequence[Endpoint[Any, Any]] | Served]


class Options(NamedTuple):
    """A service's own command-line options.

    Attributes:
        add: Adds them to the parser.
        endpoints: Builds the endpoints factory from the parsed arguments,
            before the bus connects (an ``ArmplanError`` here, say a bad
            file, ends the process with exit code 1 and the error logged).
    """

    add: Callable[[argparse.ArgumentParser], None]
    endpoints: Callable[[argparse.Namespace], EndpointsFactory]


def serve(
    name: str,
    endpoints: EndpointsFactory | Options,
    argv: Sequence[str] | None = None,
) -> int:
    """Run service ``name`` until asked to stop; returns the exit code.

    Args:
        name: The service's name, e.g. ``"ik"``.
        endpoints: Builds its endpoints from the bus, or its own options
            and how they build that.
        argv: Command-line arguments (default: ``sys.argv[1:]``).
    """
    parser = _parser(name)
    if isinstance(endpoints, Options):
        endpoints.add(parser)
    args = parser.parse_args(argv)
    stop = start_process(args.log_level)
    try:
        factory = (
            endpoints.endpoints(args) if isinstance(endpoints, Options) else endpoints
        )
        config = process_config(args, name)
        with Bus.connect(config, wait=args.wait, stop=stop) as bus:
            check_alone(bus, name)
            built = factory(bus)
            served = built if isinstance(built, Served) else Served(built)
            freeze_set_up()  # before the token: no caller waits for it
            try:
                with ServiceHost(bus, name, served.endpoints, served.ready):
                    wait_for(stop)
            finally:
                if served.stopped is not None:
                    served.stopped()
    except ArmplanError as error:
        if stop.is_set() and isinstance(error, ServiceUnavailableError):
            log.info("service %s: asked to stop before a router answered", name)
            return 0
        log.error("service %s: %s", name, error.message)
        return 1
    return 0


def _parser(name: str) -> argparse.ArgumentParser:
    parser = ArgumentParser(
        prog=f"python -m services.{name}",
        description=f"The armplan {name} service on Zenoh.",
    )
    add_common_arguments(parser)
    add_connect_options(parser)
    add_router_wait_option(parser)
    return parser
