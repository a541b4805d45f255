"""Options shared by client commands that can run against the services.

``--remote`` sends the command to the running services over Zenoh instead of
computing it in-process; ``--connect tcp/HOST:PORT`` says where the router is
(and implies ``--remote``); ``--zenoh-config FILE`` names the armplan Zenoh
configuration (namespace, limits; default ``config/zenoh.json5``) and also
implies ``--remote``: it configures only the connection to the services;
``--namespace NS`` asks the services of namespace ``NS`` instead of the
config's (``armplan up --namespace NS``) and implies ``--remote`` too.
"""

from __future__ import annotations

import argparse

from shared.bus import DEFAULT_ENDPOINT, Bus, load_config
from shared.bus.config import MAX_WAIT
from shared.bus.options import add_namespace_option, with_namespace
from shared.errors import InvalidInputError


def add_remote(parser: argparse.ArgumentParser) -> None:
    """Add ``--remote``, ``--connect``, ``--zenoh-config`` and ``--namespace``."""
    parser.add_argument(
        "--remote",
        action="store_true",
        help="ask the running services over Zenoh (see `armplan up`)",
    )
    parser.add_argument(
        "--connect",
        action="append",
        metavar="ENDPOINT",
        help=f"router endpoint, implies --remote (default {DEFAULT_ENDPOINT})",
    )
    parser.add_argument(
        "--zenoh-config",
        metavar="FILE",
        help="armplan Zenoh config (JSON5), implies --remote",
    )
    add_namespace_option(
        parser,
        "key namespace of the services, implies --remote (default: the "
        "config's, armplan)",
    )


def is_remote(args: argparse.Namespace) -> bool:
    """Whether the command goes to the services (``--namespace`` too)."""
    return bool(
        args.remote
        or args.connect
        or args.zenoh_config is not None  # an empty name is refused, not local
        or args.namespace is not None
    )


def check_timeout(timeout: float | None) -> None:
    """Refuse a ``--timeout`` [s] that is no wait: NaN, 0, negative, over a day.

    NaN and negative ones reached Zenoh and ended in a traceback
    ("ValueError: negative timeout"); 0 sent a request its caller never
    waited for. ``None``: not given.

    Raises:
        InvalidInputError: naming ``--timeout`` and the value; field
            ``timeout``, as fit's was and plan's "goes with --remote" is.
    """
    if timeout is not None and not 0.0 < timeout <= MAX_WAIT:  # NaN too
        raise InvalidInputError(
            f"--timeout must be a positive number of seconds up to {MAX_WAIT:g}, "
            f"got {timeout:g}",
            field="timeout",
        )


def connect(args: argparse.Namespace) -> Bus:
    """A bus connected to the router named by the options.

    Raises:
        ServiceUnavailableError: if no router answers there.
        BusConfigError: if the configuration, endpoint or namespace is malformed.
    """
    config = load_config(args.zenoh_config, tuple(args.connect or ()))
    return Bus.connect(with_namespace(config, args.namespace))
