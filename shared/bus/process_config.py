"""The bus settings of a process that serves as its own user, checked at start.

A service process, the bridge and the recorder read ``--config``,
``--connect`` and ``--namespace`` (:func:`shared.bus.options.bus_config`)
and check that the file logs in as their own user
(:func:`shared.bus.login.check_login`). With a login file (the secured
set) the router's access rules name one namespace, the file's (``armplan
certs --namespace``): a process given another ``--namespace`` would still
connect and say it is ready, yet hold no token and serve nothing, its keys
all dropped without a word. So that is refused too, before connecting.
"""

from __future__ import annotations

import argparse

from shared.bus.config import BusConfig
from shared.bus.config_file import load_config
from shared.bus.login import check_login, login_user
from shared.bus.options import with_namespace
from shared.errors import BusConfigError


def process_config(args: argparse.Namespace, user: str) -> BusConfig:
    """The settings of ``--config``, ``--connect``, ``--namespace`` for ``user``.

    Args:
        args: The parsed options of :func:`~shared.bus.options.add_config_option`
            and :func:`~shared.bus.options.add_connect_options`.
        user: The process's own user, e.g. ``"ik"``.

    Raises:
        WrongLoginError: the file logs in as another user.
        BusConfigError: a malformed file, endpoint or namespace, or a login
            file with another ``--namespace`` than the file's own.
    """
    file_config = load_config(args.config, tuple(args.connect or ()))
    config = with_namespace(file_config, args.namespace)
    check_login(config, user)
    check_login_namespace(config, file_config.namespace)
    return config


def check_login_namespace(config: BusConfig, rules_namespace: str) -> None:
    """Refuse a login file used under another namespace than its own.

    Args:
        config: The settings as used (``--namespace`` applied).
        rules_namespace: The file's namespace, the one the secured router's
            rules name, e.g. ``"armplan"``.

    Raises:
        BusConfigError: naming both namespaces and the way out.
    """
    user = login_user(config)
    if user is None or config.namespace == rules_namespace:
        return
    raise BusConfigError(
        f"logs in as user {user!r}, whose file was made for the namespace "
        f"{rules_namespace!r}, the only one the secured router's rules name, "
        f"but --namespace is {config.namespace!r}: the router would drop every "
        "key of this process without a word, so it does not start. Leave out "
        f"--namespace, or use a file made for {config.namespace!r} (`armplan "
        f"certs --namespace {config.namespace}`) on that namespace's router",
        source=config.source,
        setting="namespace",
    )
