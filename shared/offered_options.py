"""The options the running command offers to reach the router, for hints.

When no router answers, the error says what to give: the router's address
(``--connect``) and the client file ``armplan certs`` wrote. Not every
command has those options: ``armplan stop`` names its file with
``--config``, ``armplan plan --remote`` with ``--zenoh-config``, and
``armplan up`` and ``demo`` take no ``--connect``. The ``armplan`` command
line says what the command it runs offers (:func:`offering`); a process
that says nothing offers ``--config`` and ``--connect``, as every
``python -m`` service, the recorder and the bridge do.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from contextlib import contextmanager

#: What a ``python -m`` process offers (``shared.bus.process``, ``runner``).
DEFAULT = frozenset({"--config", "--connect"})

_offered = DEFAULT


def offered() -> frozenset[str]:
    """The option strings of the running command (``--config``, ...)."""
    return _offered


@contextmanager
def offering(options: Iterable[str]) -> Iterator[None]:
    """Within the block the running command offers ``options``; then as before."""
    global _offered
    before, _offered = _offered, frozenset(options)
    try:
        yield
    finally:
        _offered = before


def config_option() -> str | None:
    """The option that names the command's Zenoh config file, if it has one."""
    for option in ("--zenoh-config", "--config"):
        if option in _offered:
            return option
    return None
