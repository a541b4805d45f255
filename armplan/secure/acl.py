"""The router's access rules, read back from its configuration file.

:class:`AccessControl` answers the question a Zenoh router asks of every
message: may this user send (``ingress``) or receive (``egress``) this
message on this key? It follows Zenoh 1.x's ``access_control`` semantics for
subjects given by user name (subjects given otherwise, e.g. by certificate,
are not evaluated): a deny rule that matches wins over an allow
rule that matches, and a message no rule matches gets ``default_permission``.
It answers for concrete keys (no wildcards); tests use it to check the rules
against the catalogue, and ``tests/test_security.py`` checks the real router
agrees on the cases that matter.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import zenoh

from armplan.secure.errors import SecureSetupError

#: The message kinds of Zenoh's access control.
MESSAGES = (
    "put",
    "delete",
    "declare_subscriber",
    "query",
    "reply",
    "declare_queryable",
    "liveliness_token",
    "liveliness_query",
    "declare_liveliness_subscriber",
)
FLOWS = ("ingress", "egress")


@dataclass(frozen=True)
class AccessControl:
    """A router's ``access_control`` section.

    Attributes:
        section: The section as JSON data (``enabled``, ``default_permission``,
            ``rules``, ``subjects``, ``policies``).
    """

    section: dict[str, Any]

    @classmethod
    def from_file(cls, path: str | Path) -> AccessControl:
        """The section of the Zenoh configuration file at ``path``."""
        try:
            config = zenoh.Config.from_json5(Path(path).read_text())
            section = json.loads(config.get_json("access_control"))
        except (OSError, zenoh.ZError) as error:
            raise SecureSetupError(
                f"cannot read access_control from {path}: {error}", path=str(path)
            ) from None
        return cls(section)

    def usernames(self) -> list[str]:
        """Every user name a subject names, in order."""
        names = [n for s in self.section["subjects"] for n in _usernames(s)]
        return list(dict.fromkeys(names))

    def rules_of(self, user: str) -> list[dict[str, Any]]:
        """The rules that apply to ``user``'s sessions."""
        subjects = {s["id"] for s in self.section["subjects"] if user in _usernames(s)}
        ids = [
            rule
            for policy in self.section["policies"]
            if subjects & set(policy["subjects"])
            for rule in policy["rules"]
        ]
        by_id = {rule["id"]: rule for rule in self.section["rules"]}
        return [by_id[i] for i in dict.fromkeys(ids)]

    def allows(self, user: str, message: str, flow: str, key: str) -> bool:
        """Whether ``user`` may send (ingress) or receive (egress) ``message``.

        Args:
            user: The session's user name, e.g. ``"planner"``.
            message: One of :data:`MESSAGES`, e.g. ``"put"``.
            flow: ``"ingress"`` (from the session into the router) or ``"egress"``.
            key: A concrete key, e.g. ``"armplan/plan/trajectory"``.
        """
        if message not in MESSAGES or flow not in FLOWS:
            raise ValueError(f"unknown message {message!r} or flow {flow!r}")
        if not self.section.get("enabled", False):
            return True
        found = {
            rule["permission"]
            for rule in self.rules_of(user)
            if message in rule["messages"]
            and flow in rule.get("flows", FLOWS)
            and any(_includes(k, key) for k in rule["key_exprs"])
        }
        if found:
            return "deny" not in found
        return bool(self.section.get("default_permission", "deny") == "allow")


def _usernames(subject: dict[str, Any]) -> list[str]:
    """A subject's user names (none for one given by certificate or interface)."""
    return list(subject.get("usernames") or [])


def _includes(pattern: str, key: str) -> bool:
    return bool(zenoh.KeyExpr(pattern).includes(zenoh.KeyExpr(key)))
