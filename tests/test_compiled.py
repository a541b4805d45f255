"""The compiled IK modules: built by the install, and never stale."""

import importlib.machinery
import json
import subprocess
import sys
from pathlib import Path

import pytest

import shared.compiled as compiled
from shared.compiled import MODULES, STAMP, digest, extension, source, stale

SUFFIX = importlib.machinery.EXTENSION_SUFFIXES[0]


def _tree(tmp_path: Path, name: str, text: str, built: bool = True) -> None:
    code = source(name, tmp_path)
    code.parent.mkdir(parents=True, exist_ok=True)
    code.write_text(text)
    if built:
        code.with_suffix(SUFFIX).write_bytes(b"")


def test_every_listed_module_has_its_source() -> None:
    assert len(set(MODULES)) == len(MODULES)
    for name in MODULES:
        assert source(name).is_file(), name


def test_an_extension_of_another_source_is_stale(tmp_path: Path) -> None:
    """Stale: a source edited since, or one the build did not record."""
    _tree(tmp_path, "pkg.fresh", "x = 1\n")
    _tree(tmp_path, "pkg.edited", "x = 1\n")
    _tree(tmp_path, "pkg.unrecorded", "x = 1\n")
    _tree(tmp_path, "pkg.plain", "x = 1\n", built=False)
    stamp = tmp_path / "shared" / STAMP
    stamp.parent.mkdir()
    recorded = {n: digest(source(n, tmp_path)) for n in ("pkg.fresh", "pkg.edited")}
    stamp.write_text(json.dumps(recorded))
    source("pkg.edited", tmp_path).write_text("x = 2\n")
    names = ["pkg.fresh", "pkg.edited", "pkg.unrecorded", "pkg.plain"]
    assert stale(names, tmp_path) == ["pkg.edited", "pkg.unrecorded"]
    assert extension("pkg.plain", tmp_path) is None


def test_the_installed_extensions_are_loaded_when_fresh() -> None:
    built = [name for name in MODULES if extension(name) is not None]
    if not built:
        pytest.skip("installed without a C compiler: the modules run as Python")
    assert not stale(), "reinstall (pip install -e .): a compiled module is stale"
    assert compiled.running_compiled()


def test_a_stale_build_runs_every_module_from_source(tmp_path: Path) -> None:
    """With the guard's finder in place, the listed modules load from source."""
    script = (
        "import sys, warnings\n"
        "import shared.compiled as c\n"
        "c.stale = lambda *a, **k: ['services.ik.track']\n"
        "with warnings.catch_warnings(record=True) as seen:\n"
        "    warnings.simplefilter('always')\n"
        "    c.guard()\n"
        "import services.ik.track, services.ik.kernel.chain\n"
        "print(services.ik.track.__file__, services.ik.kernel.chain.__file__)\n"
        "print(c.running_compiled(), 'reinstall' in str(seen[0].message))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    ).stdout.split()
    assert out[0].endswith("track.py") and out[1].endswith("chain.py")
    assert out[2:] == ["False", "True"]
