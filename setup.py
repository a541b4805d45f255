"""Build armplan, compiling the IK's hot loop with mypyc when a C compiler is there.

The modules are listed in ``shared/compiled.py``. Each extension is
optional: if it cannot be built (no C compiler, as in a slim container),
the install goes on and the module runs as Python. ``ARMPLAN_PURE=1``
skips compiling altogether. Everything else is in ``pyproject.toml``.
"""

import os
import runpy
from pathlib import Path

from setuptools import setup

HERE = Path(__file__).resolve().parent
#: mypy's options for the compiled modules (not pyproject's [tool.mypy], which
#: checks the whole tree with the pydantic plugin).
MYPY_OPTIONS = [
    "--config-file=",
    "--python-version=3.11",
    "--ignore-missing-imports",
    "--follow-imports=silent",
    "--check-untyped-defs",
]


def compiled_extensions() -> list:
    """The mypyc extensions of the listed modules, or none."""
    if os.environ.get("ARMPLAN_PURE"):
        return []
    listing = HERE / "shared" / "compiled.py"
    if not listing.exists():
        return []
    modules = runpy.run_path(str(listing))["MODULES"]
    paths = [name.replace(".", "/") + ".py" for name in modules]
    if not all((HERE / p).exists() for p in paths):
        return []  # a partial tree (the Dockerfile's dependency layer)
    from mypyc.build import mypycify

    extensions = mypycify(MYPY_OPTIONS + paths, opt_level="3")
    for extension in extensions:
        extension.optional = True
    return extensions


setup(ext_modules=compiled_extensions())
