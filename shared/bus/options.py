"""The command-line options that say which router and namespace to use.

Shared by the commands that join a running system (``armplan stop``,
``status``, ``record``, ``replay``, ``python -m services.recorder``, the
service processes ``python -m services.<name>`` and ``python -m
bridge.serve``), the client commands' ``--remote`` options
(``armplan.cli.remote``: ``--namespace`` and :func:`with_namespace`) and
those that start one (``armplan up``: ``--config`` and ``--namespace``;
``demo``: ``--config`` only), so each option reads and behaves the same
everywhere.
"""

from __future__ import annotations

import argparse
import dataclasses

from shared.bus.config import MAX_WAIT, BusConfig
from shared.bus.config_file import load_config

#: ``--namespace``'s help where a command does not say more.
NAMESPACE_HELP = "key namespace (default: the config's, armplan)"


def add_config_option(parser: argparse.ArgumentParser) -> None:
    """``--config FILE``: the armplan Zenoh config."""
    parser.add_argument(
        "--config", metavar="FILE", help="armplan Zenoh config (default: the repo's)"
    )


def add_connect_options(
    parser: argparse.ArgumentParser, namespace_help: str = NAMESPACE_HELP
) -> None:
    """``--connect ENDPOINT`` (repeatable) and ``--namespace NS``.

    ``namespace_help`` is ``--namespace``'s help; ``--config`` is added
    apart (:func:`add_config_option`).
    """
    parser.add_argument(
        "--connect",
        action="append",
        metavar="ENDPOINT",
        help="router endpoint (default tcp/127.0.0.1:7447, from the config)",
    )
    add_namespace_option(parser, namespace_help)


def add_namespace_option(
    parser: argparse.ArgumentParser, help_text: str = NAMESPACE_HELP
) -> None:
    """``--namespace NS``: the key namespace instead of the config's."""
    parser.add_argument("--namespace", metavar="NS", help=help_text)


def add_router_wait_option(parser: argparse.ArgumentParser) -> None:
    """``--wait S``: how long a process waits for the router at its start."""
    parser.add_argument(
        "--wait",
        type=router_wait,
        default=10.0,
        metavar="S",
        help="how long to wait for the router at start [s] (default 10)",
    )


def router_wait(text: str) -> float:
    """``text`` as a wait for the router [s]: 0 (try once) up to ``MAX_WAIT``.

    ``--wait nan`` waited for ever, saying nothing (no deadline is passed by
    NaN), and ``--wait -1`` tried once as 0 does.

    Raises:
        argparse.ArgumentTypeError: naming ``text``, for anything else.
    """
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.0 <= value <= MAX_WAIT:  # NaN too
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a number of seconds from 0 to {MAX_WAIT:g} (a day)"
        )
    return value


def bus_config(args: argparse.Namespace) -> BusConfig:
    """The bus settings of ``--config``, ``--connect`` and ``--namespace``.

    Raises:
        BusConfigError: if the file, an endpoint or the namespace is malformed.
    """
    config = load_config(args.config, tuple(args.connect or ()))
    return with_namespace(config, getattr(args, "namespace", None))


def with_namespace(config: BusConfig, namespace: str | None) -> BusConfig:
    """``config`` with the namespace of ``--namespace``; unchanged for ``None``.

    The source stays the file (its checks, the ``--config`` a child gets);
    ``namespace_from`` names the option, so an error names both.

    Raises:
        BusConfigError: if ``namespace`` is malformed (e.g. ``lab/*``).
    """
    if namespace is None:
        return config
    return dataclasses.replace(
        config, namespace=namespace, namespace_from="--namespace"
    )
