"""Build armplan, compiling the IK's hot loop with mypyc when a C compiler is there.

The modules are listed in ``shared/compiled.py``. Each extension is
optional: if it cannot be built (no C compiler, as in a slim container),
the install goes on and the module runs as Python. ``ARMPLAN_PURE=1``
skips compiling altogether. After building, the SHA-256 of each compiled
source goes to ``shared/compiled_sources.json``, which the guard in
``shared.compiled`` checks. Everything else is in ``pyproject.toml``.
"""

import hashlib
import json
import os
import runpy
from pathlib import Path

from setuptools import setup
from setuptools.command.build_ext import build_ext

HERE = Path(__file__).resolve().parent
LISTING = HERE / "shared" / "compiled.py"
#: mypy's options for the compiled modules (not pyproject's [tool.mypy], which
#: checks the whole tree with the pydantic plugin).
MYPY_OPTIONS = [
    "--config-file=",
    "--python-version=3.11",
    "--ignore-missing-imports",
    "--follow-imports=silent",
    "--check-untyped-defs",
]


def listed() -> list[str]:
    """The modules to compile, or none if the tree is partial."""
    if os.environ.get("ARMPLAN_PURE") or not LISTING.exists():
        return []
    modules = list(runpy.run_path(str(LISTING))["MODULES"])
    if not all(_path(name).exists() for name in modules):
        return []  # a partial tree (the Dockerfile's dependency layer)
    return modules


def _path(name: str) -> Path:
    return HERE.joinpath(*name.split(".")).with_suffix(".py")


def compiled_extensions(modules: list[str]) -> list:
    """The mypyc extensions of ``modules``, each optional."""
    if not modules:
        return []
    from mypyc.build import mypycify

    paths = [str(_path(name).relative_to(HERE)) for name in modules]
    extensions = mypycify(MYPY_OPTIONS + paths, opt_level="3")
    for extension in extensions:
        extension.optional = True
    return extensions


class BuildAndStamp(build_ext):
    """build_ext, then the record of which sources the built extensions are."""

    def run(self) -> None:
        super().run()
        built = {}
        for name in listed():
            target = Path(self.get_ext_fullpath(name))
            if not target.is_absolute():
                target = HERE / target
            if target.exists():
                built[name] = hashlib.sha256(_path(name).read_bytes()).hexdigest()
        root = HERE if self.inplace else Path(self.build_lib)
        stamp = root / "shared" / "compiled_sources.json"
        stamp.parent.mkdir(parents=True, exist_ok=True)
        stamp.write_text(json.dumps(built, indent=1, sort_keys=True) + "\n")


setup(
    ext_modules=compiled_extensions(listed()),
    cmdclass={"build_ext": BuildAndStamp},
)
