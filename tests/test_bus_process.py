"""What every bus process does once it has set up (``shared.bus.process``)."""

from __future__ import annotations

import gc
import threading
from collections.abc import Iterator

import pytest

from shared.bus.process import wait_for


@pytest.fixture
def unfrozen() -> Iterator[None]:
    """Start with nothing frozen and put the test process back so after."""
    gc.unfreeze()
    yield
    gc.unfreeze()


def _tracked(thing: object) -> bool:
    """Whether the garbage collector's full collections scan ``thing``."""
    return any(other is thing for other in gc.get_objects())


@pytest.mark.usefixtures("unfrozen")
def test_waiting_to_be_stopped_freezes_what_the_set_up_made() -> None:
    """A service waits for its stop once set up: its models, sessions and
    imports are then frozen out of the collector's scans (a planner's first
    full collection took 64-80 ms), and what it makes later is not."""
    set_up = {"model": [[0.1, 0.2], [0.3]]}  # containers: tracked by the collector
    assert _tracked(set_up)
    stop = threading.Event()
    threading.Timer(0.05, stop.set).start()
    wait_for(stop)
    assert gc.get_freeze_count() > 0
    assert not _tracked(set_up)
    later = {"request": [1.0]}
    assert _tracked(later)
    cycle: list[object] = []
    cycle.append(cycle)  # made after the freeze: collected as before
    del cycle
    assert gc.collect() >= 1
