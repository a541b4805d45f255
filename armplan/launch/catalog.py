"""The processes ``armplan up`` starts: the router, then every service.

Each service runs as ``python -m services.<name>`` (its ``__main__.py`` calls
``shared.bus.serve``); the router as ``python -m shared.bus.router``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

from shared.bus import Route
from shared.bus.robot_routes import EXECUTE, STOP
from shared.bus.routes import ROUTES
from shared.errors import InvalidInputError

#: The router's module.
ROUTER_MODULE = "shared.bus.router"


class ServiceSpec(NamedTuple):
    """One service process.

    Attributes:
        name: The service's name (its liveliness token), e.g. ``"ik"``.
        module: The module run with ``python -m``, e.g. ``"services.ik"``.
        routes: The routes it answers.
        after: Services it is started after, once they are alive, when they
            are part of the same launch (``Launcher.start``).
    """

    name: str
    module: str
    routes: tuple[Route[Any, Any], ...]
    after: tuple[str, ...] = ()


def _spec(name: str, after: tuple[str, ...] = ()) -> ServiceSpec:
    routes = tuple(r for r in ROUTES if r.service == name)
    return ServiceSpec(name, f"services.{name}", routes, after)


#: Every service, in start order (the planner last: it calls the others).
#: decide starts once fit is alive: it then asks fit for its model before it
#: declares its own token, so "ready" means it decides with fit's model (fit
#: takes seconds longer to start when it checks a kept model; started
#: together, decide came alive with the shipped model and swapped fit's in
#: only after ``armplan up`` said ready).
SERVICES: tuple[ServiceSpec, ...] = (
    _spec("fit"),
    _spec("decide", after=("fit",)),
    _spec("ik"),
    _spec("timing"),
    _spec("planner"),
)


def service_spec(name: str) -> ServiceSpec:
    """The service called ``name``; ``InvalidInputError`` listing the known ones."""
    for spec in SERVICES:
        if spec.name == name:
            return spec
    known = ", ".join(s.name for s in SERVICES)
    raise InvalidInputError(
        f"unknown service {name!r}; known: {known}", field="service"
    )


def service_specs(names: Sequence[str]) -> tuple[ServiceSpec, ...]:
    """The services called ``names``, in that order, each named once.

    Raises:
        InvalidInputError: an unknown name (as :func:`service_spec`), or a
            name given more than once: two processes of one service would
            both answer its routes, and the launcher would watch only one.
    """
    twice = list(dict.fromkeys(n for n in names if list(names).count(n) > 1))
    if twice:
        listed = ", ".join(map(repr, twice))
        noun = "service" if len(twice) == 1 else "services"
        raise InvalidInputError(
            f"{noun} {listed} named more than once: name each service once "
            "(each runs as one process)",
            field="service",
            services=twice,
        )
    return tuple(map(service_spec, names))


#: The recorder process (``python -m services.recorder``, liveliness token
#: ``recorder``). Not in ``SERVICES``: ``armplan up`` does not start it, since
#: it writes files; ``armplan demo`` starts it with
#: ``services.recorder.RecorderProcess`` and docker-compose runs it with a
#: volume for the recordings. It answers no route.
RECORDER = ServiceSpec("recorder", "services.recorder", ())
#: The robot bridge (``python -m bridge.serve``, token ``bridge``). Not in
#: ``SERVICES``: it needs a robot; ``armplan up --with-bridge/--with-sim`` and
#: ``armplan demo`` start it (``armplan.launch.robot.RobotStack``).
BRIDGE = ServiceSpec("bridge", "bridge.serve", (EXECUTE, STOP))
#: The simulated NAO (``python -m bridge.sim``): it speaks libqi, not Zenoh, so
#: it has no token and no route; ready once it prints its address.
SIM = ServiceSpec("sim", "bridge.sim", ())
#: Every process the catalogue knows besides the router.
PROCESSES: tuple[ServiceSpec, ...] = (*SERVICES, RECORDER, BRIDGE, SIM)


def unknown_hint(names: Sequence[str]) -> str:
    """A hint for those of ``names`` no liveliness token can show, or ``""``.

    For a service that is not alive: a misspelt name ("brige") waits its
    whole timeout and then reads like a process that did not start; the
    simulated NAO runs but speaks NAOqi, not Zenoh, so it holds no token.
    """
    ours = [s.name for s in PROCESSES if s.routes or s.name == RECORDER.name]
    silent = [s.name for s in PROCESSES if s.name not in ours]
    unknown = [n for n in names if n not in ours and n not in silent]
    hints = [
        f"{n!r} holds no liveliness token (it speaks NAOqi, not Zenoh)"
        for n in names
        if n in silent
    ]
    if unknown:
        hints.append(
            f"no armplan process is called {', '.join(map(repr, unknown))}; "
            f"ours: {', '.join(ours)}"
        )
    return f" ({'; '.join(hints)})" if hints else ""
