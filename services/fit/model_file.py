"""Reading and writing motion-model files, with clear errors.

Reading checks, in order: the file exists and is readable, it is complete
JSON (a truncated file is named as such), it is a JSON object with a
``version`` equal to ``MODEL_VERSION``, and only then validates the whole
model (``MotionModel``), naming the first field that is wrong.
"""

from __future__ import annotations

import json
from pathlib import Path

from services.fit.model import MODEL_VERSION, MotionModel
from shared.errors import InvalidInputError, ModelFileError
from shared.input_files import read_at_most
from shared.messages.base import parse
from shared.output_paths import write_whole

#: Largest motion-model file read [bytes] (the shipped one: about 270 kB).
MAX_MODEL_BYTES = 128 * 1024 * 1024


def save_model(model: MotionModel, path: str | Path) -> None:
    """Write ``model`` as JSON to ``path`` (atomically: a reader never sees half).

    A symbolic link's target is the file replaced, and a path that is no
    regular file (``/dev/null``, a FIFO) is written into, not replaced
    (``shared.output_paths.write_whole``).

    Raises:
        ModelFileError: if ``path`` is no file name or cannot be written; no
            partial file is left behind.
    """
    given, path = str(path), Path(path)
    if not given or not path.name or path.name == "..":
        raise ModelFileError(repr(given), "not a file name for the motion model")
    try:
        write_whole(path, model.model_dump_json(indent=None) + "\n")
    except OSError as exc:
        raise ModelFileError(str(path), f"cannot write it: {exc.strerror}") from None


def load_model(path: str | Path) -> MotionModel:
    """The motion model in ``path``.

    Raises:
        ModelFileError: naming the file and the problem (missing, truncated,
            not JSON, binary, of another version, malformed).
    """
    path = Path(path)
    try:
        text = read_at_most(path, MAX_MODEL_BYTES).decode()
    except FileNotFoundError:
        raise ModelFileError(str(path), "no such motion-model file") from None
    except UnicodeDecodeError:  # an MCAP of demonstrations, say
        raise ModelFileError(
            str(path),
            "not a motion model: a binary file, not the JSON armplan fit writes",
        ) from None
    except OSError as exc:
        raise ModelFileError(str(path), f"cannot read it ({exc})") from None
    if not text.strip():
        raise ModelFileError(str(path), "the motion-model file is empty")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        cut = exc.pos >= len(text.rstrip()) - 1
        what = "truncated" if cut else "not valid JSON"
        raise ModelFileError(
            str(path), f"the motion-model file is {what} ({exc.msg} at {exc.pos})"
        ) from None
    if not isinstance(data, dict):
        raise ModelFileError(str(path), "not a motion model (expected a JSON object)")
    _check_version(data.get("version"), path)
    try:
        return parse(MotionModel, data)
    except InvalidInputError as exc:
        raise ModelFileError(
            str(path), f"malformed motion model: {exc.message}", field=exc.field
        ) from None


def _check_version(version: object, path: Path) -> None:
    if version is None:
        raise ModelFileError(
            str(path), "has no 'version' field: not an armplan motion model"
        )
    if version != MODEL_VERSION:
        raise ModelFileError(
            str(path),
            f"motion-model file version {version!r}; this armplan reads version "
            f"{MODEL_VERSION}: refit it with 'armplan fit'",
            found=version if isinstance(version, (int, float, str)) else None,
            expected=MODEL_VERSION,
        )
