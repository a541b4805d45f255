"""A docstring's reST markup made plain, for ``--help``.

Descriptions taken from a module's docstring showed its Sphinx roles and
literals as written (``:class:`~shared.messages.ExecuteRequest` ``,
double backticks). :func:`plain_text` renders them as Sphinx would in
running text: a role shows its target (only its last dotted part after a
``~``), a literal its text.
"""

from __future__ import annotations

import re

#: A Sphinx role, ``:class:`X` `` or ``:py:func:`~a.b` ``: its target in group 2.
_ROLE = re.compile(r":(?:[a-z]+:)?[a-z]+:`(~?)([^`]+)`")
#: An inline literal: its text in group 1.
_LITERAL = re.compile(r"``(.+?)``", re.DOTALL)


def plain_text(text: str | None) -> str | None:
    """``text`` without reST roles and double backticks (None stays None).

    ``:class:`~a.b.C` `` -> ``C``; ``:mod:`a.b` `` -> ``a.b``;
    ````x```` -> ``x``. A role's explicit title (``:func:`title <target>` ``)
    is kept without its target.
    """
    if text is None:
        return None
    return _LITERAL.sub(r"\1", _ROLE.sub(_role_text, text))


def _role_text(match: re.Match[str]) -> str:
    """What a role shows: its title, else its target (last part after ``~``)."""
    short, target = match.group(1), match.group(2)
    titled = re.fullmatch(r"(.+?)\s*<[^>]*>", target, re.DOTALL)
    if titled:
        return titled.group(1)
    return target.rsplit(".", 1)[-1] if short else target
