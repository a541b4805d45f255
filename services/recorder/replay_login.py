"""Which replayed messages a secured router would drop, by the replay's login.

A replay publishes every message as the one user of its configuration, while
the secured router's rules (config/secure/router.json5) let each topic be
published by its publisher only (``shared.bus.topics``: the planner's
``plan/*``, the bridge's ``bridge/*``, fit's model updates). A Zenoh put
gets no answer, so a replay with the client's file said "sent 485 of 485
messages" while the router dropped them all. :func:`refused_by_rules` names
the messages a login cannot publish under those rules, so the replay can say
so before it sends them. Keys outside the catalogue are not judged.
"""

from __future__ import annotations

from collections.abc import Mapping

from shared.bus.topics import find_topic

#: The login of another machine's router: its rules relay every armplan key.
ROUTER_USER = "router"


def refused_by_rules(counts: Mapping[str, int], user: str) -> dict[str, int]:
    """Each topic ``user`` may not publish, with its number of messages.

    Args:
        counts: The messages to replay per relative key, in first-seen order
            (``Replay.counts``).
        user: The replay's login, e.g. ``"client"``.

    Returns:
        ``{path: count}`` in first-seen order, e.g. ``{"plan/trajectory": 4}``.
    """
    if user == ROUTER_USER:
        return {}
    refused = {}
    for path, count in counts.items():
        topic = find_topic(path)
        if topic is not None and topic.publisher != user:
            refused[path] = count
    return refused


def refused_warning(refused: dict[str, int], user: str, source: str) -> str:
    """The warning for :func:`refused_by_rules`'s result (not empty)."""
    parts = [
        f"{path} ({count} message{'' if count == 1 else 's'}, {_publisher(path)}'s)"
        for path, count in refused.items()
    ]
    example = next(iter(refused))
    return (
        f"{source} logs in as user {user!r}, which the secured router's rules do "
        f"not let publish {', '.join(parts)}: the router drops those messages "
        "without a word. Replay each publisher's keys with its own file, e.g. "
        f"--keys {example} --config DIR/{_publisher(example)}.json5, or replay "
        "into an unsecured router"
    )


def _publisher(path: str) -> str:
    topic = find_topic(path)
    assert topic is not None
    return topic.publisher
