"""Which arm a marker map's names say, against the arm it gives.

Labs name markers by side: Plug-in Gait's ``RSHO``/``LSHO``, or
``R_Shoulder``, ``LeftElbow``, ``wrist.L``. A map of ``LSHO``, ``LELB`` and
``LWRB`` that gives no ``arm`` was imported as the default right arm without
a word: the left arm's reaches, retargeted onto NAO's right arm, point its
elbow inwards and fit a wrong model. The names decide nothing on their own
(a lab may name markers as it likes); they only say when the map's arm
looks like the other one.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from shared.robot.side import Side

#: A side at the start of a name (``R``, ``Left``, ``l_``) or at its end
#: (``_R``, ``.left``). A lone letter counts only before a capital, a digit
#: or a separator, so that ``Radius`` or ``lat`` say nothing.
_PREFIX = re.compile(
    r"^(?:(?i:(left|right))|([LR])(?=[A-Z0-9_\-. ])|([lr])(?=[_\-. ]))"
)
_SUFFIX = re.compile(r"[_\-. ](?i:(left|right|l|r))$")


def named_side(names: Iterable[str]) -> Side | None:
    """The side every one of ``names`` says, or ``None`` if not all say one.

    A ``Subject:`` prefix (as C3D labels carry) is left out.
    """
    sides = {_side_of(name.split(":")[-1]) for name in names}
    if len(sides) != 1:
        return None
    return sides.pop()


def _side_of(name: str) -> Side | None:
    """The side ``name`` says by its first or last letters, if any."""
    found = _PREFIX.match(name) or _SUFFIX.search(name)
    if found is None:
        return None
    word = next(group for group in found.groups() if group is not None)
    return Side.LEFT if word[0].lower() == "l" else Side.RIGHT


def other_side_named(names: dict[str, str], arm: Side) -> str | None:
    """What the names say if they name the arm that is not ``arm``, else ``None``.

    Args:
        names: Role to marker name (``MarkerMap.names``).
        arm: The map's arm.
    """
    side = named_side(names.values())
    if side is None or side is arm:
        return None
    listed = ", ".join(names.values())
    return f"the markers ({listed}) are named like the {side.value} arm's"
