"""Replace only what an earlier demo wrote into the output folder.

``armplan demo --out .`` writes into a folder the user also keeps files in.
A run removes an earlier run's results first (a failed run must not leave
them behind), but only files an earlier demo wrote: each run lists the files
it writes in a hidden file, :data:`LIST_FILE`, before it writes any. A file
of one of those names that no earlier run listed (the user's own
``play.py``, say) stops the run before anything starts, naming the file;
other files (``logs/nao.log``) are never touched.

A folder without that list that holds at least :data:`OLD_RUN_FILES` of
the demo's files and nothing else is a demo's from before the list existed,
such as the default ``./armplan-demo``: its files are replaced as an
earlier run's. (Fewer, a file of the user's could pass for one.)
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

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
    """Remove an earlier demo's ``names`` from ``out``, then list them as this run's.

    Args:
        out: The output folder (it exists).
        names: The files this run writes, relative to ``out`` (``logs/bridge.log``).
        option: The command-line option naming ``out``, for the error.

    Raises:
        InvalidInputError: one of ``names`` is in ``out`` but no earlier demo
            listed it (or it is a folder): naming that file; nothing removed.
    """
    earlier = _listed(out)
    if not (out / LIST_FILE).exists() and _only_demo_files(out, names):
        earlier = set(names)  # written before the demo listed its files
    present = [name for name in names if _present(out / name)]
    for name in present:
        path = out / name
        if name not in earlier or path.is_dir():
            raise InvalidInputError(
                f"cannot write into {out} ({option}): {path} is not from an "
                "earlier armplan demo and the demo would replace it; move it "
                f"away or give another {option}",
                field=option.lstrip("-"),
                path=str(path),
            )
    for name in present:
        (out / name).unlink()
    _write_list(out, names, option)


def _listed(out: Path) -> set[str]:
    """The names an earlier run listed in ``out`` (none if no list)."""
    try:
        text = (out / LIST_FILE).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return set()
    return {line for line in text.splitlines() if line and not line.startswith("#")}


def _only_demo_files(out: Path, names: Sequence[str]) -> bool:
    """Whether ``out`` holds ``OLD_RUN_FILES`` or more of ``names``, nothing else."""
    try:
        found = [p for p in out.rglob("*") if not p.is_dir() or p.is_symlink()]
    except OSError:
        return False
    files = [p.relative_to(out).as_posix() for p in found]
    files = [f for f in files if not f.startswith(OWN_PREFIX)]  # the run's claim
    return all(f in names for f in files) and len(files) >= OLD_RUN_FILES


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
