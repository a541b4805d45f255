"""Warn when a recorder starts in a namespace where no armplan process runs.

A recorder under ``--namespace nao1`` while every service runs under
``armplan`` recorded 0 messages and said nothing. It is not refused (a
recorder may be started before the services it records): it logs a
warning naming its namespace and the namespaces that do have processes
alive (their liveliness tokens, ``<ns>/alive/<service>``).
"""

from __future__ import annotations

import logging

import zenoh

from shared.bus import Bus
from shared.bus.liveness import alive_by_namespace

log = logging.getLogger("armplan.recorder")


def nobody_alive_note(bus: Bus, me: str) -> str | None:
    """The warning for a namespace with no process alive but recorders, or ``None``.

    Args:
        bus: The recorder's open bus.
        me: The recorder's service name: recorders publish nothing, so
            they do not count.
    """
    namespace = bus.config.namespace
    if set(bus.alive()) - {me}:
        return None
    others = {
        ns: services
        for ns, services in alive_by_namespace(bus.session).items()
        if ns != namespace and set(services) - {me}
    }
    where = (
        f"processes are alive under {', '.join(repr(ns) for ns in others)}: "
        "check --namespace"
        if others
        else "it records what they publish once they start"
    )
    return (
        f"recorder: no armplan process is alive in namespace {namespace!r}, "
        f"so nothing is published under {namespace}/ yet; {where}"
    )


def warn_if_nobody_alive(bus: Bus, me: str) -> None:
    """Log :func:`nobody_alive_note` if there is one (a failed query: none)."""
    try:
        note = nobody_alive_note(bus, me)
    except zenoh.ZError as error:  # a hint only: the recording goes on
        log.debug("recorder: could not ask which processes are alive: %s", error)
        return
    if note is not None:
        log.warning("%s", note)
