"""The files ``armplan faults`` writes into its folder, and an earlier run's there.

``--out DIR`` may name a folder that already holds a recording worth
keeping: an ``armplan demo`` folder's ``session.mcap`` recorded on a real
NAO, say. The suite writes files of the same names (its recorders replace
an existing file, its logs are appended to), so a folder holding any of
them is refused, naming them, unless the run is told to overwrite; then
they are removed first, so that no earlier run's recording or log is mixed
with this run's.
"""

from __future__ import annotations

import re
from pathlib import Path

from armplan.demo.stack import LOGS_DIR, RECORDING_FILE, SIM_LOG_FILE
from shared.errors import InvalidInputError

#: The suite's configuration file, in its folder.
CONFIG_FILE = "zenoh.json5"
#: The files the suite writes, relative to its folder: the configuration,
#: the recording, the sim's log, the processes' logs.
OUTPUTS = (
    CONFIG_FILE,
    RECORDING_FILE,
    SIM_LOG_FILE,
    *(f"{LOGS_DIR}/{name}.log" for name in ("services", "bridge", "recorder")),
)
#: A restarted recorder's file (``session-2.mcap``) and log (``recorder-2.log``).
NUMBERED = (
    re.compile(rf"{re.escape(Path(RECORDING_FILE).stem)}-[0-9]+\.mcap"),
    re.compile(rf"{LOGS_DIR}/recorder-[0-9]+\.log"),
)


def earlier_outputs(out: Path) -> list[Path]:
    """The files in ``out`` (a folder, or missing) of the names the suite writes."""
    found = [out / name for name in OUTPUTS if _present(out / name)]
    for folder in (out, out / LOGS_DIR):
        if folder.is_dir():
            found += sorted(
                entry
                for entry in folder.iterdir()
                if any(p.fullmatch(entry.relative_to(out).as_posix()) for p in NUMBERED)
            )
    return found


def claim_out_folder(out: Path, overwrite: bool, option: str = "--out") -> None:
    """Make sure the suite writes over nothing in ``out``; with ``overwrite``, clear it.

    Args:
        out: The suite's folder (it may not exist yet).
        overwrite: Remove an earlier run's files instead of refusing.
        option: The command-line option naming ``out``, for the message.

    Raises:
        InvalidInputError: ``out`` holds files of the names the suite writes
            (naming them) and ``overwrite`` is false, or one of them is a
            folder; nothing is removed then.
    """
    found = earlier_outputs(out)
    field = option.lstrip("-")
    folders = [path for path in found if path.is_dir() and not path.is_symlink()]
    if folders or (found and not overwrite):
        names = ", ".join(str(path.relative_to(out)) for path in found)
        advice = "move them away" if folders else "give --overwrite to replace them"
        raise InvalidInputError(
            f"cannot write into {out} ({option}): it holds {names}, which armplan "
            f"faults would replace or add to; {advice}, or give another {option}",
            field=field,
            paths=[str(path) for path in found],
        )
    for path in found:
        try:
            path.unlink()
        except OSError as error:
            raise InvalidInputError(
                f"cannot replace {path} ({option}): {error.strerror}",
                field=field,
                path=str(path),
            ) from None


def _present(path: Path) -> bool:
    """Whether anything (a broken link too) stands at ``path``."""
    return path.is_symlink() or path.exists()
