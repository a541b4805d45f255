"""The fit service reads demonstration files inside its directory only."""

from __future__ import annotations

import pathlib

import pytest

from services.fit.demo_dir import DEMOS_DIR_ENV, demo_file, demos_dir
from shared.errors import InvalidInputError


def test_a_name_inside_the_directory_is_resolved_there(tmp_path: pathlib.Path) -> None:
    """Relative names, subdirectories included, land inside the root."""
    root = tmp_path.resolve()
    assert demo_file("a.mcap", root) == root / "a.mcap"
    assert demo_file("sub/../b.mcap", root) == root / "b.mcap"


@pytest.mark.parametrize(
    "name", ["../a.mcap", "/etc/a.mcap", "sub/../../a.mcap", "link/a.mcap"]
)
def test_a_name_leading_outside_is_refused(tmp_path: pathlib.Path, name: str) -> None:
    """Parent steps, absolute paths and links out of the root are refused."""
    root = (tmp_path / "root").resolve()
    root.mkdir()
    (root / "link").symlink_to(tmp_path)
    with pytest.raises(InvalidInputError, match="outside the fit service's") as caught:
        demo_file(name, root)
    assert caught.value.evidence["field"] == "files"


def test_only_mcap_files_are_read(tmp_path: pathlib.Path) -> None:
    """Any other file name is refused before it is resolved."""
    with pytest.raises(InvalidInputError, match=r"must be an \.mcap file"):
        demo_file("model.json", tmp_path)


def test_a_name_with_a_nul_character_is_refused(tmp_path: pathlib.Path) -> None:
    """A request naming "\\u0000.mcap" made the fit service answer
    internal_error (ValueError: embedded null byte); now invalid_input."""
    with pytest.raises(InvalidInputError, match="NUL character") as caught:
        demo_file("a\0.mcap", tmp_path)
    assert caught.value.evidence["field"] == "files"


def test_the_directory_comes_from_the_environment(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """$ARMPLAN_DEMOS_DIR if set, else the working directory."""
    monkeypatch.setenv(DEMOS_DIR_ENV, str(tmp_path))
    assert demos_dir() == tmp_path.resolve()
    monkeypatch.delenv(DEMOS_DIR_ENV)
    monkeypatch.chdir(tmp_path)
    assert demos_dir() == tmp_path.resolve()
