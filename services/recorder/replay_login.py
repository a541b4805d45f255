"""Which replayed messages a secured router would drop, by the replay's login.

A replay publishes every message as the one user of its configuration, while
the secured router's rules (config/secure/router.json5) let each topic be
published by its publisher only (``shared.bus.topics``: the planner's
``plan/*``, the bridge's ``bridge/*``, fit's model updates), and any other
key under the namespace by no process (the bridge excepted: every key under
``bridge/``). A Zenoh put gets no answer, so a replay with the client's file
said "sent 485 of 485 messages" while the router dropped them all, and a
file of another tool with a key outside the catalogue was dropped without a
warning. :func:`refused_by_rules` names the messages a login cannot publish
under those rules, so the replay can say so before it sends them.
"""

from __future__ import annotations

from collections.abc import Mapping

import zenoh

from shared.bus.topics import find_topic

#: The login of another machine's router: its rules relay every armplan key.
ROUTER_USER = "router"
#: Logins that may publish every key under a subtree, beyond their topics
#: (the router's rule ``bridge_publishes``: ``armplan/bridge/**``).
SUBTREES = {"bridge": "bridge/**"}


def publisher_of(path: str) -> str | None:
    """The login the rules let publish the relative key ``path``, if one.

    E.g. ``"planner"`` for ``plan/trajectory``, ``"bridge"`` for
    ``bridge/anything``, ``None`` for ``misc/raw`` (``router`` aside).
    """
    topic = find_topic(path)
    if topic is not None:
        return topic.publisher
    key = zenoh.KeyExpr(f"r/{path}")
    for user, subtree in SUBTREES.items():
        if zenoh.KeyExpr(f"r/{subtree}").includes(key):
            return user
    return None


def refused_by_rules(counts: Mapping[str, int], user: str) -> dict[str, int]:
    """Each key ``user`` may not publish, with its number of messages.

    Args:
        counts: The messages to replay per relative key, in first-seen order
            (``Replay.counts``; each a Zenoh key).
        user: The replay's login, e.g. ``"client"``.

    Returns:
        ``{path: count}`` in first-seen order, e.g. ``{"plan/trajectory": 4}``.
    """
    if user == ROUTER_USER:
        return {}
    return {path: n for path, n in counts.items() if publisher_of(path) != user}


def refused_warning(refused: dict[str, int], user: str, source: str) -> str:
    """The warning for :func:`refused_by_rules`'s result (not empty)."""
    parts = [
        f"{path} ({count} message{'' if count == 1 else 's'}, {_whose(path)})"
        for path, count in refused.items()
    ]
    owned = [path for path in refused if publisher_of(path) is not None]
    advice = []
    if owned:
        advice.append(
            "replay each publisher's keys with its own file, e.g. "
            f"--keys {owned[0]} --config DIR/{publisher_of(owned[0])}.json5"
        )
    if len(owned) < len(refused):
        advice.append("leave out with --keys the keys no process may publish")
    advice.append("or replay into an unsecured router")
    text = ", ".join(advice)
    return (
        f"{source} logs in as user {user!r}, which the secured router's rules do "
        f"not let publish {', '.join(parts)}: the router drops those messages "
        f"without a word. {text[:1].upper()}{text[1:]}"
    )


def _whose(path: str) -> str:
    publisher = publisher_of(path)
    return "no process's" if publisher is None else f"{publisher}'s"
