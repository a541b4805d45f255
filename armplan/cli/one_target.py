"""``--target`` given once: ``ik`` and ``decide`` take one target.

``armplan plan --target A --target B`` reaches A, then B. The same line to
``armplan ik`` or ``armplan decide`` kept the last ``--target`` and dropped
the others without a word (argparse's last-wins): an answer for B alone,
exit 0. :class:`OneTarget` refuses a second ``--target`` instead, as a
malformed command line (exit 2), pointing to ``plan`` for several.
"""

from __future__ import annotations

import argparse
from typing import Any


class OneTarget(argparse.Action):
    """Stores ``--target``'s values; a second ``--target`` is an argument error."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        if getattr(namespace, self.dest, None) is not None:
            command = parser.prog.split()[-1]
            raise argparse.ArgumentError(
                self,
                f"given twice: {command} takes one target (armplan plan "
                "reaches several, one after another)",
            )
        setattr(namespace, self.dest, values)
