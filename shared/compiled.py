"""The modules compiled to C with mypyc, and the guard against a stale build.

The IK's hot loop (forward kinematics, the weighted step of eq. 14, the
measures, the decision at each path point) is plain typed Python. Installing
armplan (``pip install -e .``) compiles these modules with mypyc when a C
compiler is there (``setup.py``); the extension modules then sit beside the
sources and Python loads them instead. Without a compiler the install goes
on and the same code runs as Python, slower (``armplan bench`` says which).

An editable install keeps the compiled modules of the day it ran: edit one
of these files and the extension would still run the old code. So the build
writes the SHA-256 of each compiled source to ``shared/compiled_sources.json``
and the guard checks them once, at the first import of ``shared``: if any
extension's source differs from what was compiled (or was not recorded),
every module of the list is loaded from its source (mixing would let
compiled callers reach old compiled callees) and a warning says to
reinstall.
"""

from __future__ import annotations

import hashlib
import importlib.abc
import importlib.machinery
import importlib.util
import json
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType

#: Compiled modules, by name (``setup.py`` reads this tuple).
MODULES: tuple[str, ...] = (
    "services.ik.kernel.chain",
    "services.ik.kernel.small",
    "services.ik.weighted",
    "services.ik.gpm",
    "services.ik.task",
    "services.ik.track",
    "services.ik.iterate",
    "services.ik.measures.base",
    "services.ik.measures.tpe",
    "services.ik.measures.ntpe",
    "services.ik.measures.elbow_travel",
    "services.ik.measures.grasp",
    "services.ik.measures.swivel_goal",
    "shared.geometry.swivel",
    "shared.geometry.palm",
    "services.decide.decider",
    "services.decide.point",
    "services.fit.variables",
)

#: The record of compiled sources, beside this file: module name -> SHA-256.
STAMP = "compiled_sources.json"

_ROOT = Path(__file__).resolve().parent.parent


def source(name: str, root: Path = _ROOT) -> Path:
    """The source file of module ``name`` under ``root`` (the project's)."""
    return root.joinpath(*name.split(".")).with_suffix(".py")


def extension(name: str, root: Path = _ROOT) -> Path | None:
    """The compiled extension of module ``name`` beside its source, if any."""
    path = source(name, root)
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        candidate = path.with_suffix(suffix)
        if candidate.exists():
            return candidate
    return None


def digest(path: Path) -> str:
    """SHA-256 of a file's bytes, hex."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def stale(modules: Sequence[str] = MODULES, root: Path = _ROOT) -> list[str]:
    """Modules with an extension whose source is not the one compiled."""
    stamp = root / "shared" / STAMP
    built: dict[str, str] = json.loads(stamp.read_text()) if stamp.exists() else {}
    return [
        name
        for name in modules
        if extension(name, root) is not None
        and built.get(name) != digest(source(name, root))
    ]


def running_compiled() -> bool:
    """True if this process runs every listed module compiled."""
    return all(_is_extension(importlib.import_module(name)) for name in MODULES)


def _is_extension(module: ModuleType | None) -> bool:
    origin = getattr(getattr(module, "__spec__", None), "origin", None) or ""
    return origin.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES))


class _Sources(importlib.abc.MetaPathFinder):
    """Finds the listed modules' sources, ahead of their stale extensions."""

    def find_spec(
        self,
        fullname: str,
        path: Sequence[str] | None,
        target: ModuleType | None = None,
    ) -> importlib.machinery.ModuleSpec | None:
        if fullname not in MODULES:
            return None
        return importlib.util.spec_from_file_location(fullname, source(fullname))


def guard() -> None:
    """Load every listed module from source if any extension is stale."""
    changed = stale()
    if changed and not any(isinstance(f, _Sources) for f in sys.meta_path):
        sys.meta_path.insert(0, _Sources())
        warnings.warn(
            f"{changed[0]} changed since it was compiled: running the IK as "
            "Python, slower; reinstall (pip install -e .) to compile it again",
            stacklevel=2,
        )
