"""``armplan status``: which services are alive on the router.

``--namespace NS`` asks about another namespace than the config's (two
systems sharing one router). ``--json`` prints one document: ``router``,
``namespace`` and ``services``, each ``{"service", "state", "keys"}`` with
``keys`` a list of the key expressions it answers (``[]`` for none);
docs/services.md has the fields.
Without a router it is the same document, every service absent, with the
error added.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from armplan.cli.output import print_json, print_table
from armplan.cli.parsing import add_json
from armplan.launch import SERVICES
from armplan.launch.catalog import PROCESSES, ServiceSpec, unknown_hint
from shared.bus import Bus, BusConfig
from shared.bus.elsewhere import elsewhere_hint
from shared.bus.keys import alive_key, alive_pattern
from shared.bus.options import add_config_option, add_connect_options, bus_config
from shared.errors import ServiceUnavailableError
from shared.printable import printable, printable_lines

ORDER = 81
HELP = "list the services alive on the Zenoh router (liveliness tokens)"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``status``."""
    parser = commands.add_parser("status", help=HELP, description=HELP)
    add_config_option(parser)
    add_connect_options(
        parser,
        namespace_help="list the services alive in this key namespace "
        "(default: the config's, armplan)",
    )
    parser.add_argument(
        "--require",
        nargs="+",
        metavar="SERVICE",
        default=[],
        help="fail (exit 1) unless these services are alive (health checks)",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print every known service and whether it is alive."""
    config = bus_config(args)
    try:
        with Bus.connect(config) as bus:
            alive, error = bus.alive(), None
            elsewhere = bus.alive_elsewhere(set(args.require) - set(alive))
    except ServiceUnavailableError as no_router:
        if not args.json:
            raise
        alive, error = [], no_router  # the document still, every service absent
        elsewhere = {}
    rows = _rows(alive, config.namespace)
    error = error or _missing(args.require, alive, config, elsewhere)
    if not args.json:
        sys.stdout.write(f"router {config.endpoint}, namespace {config.namespace}\n")
        table = [(printable(n), state, ", ".join(k) or "-") for n, state, k in rows]
        print_table(("service", "state", "keys"), table)  # names from the network
        if error is not None:
            raise error
        return 0
    document: dict[str, Any] = {
        "router": config.endpoint,
        "namespace": config.namespace,
        "services": [
            dict(zip(("service", "state", "keys"), r, strict=True)) for r in rows
        ],
    }
    if error is None:
        print_json(document)
        return 0
    print_json(document | {"error": error.to_wire()})  # one JSON document
    sys.stderr.write(f"armplan: error: {printable_lines(error.message)}\n")
    return 1


def _missing(
    required: list[str],
    alive: list[str],
    config: BusConfig,
    elsewhere: dict[str, list[str]],
) -> ServiceUnavailableError | None:
    """The error for the ``required`` services not ``alive``; ``None`` if none.

    Its key is the liveliness token looked for (``armplan/alive/ik``), or the
    pattern of every token (``armplan/alive/*``) for several services; it
    says where else a missing one is alive (``elsewhere``, by service).
    """
    missing = [name for name in required if name not in alive]
    if not missing:
        return None
    ns = config.namespace
    return ServiceUnavailableError(
        ", ".join(missing),
        key=alive_key(ns, missing[0]) if len(missing) == 1 else alive_pattern(ns),
        reason=f"not alive on {config.endpoint}{unknown_hint(missing)}"
        f"{elsewhere_hint(elsewhere)}",
        elsewhere=elsewhere,
    )


def _rows(alive: list[str], namespace: str) -> list[tuple[str, str, list[str]]]:
    """(service, alive|absent, keys) for every service, then any other process alive.

    A process ``armplan up`` starts only when asked (recorder, bridge) is
    listed once alive, with its keys; a token no process of ours declares
    has no keys (``[]``; ``-`` in the table).
    """
    known = {s.name for s in SERVICES}
    others = {s.name: s for s in PROCESSES if s.name not in known}
    rows = [
        (
            spec.name,
            "alive" if spec.name in alive else "absent",
            _keys(spec, namespace),
        )
        for spec in SERVICES
    ]
    rows += [
        (name, "alive", _keys(others[name], namespace) if name in others else [])
        for name in alive
        if name not in known
    ]
    return rows


def _keys(spec: ServiceSpec, namespace: str) -> list[str]:
    """The keys ``spec`` answers (none: ``[]``)."""
    return [r.key(namespace) for r in spec.routes]
