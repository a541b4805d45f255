"""The metadata records of an MCAP file (e.g. the recorder's ``armplan`` record).

The recorder writes one ``armplan`` metadata record at the start of every
file: the namespace and key expressions it recorded, the file's number in a
rotating recording, and when it started. A replay reads the namespace from
it to republish under another one.
"""

from __future__ import annotations

from pathlib import Path

from mcap.records import Metadata
from mcap.stream_reader import StreamReader

from shared.errors import RecordingError
from shared.recording.reader import Recording

#: Name of the recorder's metadata record.
ARMPLAN_METADATA = "armplan"


def read_metadata(path: str | Path) -> dict[str, dict[str, str]]:
    """Every metadata record of ``path`` by name, read up to any damage.

    Raises:
        RecordingError: if the file is missing, a folder, empty or unreadable.
    """
    Recording(path)  # the same checks and errors as for reading messages
    found: dict[str, dict[str, str]] = {}
    try:
        stream = open(path, "rb")  # noqa: SIM115 (closed below)
    except OSError as exc:
        raise RecordingError(
            f"cannot read {path}: {exc.strerror}", path=str(path)
        ) from None
    with stream:
        try:
            for record in StreamReader(stream, emit_chunks=False).records:
                if isinstance(record, Metadata):
                    found[record.name] = dict(record.metadata)
        except Exception:  # damage: what was read before it stands
            return found
    return found
