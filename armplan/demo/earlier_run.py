"""Replace only what an earlier demo wrote into the output folder.

``armplan demo --out .`` writes into a folder the user also keeps files in.
A run removes an earlier run's results first (a failed run must not leave
them behind), but only files an earlier demo wrote: each run lists the files
it writes in a hidden file, :data:`LIST_FILE`, before it writes any. A file
of one of those names that no earlier run listed (the user's own
``play.py``, say) stops the run before anything starts, naming the file;
other files (``logs/nao.log``) are never touched. A ``<name>.partial``
file beside a listed ``name`` (a run killed while it wrote its outputs) is
that run's too, and removed.

A folder without that list that holds at least :data:`OLD_RUN_FILES` of
the demo's files and nothing else is a demo's from before the list existed,
such as the default ``./armplan-demo``: its files are replaced as an
earlier run's. (Fewer, a file of the user's could pass for one.)
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

from shared.errors import InvalidInputError

#: The list of the files the demo writes, inside the output folder.
LIST_FILE = ".armplan-demo-files"
_HEADER = "# files armplan demo writes here, replaced by its next run\n"
#: Fewest of the demo's files, and nothing else, that make a folder without
#: the list an earlier demo's (a demo that got as far as the robot wrote
#: five or more).
OLD_RUN_FILES = 3
#: The demo's own hidden files (this run's claim on the folder, the list).
OWN_PREFIX = ".armplan-demo"


def replace_earlier_run(out: Path, names: Sequence[str], option: str = "--out") -> None:
    """Remove an earlier demo's files from ``out``, then list ``names`` as this run's.

    An earlier demo's files are the ``names`` its list holds and their
    ``<name>.partial`` files (left by a run killed while it wrote).

    Args:
        out: The output folder (it exists).
        names: The files this run writes, relative to ``out`` (``logs/bridge.log``).
        option: The command-line option naming ``out``, for the error.

    Raises:
        InvalidInputError: one of ``names`` is in ``out`` but no earlier demo
            listed it (or it is a folder), or a folder of theirs (``logs``)
            is a file: naming that path; nothing removed.
    """
    _check_folders(out, names, option)
    leftovers = _earlier_partials(out, names, option)
    present = [name for name in names if _present(out / name)]
    earlier, why = _listed(out), f"its {LIST_FILE} list does not say the demo wrote it"
    if present and not (out / LIST_FILE).exists():
        earlier, why = _unlisted(out, names)
    for name in present:
        path = out / name
        if name not in earlier or path.is_dir():
            held = (
                f"a folder {name}, where the demo writes a file"
                if path.is_dir()
                else f"{name}, which the demo would replace, and {why}"
            )
            raise InvalidInputError(
                f"{out} ({option}) holds {held}: move it or choose another {option}",
                field=option.lstrip("-"),
                path=str(path),
            )
    for name in present:
        (out / name).unlink()
    for partial in leftovers:
        partial.unlink()
    _write_list(out, names, option)


def _unlisted(out: Path, names: Sequence[str]) -> tuple[set[str], str]:
    """The names taken as an earlier run's in a folder without the list.

    Returns:
        Those names (all of the demo's, or none), and why a file of the
        demo's names is not taken for an earlier run's: the end of the
        error's sentence "OUT holds NAME, which the demo would replace, and
        ...".
    """
    unlisted = f"no {LIST_FILE} list says the demo wrote it"
    try:
        look = _look(out, names)
    except OSError as error:
        return set(), f"{unlisted} (the folder cannot be read: {error.strerror})"
    if look.other is None and look.files >= OLD_RUN_FILES:
        return set(names), ""  # written before the demo listed its files
    if look.other is not None:
        other = look.other.relative_to(out).as_posix()
        return set(), (
            f"{unlisted} (the folder also holds {other}, so it is not just an "
            "older demo's output)"
        )
    return set(), unlisted


def _listed(out: Path) -> set[str]:
    """The names an earlier run listed in ``out`` (none if no list)."""
    try:
        text = (out / LIST_FILE).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return set()
    return {line for line in text.splitlines() if line and not line.startswith("#")}


class _Look(NamedTuple):
    """What a folder without the list holds: the demo's files, and the first other."""

    files: int
    other: Path | None


def _look(out: Path, names: Sequence[str]) -> _Look:
    """Count the demo's files in ``out``, up to the first other file or folder.

    Only the demo's own folders (``logs``) are looked into, and the look
    ends at the first other file or folder: ``--out`` may name a large
    tree (``--out .`` in a home folder), which must not be walked.
    """
    folders = {name.split("/")[0] for name in names if "/" in name}
    count = 0
    pending = [out]
    while pending:
        for entry in pending.pop().iterdir():
            name = entry.relative_to(out).as_posix()
            if name.startswith(OWN_PREFIX):  # the run's claim
                continue
            if entry.is_dir() and not entry.is_symlink():
                if name not in folders:
                    return _Look(count, entry)
                pending.append(entry)
            elif name in names:
                count += 1
            else:
                return _Look(count, entry)
    return _Look(count, None)


def _earlier_partials(out: Path, names: Sequence[str], option: str) -> list[Path]:
    """The ``<name>.partial`` files an earlier run left; refuse any other.

    The outputs are written under those names first, then renamed
    (``replaced_together``): a user's file there would be overwritten and
    removed, a folder there found only once the robot had moved. A regular
    file ``<name>.partial`` where an earlier run's list names ``name`` is
    that run's, left by a kill (SIGKILL) while it wrote: the caller removes it.

    Raises:
        InvalidInputError: naming the first such path that is not an
            earlier run's.
    """
    listed = _listed(out)
    leftovers = []
    for name in names:
        partial = out / f"{name}.partial"
        if not _present(partial):
            continue
        if name in listed and partial.is_file() and not partial.is_symlink():
            leftovers.append(partial)
            continue
        raise InvalidInputError(
            f"cannot write into {out} ({option}): {partial} stands where the "
            f"demo writes {name} first; move it away or give another {option}",
            field=option.lstrip("-"),
            path=str(partial),
        )
    return leftovers


def _check_folders(out: Path, names: Sequence[str], option: str) -> None:
    """Refuse if a folder the demo writes into (``logs``) is something else.

    Raises:
        InvalidInputError: ``out/logs`` is a file (or a broken link), naming it.
    """
    for folder in dict.fromkeys(n.split("/")[0] for n in names if "/" in n):
        path = out / folder
        if _present(path) and not path.is_dir():
            raise InvalidInputError(
                f"cannot write into {out} ({option}): {path} is not a folder and "
                f"the demo writes its {folder} there; move it away or give "
                f"another {option}",
                field=option.lstrip("-"),
                path=str(path),
            )


def _present(path: Path) -> bool:
    """Whether anything (a broken link too) stands at ``path``."""
    return path.is_symlink() or path.exists()


def _write_list(out: Path, names: Sequence[str], option: str) -> None:
    """Write :data:`LIST_FILE`, before any of ``names`` is written."""
    path = out / LIST_FILE
    try:
        path.write_text(_HEADER + "".join(f"{n}\n" for n in names), encoding="utf-8")
    except OSError as error:
        raise InvalidInputError(
            f"cannot write into {out} ({option}): {path}: {error.strerror}",
            field=option.lstrip("-"),
        ) from None
