r"""Text from a file, made safe to print: its control characters escaped.

A name a file supplies (an MCAP channel's topic, a schema name, a metadata
value) reaches the user's terminal in tables and error messages. Printed as
it is, a name holding ``ESC [2J`` clears the screen, ``ESC ]0;...`` retitles
the window, and colour codes, a carriage return or a backspace forge what
the line says. :func:`printable` writes every character Python does not
call printable (control and format characters, line and paragraph breaks,
unassigned code points) as ``repr`` does: ``\x1b``, ``\n``, ``\u202e``.
"""

from __future__ import annotations


def printable(text: str) -> str:
    """``text`` with each unprintable character as its ``repr`` escape.

    Printable text (letters, digits, punctuation, the space) is returned as
    it is, backslashes included, so an ordinary name prints as itself.

    Args:
        text: A name or message that may come from a file.
    """
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def printable_lines(text: str) -> str:
    """``text`` made :func:`printable` line by line, its line breaks kept.

    For a whole message (an error's) that may span lines on purpose.
    """
    return "\n".join(printable(line) for line in text.split("\n"))
