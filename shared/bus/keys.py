"""Key expressions of armplan on Zenoh: everything lives under one namespace.

A namespace is one or more plain chunks (``armplan``, ``robots/nao1``), so two
robots can share a router with namespaces ``nao1`` and ``nao2``. Under it:

- ``<ns>/<path>``: a service's queryable, e.g. ``armplan/ik/solve``;
- ``<ns>/alive/<service>``: the liveliness token of a running service;
- ``<ns>/caller/<session id>``: the liveliness token of every open bus, so a
  service can tell that a caller's session has ended (its process
  interrupted or killed) before it publishes what only that caller wanted.
"""

from __future__ import annotations

import re

from shared.errors import InvalidInputError

#: One key chunk: letters, digits, ``_`` and ``-`` (no wildcards, no ``$``).
_CHUNK = r"[A-Za-z0-9_\-]+"
#: Matched whole (``fullmatch``): ``$`` would let a trailing newline through.
_PATH = re.compile(rf"{_CHUNK}(/{_CHUNK})*")
_NAME = re.compile(_CHUNK)
#: The chunk under which liveliness tokens live.
ALIVE = "alive"
#: The chunk under which each open bus's caller token lives.
CALLER = "caller"


def check_path(path: str, what: str) -> str:
    """``path`` if it is plain chunks joined by ``/``; else ``InvalidInputError``."""
    if not _PATH.fullmatch(path):
        raise InvalidInputError(
            f"{what} {path!r} must be chunks of letters, digits, '_' or '-' "
            "joined by '/', without wildcards",
            field=what,
        )
    return path


def check_name(name: str) -> str:
    """``name`` if it is a valid service name (one chunk, e.g. ``"ik"``)."""
    if not _NAME.fullmatch(name):
        raise InvalidInputError(
            f"service name {name!r} must be one chunk of letters, digits, '_' or '-'",
            field="service",
        )
    return name


def service_key(namespace: str, path: str) -> str:
    """The full key of a service path, e.g. ``armplan/ik/solve``."""
    return f"{namespace}/{path}"


def alive_key(namespace: str, service: str) -> str:
    """The liveliness token key of ``service``, e.g. ``armplan/alive/ik``."""
    return f"{namespace}/{ALIVE}/{service}"


def alive_pattern(namespace: str) -> str:
    """The key expression matching every service's liveliness token."""
    return f"{namespace}/{ALIVE}/*"


def alive_anywhere(service: str) -> str:
    """The key expression matching ``service``'s token in every namespace.

    E.g. ``**/alive/bridge``: asked once a wait has failed, to say where else
    the service is alive (another ``--namespace``).
    """
    return f"**/{ALIVE}/{service}"


def namespace_from_alive_key(key: str, service: str) -> str:
    """The namespace of a token key of ``service`` (``lab1/alive/bridge``: ``lab1``).

    ``""`` if ``key`` is not such a key (e.g. ``alive/bridge``, without one).
    """
    suffix = f"/{ALIVE}/{service}"
    return key.removesuffix(suffix) if key.endswith(suffix) else ""


def service_from_alive_key(namespace: str, key: str) -> str:
    """The service name in a liveliness token key (inverse of :func:`alive_key`)."""
    return key.removeprefix(f"{namespace}/{ALIVE}/")


def caller_key(namespace: str, session: str) -> str:
    """The caller token of the session ``session`` (its Zenoh id, hex).

    E.g. ``armplan/caller/8f3a...``.
    """
    return f"{namespace}/{CALLER}/{session}"


def caller_pattern(namespace: str) -> str:
    """The key expression matching every open bus's caller token."""
    return f"{namespace}/{CALLER}/*"
