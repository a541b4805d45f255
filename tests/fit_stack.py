"""A router and a real fit service reading a folder of two demonstration sets."""

from __future__ import annotations

import contextlib
import pathlib
from collections.abc import Iterator

import pytest

from armplan.launch import Launcher, free_endpoint
from services.fit.demo_dir import DEMOS_DIR_ENV
from shared.bus import load_config
from shared.demos import synthesize, write_demos

BIG = "big.mcap"  # 16 points x 5 subjects x 2 trials: seconds to fit
SMALL = "small.mcap"


@contextlib.contextmanager
def fit_stack(
    folder: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> Iterator[tuple[Launcher, pathlib.Path]]:
    """Router and fit service reading ``folder`` (``BIG``, ``SMALL``); the
    service's log file."""
    write_demos(folder / BIG, synthesize(9, subjects=5, trials=2))
    write_demos(folder / SMALL, synthesize(9, subjects=1, trials=1))
    monkeypatch.setenv(DEMOS_DIR_ENV, str(folder))
    log = folder / "fit.log"
    config = load_config(endpoints=(free_endpoint(),))
    with log.open("w") as out, Launcher(config, ["fit"], log=out) as launched:
        yield launched, log
