"""The simulated NAO's log (bridge.sim.log): its file, and what it keeps in memory."""

from __future__ import annotations

from pathlib import Path

from bridge.sim.log import SimLog, read_log


def _write(log: SimLog, count: int) -> None:
    """``count`` ``state`` entries, numbered by ``cycle``."""
    for cycle in range(count):
        log.write("state", cycle=cycle, positions={"RHand": 0.5})


def test_no_entry_is_kept_in_memory_unless_asked() -> None:
    """The sim's process never reads its log back: it kept the last 20 000
    entries in memory, --log given or not; by default now none."""
    log = SimLog()
    _write(log, 3)
    assert log.entries() == []


def test_the_last_keep_entries_are_kept() -> None:
    """An in-process reader that asks for ``keep`` entries gets the last ones."""
    log = SimLog(keep=2)
    _write(log, 5)
    assert [e["cycle"] for e in log.entries()] == [3, 4]


def test_the_file_gets_every_entry_whatever_is_kept(tmp_path: Path) -> None:
    """``--log FILE`` is where the entries go, each one, none kept in memory."""
    path = tmp_path / "sim.jsonl"
    log = SimLog(path)
    _write(log, 5)
    log.close()
    assert [e["cycle"] for e in read_log(path)] == [0, 1, 2, 3, 4]
    assert log.entries() == []
