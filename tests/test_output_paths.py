"""Files written under partial names and renamed to theirs together, or not at all."""

from __future__ import annotations

from pathlib import Path

import pytest

from shared.errors import InvalidInputError
from shared.output_paths import replaced_together

NAMES = ("result.json", "result.md", "result.png")


@pytest.fixture
def older(tmp_path: Path) -> list[Path]:
    """An older set of the three files, each holding ``older <name>``."""
    paths = [tmp_path / name for name in NAMES]
    for path in paths:
        path.write_text(f"older {path.name}")
    return paths


def contents(folder: Path) -> dict[str, str]:
    """Every file in ``folder`` by name, with its text."""
    return {path.name: path.read_text() for path in sorted(folder.iterdir())}


def test_a_whole_set_replaces_the_older_one(older: list[Path]) -> None:
    """Once the block has written every partial file, each takes its name."""
    with replaced_together(older) as partials:
        for partial in partials:
            partial.write_text(f"newer {partial.name}")
    assert contents(older[0].parent) == {n: f"newer {n}.partial" for n in NAMES}


def test_a_failure_in_the_block_leaves_the_older_set(older: list[Path]) -> None:
    """Ctrl-C after two of three files: nothing replaced, no partial file left."""
    with pytest.raises(KeyboardInterrupt), replaced_together(older) as partials:
        partials[0].write_text("newer")
        partials[1].write_text("newer")
        raise KeyboardInterrupt
    assert contents(older[0].parent) == {n: f"older {n}" for n in NAMES}


def test_a_folder_in_a_files_place_leaves_the_older_set(older: list[Path]) -> None:
    """A folder where the last file goes: a typed error naming it, before any
    file is renamed, and no partial file left."""
    older[-1].unlink()
    older[-1].mkdir()
    with pytest.raises(InvalidInputError) as caught, replaced_together(older) as new:
        for partial in new:
            partial.write_text("newer")
    assert caught.value.message == f"cannot write {older[-1]}: Is a directory"
    assert caught.value.field == "out"
    older[-1].rmdir()
    assert contents(older[0].parent) == {n: f"older {n}" for n in NAMES[:-1]}


def test_a_failed_write_names_the_file_asked_for(older: list[Path]) -> None:
    """A write that fails inside the block (a folder stands at a partial
    name, as a full disk would fail it) named 'result.md.partial'; the
    error names result.md, and the older set stays whole."""
    partial_md = older[1].with_name(older[1].name + ".partial")
    partial_md.mkdir()
    with pytest.raises(InvalidInputError) as caught, replaced_together(older) as new:
        for partial in new:
            partial.write_text("newer")
    assert caught.value.message == f"cannot write {older[1]}: Is a directory"
    partial_md.rmdir()
    assert contents(older[0].parent) == {n: f"older {n}" for n in NAMES}
