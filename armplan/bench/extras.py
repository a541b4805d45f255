"""The peers' packages come with the development extra; say so if one is missing."""

from __future__ import annotations

import importlib.util

from shared.errors import ArmplanError


def require(*modules: str) -> None:
    """Raise ``ArmplanError`` naming the modules that are not installed."""
    missing = [name for name in modules if importlib.util.find_spec(name) is None]
    if missing:
        raise ArmplanError(
            f"the benchmark's peers need {', '.join(missing)}, from the development "
            "extra: pip install -c constraints.txt -e '.[dev]'",
            missing=missing,
        )
