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
under those rules, so the replay can say so before it sends them, and
refuse to start when every message would be dropped (:func:`check_publishable`).
The rules name one namespace, the one ``armplan certs --namespace`` wrote
into the login's file: a replay under another (``--namespace``) has every
key dropped, and :func:`check_rules_namespace` refuses it.
"""

from __future__ import annotations

from collections.abc import Mapping

import zenoh

from shared.bus.topics import find_topic
from shared.errors import InvalidInputError

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


def check_rules_namespace(
    user: str, namespace: str, rules_namespace: str, source: str
) -> None:
    """Refuse a replay under another namespace than its login's rules name.

    Args:
        user: The replay's login, e.g. ``"planner"``.
        namespace: The namespace the replay publishes under (``--namespace``).
        rules_namespace: The namespace of the login's file, which ``armplan
            certs --namespace`` also wrote into the router's rules.
        source: The login's file, for the message.

    Raises:
        InvalidInputError: if they differ: the router would drop every key.
    """
    if namespace == rules_namespace:
        return
    raise InvalidInputError(
        f"{source} logs in as user {user!r}, whose file was made for the "
        f"namespace {rules_namespace!r}, the only one the secured router's rules "
        f"name, but the replay publishes under --namespace {namespace!r}: the "
        "router would drop every message without a word, so none is sent. "
        f"Replay under {rules_namespace!r} (leave out --namespace), with a login "
        f"file made for {namespace!r} (`armplan certs --namespace {namespace}`) "
        "on that namespace's router, or into an unsecured router",
        field="namespace",
        namespace=namespace,
        rules_namespace=rules_namespace,
    )


def check_publishable(
    refused: dict[str, int], total: int, user: str, source: str, keys: bool
) -> None:
    """Refuse a replay of which the router would drop every message.

    Args:
        refused: :func:`refused_by_rules`'s result.
        total: The number of messages to replay.
        user: The replay's login.
        source: Its file, for the message.
        keys: Whether ``--keys`` chose the messages.

    Raises:
        InvalidInputError: if ``refused`` holds all ``total`` messages.
    """
    if not refused or sum(refused.values()) < total:
        return
    chosen = "every message --keys keeps" if keys else "every message"
    raise InvalidInputError(
        f"{_refused(refused, user, source)}: the router would drop {chosen} "
        f"without a word, so none is sent. {_advice(refused)}",
        field="keys" if keys else "config",
        user=user,
        refused=refused,
    )


def refused_warning(refused: dict[str, int], user: str, source: str) -> str:
    """The warning for :func:`refused_by_rules`'s result (not empty)."""
    return (
        f"{_refused(refused, user, source)}: the router drops those messages "
        f"without a word. {_advice(refused)}"
    )


def _refused(refused: dict[str, int], user: str, source: str) -> str:
    """Who logs in, and the keys (with counts and publisher) it may not publish."""
    parts = [
        f"{path} ({count} message{'' if count == 1 else 's'}, {_whose(path)})"
        for path, count in refused.items()
    ]
    return (
        f"{source} logs in as user {user!r}, which the secured router's rules do "
        f"not let publish {', '.join(parts)}"
    )


def _advice(refused: dict[str, int]) -> str:
    """What to do about the refused keys, as a sentence."""
    owned = [path for path in refused if publisher_of(path) is not None]
    advice = []
    if owned:
        advice.append(
            "replay each publisher's keys with its own file, e.g. "
            f"--keys {owned[0]} --config DIR/{publisher_of(owned[0])}.json5"
        )
    if len(owned) < len(refused):
        advice.append(
            "choose with --keys the keys to keep, without those no process may publish"
        )
    advice.append("or replay into an unsecured router")
    text = ", ".join(advice)
    return f"{text[:1].upper()}{text[1:]}"


def _whose(path: str) -> str:
    publisher = publisher_of(path)
    return "no process's" if publisher is None else f"{publisher}'s"
