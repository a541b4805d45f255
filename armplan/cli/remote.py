"""Options shared by client commands that can run against the services.

``--remote`` sends the command to the running services over Zenoh instead of
computing it in-process; ``--connect tcp/HOST:PORT`` says where the router is
(and implies ``--remote``); ``--zenoh-config FILE`` names the armplan Zenoh
configuration (namespace, limits; default ``config/zenoh.json5``) and also
implies ``--remote``: it configures only the connection to the services.
"""

from __future__ import annotations

import argparse

from shared.bus import DEFAULT_ENDPOINT, Bus, load_config


def add_remote(parser: argparse.ArgumentParser) -> None:
    """Add ``--remote``, ``--connect`` and ``--zenoh-config`` to ``parser``."""
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


def is_remote(args: argparse.Namespace) -> bool:
    """Whether the command should go to the services (``--zenoh-config`` too)."""
    return bool(args.remote or args.connect or args.zenoh_config)


def connect(args: argparse.Namespace) -> Bus:
    """A bus connected to the router named by the options.

    Raises:
        ServiceUnavailableError: if no router answers there.
        BusConfigError: if the configuration or endpoint is malformed.
    """
    config = load_config(args.zenoh_config, tuple(args.connect or ()))
    return Bus.connect(config)
