"""Read the one JSON5 configuration file every armplan process shares.

Which file: the path given (``--config``), else ``$ARMPLAN_ZENOH_CONFIG``,
else the repository's ``config/zenoh.json5`` if present, else the built-in
defaults of :class:`~shared.bus.config.BusConfig` (the same values). Zenoh
itself parses the JSON5, so the file is exactly what a Zenoh router accepts.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

import zenoh

from shared.bus.config import BusConfig
from shared.errors import BusConfigError
from shared.input_files import read_at_most

#: Environment variable naming the configuration file.
ENV_CONFIG = "ARMPLAN_ZENOH_CONFIG"
#: The repository's configuration file (absent in an installed wheel).
REPO_CONFIG = Path(__file__).resolve().parents[2] / "config" / "zenoh.json5"
_SETTINGS: dict[str, type | tuple[type, ...]] = {
    "namespace": str,
    "max_payload": int,
    "timeout": (int, float),
    "resend_after": (int, float),
    "workers": int,
    "queue_limit": int,
    "client": dict,
}
#: How an error names each type of setting (a tuple of types: a number).
_KINDS: dict[type | tuple[type, ...], str] = {
    str: "a string",
    int: "an integer",
    dict: "an object",
}


def config_path(path: str | Path | None = None) -> Path | None:
    """The configuration file to read, or ``None`` for the built-in defaults.

    Raises:
        BusConfigError: ``path`` is an empty name (``--config "$FILE"``, FILE
            unset), which ``Path`` reads as ``.``, the folder.
    """
    if path is not None:
        if not str(path).strip():
            raise BusConfigError(
                "the file name given is empty: name a JSON5 file, or leave the "
                "option out for the default",
                source="''",
            )
        return Path(path)
    if os.environ.get(ENV_CONFIG):
        return Path(os.environ[ENV_CONFIG])
    return REPO_CONFIG if REPO_CONFIG.is_file() else None


def load_config(
    path: str | Path | None = None, endpoints: tuple[str, ...] = ()
) -> BusConfig:
    """The bus settings from the file (see the module docstring).

    Args:
        path: A JSON5 file, or ``None`` to look it up.
        endpoints: Router endpoints replacing the file's ``listen`` ones
            (``--listen`` / ``--connect``); empty keeps the file's.

    Raises:
        BusConfigError: if the file is missing, malformed, enables multicast
            scouting, or holds a setting of the wrong type.
    """
    found = config_path(path)
    config = BusConfig() if found is None else _read(found)
    if endpoints:
        config = config.with_endpoints(endpoints, "--listen/--connect")
    return config


def _read(path: Path) -> BusConfig:
    source = str(path)
    text = _text(path, source)
    try:
        parsed = zenoh.Config.from_json5(text)
    except zenoh.ZError as error:
        problem = " ".join(str(error).split())
        raise BusConfigError(
            f"not a valid Zenoh config: {problem}", source=source
        ) from None
    _check_no_multicast(parsed, source)
    settings = _armplan_settings(parsed, source, text)
    client = settings.pop("client", {})
    return BusConfig(
        endpoints=_listen_endpoints(parsed, source),
        client_settings=tuple((k, json.dumps(v)) for k, v in client.items()),
        source=source,
        router_text=text,
        **settings,
    )


def _text(path: Path, source: str) -> str:
    """The file's text: UTF-8, at most ``MAX_INPUT_BYTES`` (16 MiB) of it.

    ``--config /dev/zero`` took memory until a ``MemoryError`` traceback, and
    a file saved as UTF-16 ended in a ``UnicodeDecodeError`` one.
    """
    try:
        data = read_at_most(path)
    except OSError as error:
        raise BusConfigError(f"cannot read it ({error})", source=source) from None
    try:
        return data.decode()
    except UnicodeDecodeError as error:
        raise BusConfigError(
            f"not a valid Zenoh config: not UTF-8 text (byte {error.start} is "
            f"{data[error.start]:#04x}): save it as UTF-8 JSON5",
            source=source,
        ) from None


def _get(config: zenoh.Config, key: str) -> Any:
    """The value at ``key`` as Python data, ``None`` if unset."""
    try:
        return json.loads(config.get_json(key))
    except zenoh.ZError:
        return None


def _check_no_multicast(config: zenoh.Config, source: str) -> None:
    """Refuse a file that does not switch multicast scouting off itself.

    A Zenoh router reading the file directly (``zenohd -c``) would scout by
    multicast if the setting were left out.
    """
    if _get(config, "scouting/multicast/enabled") is not False:
        raise BusConfigError(
            "multicast scouting must stay off (set it to false): armplan's "
            "endpoints are explicit",
            source=source,
            setting="scouting/multicast/enabled",
        )


def _listen_endpoints(config: zenoh.Config, source: str) -> tuple[str, ...]:
    endpoints = _get(config, "listen/endpoints")
    if not isinstance(endpoints, list) or not endpoints:
        raise BusConfigError(
            'must list the router\'s endpoints, e.g. ["tcp/127.0.0.1:7447"]',
            source=source,
            setting="listen/endpoints",
        )
    return tuple(str(e) for e in endpoints)


def _armplan_settings(
    config: zenoh.Config, source: str, text: str = ""
) -> dict[str, Any]:
    """The ``metadata.armplan`` settings, each known and of its type.

    Args:
        config: The parsed file.
        source: The file, for the errors.
        text: The file's text, to name a value as written (JSON5's
            ``Infinity`` and ``NaN`` are read back as ``null``).

    Raises:
        BusConfigError: naming the setting and the value given.
    """
    metadata = _get(config, "metadata") or {}
    settings = metadata.get("armplan", {}) if isinstance(metadata, dict) else {}
    if not isinstance(settings, dict):
        raise BusConfigError(
            "must be an object", source=source, setting="metadata/armplan"
        )
    for name, value in settings.items():
        problem = _setting_problem(name, value, text)
        if problem:
            raise BusConfigError(
                problem, source=source, setting=f"metadata/armplan/{name}"
            )
    return dict(settings)


def _setting_problem(name: str, value: Any, text: str) -> str:
    """What is wrong with setting ``name`` = ``value``, or ``""``."""
    wanted = _SETTINGS.get(name)
    if wanted is None:
        return f"unknown setting {name!r}; known: {', '.join(_SETTINGS)}"
    if isinstance(value, wanted) and not isinstance(value, bool):
        return ""
    kind = _KINDS.get(wanted, "a number")
    if value is None:  # null, or a non-finite number JSON cannot carry
        written = _written_null(text, name)
        finite = "" if written == "null" else ": give a finite number"
        return f"{name} must be {kind}, got {written}{finite}"
    return f"{name} must be {kind}, got {json.dumps(value)}"


def _written_null(text: str, name: str) -> str:
    """How the file wrote the value of ``name`` that reads back as null.

    ``Infinity``, ``-Infinity`` or ``NaN`` (which Zenoh's JSON turns into
    null), else ``null``.
    """
    key = rf"(?<![\w$])[\"']?{re.escape(name)}[\"']?\s*:\s*"
    found = re.search(key + r"([+-]?(?:Infinity|NaN))(?![\w$])", text)
    return found.group(1) if found else "null"
