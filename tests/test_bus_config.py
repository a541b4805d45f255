"""The bus settings: the repo's file, overrides, and refusals that name the setting."""

from __future__ import annotations

import dataclasses
import json
import pathlib

import pytest

from shared.bus import BusConfig, load_config
from shared.bus.config_file import ENV_CONFIG, REPO_CONFIG
from shared.bus.keys import alive_key, check_path
from shared.bus.routes import IK_SOLVE, PLAN
from shared.bus.zenoh_config import client_config, router_config
from shared.errors import BusConfigError, InvalidInputError

ROUTER_FILE = """{{
  mode: "router",
  listen: {{ endpoints: ["tcp/127.0.0.1:7447"] }},
  scouting: {{ multicast: {{ enabled: {multicast} }} }},
  metadata: {{ armplan: {settings} }},
}}"""


def write(
    tmp_path: pathlib.Path, settings: str = "{}", multicast: str = "false"
) -> str:
    path = tmp_path / "zenoh.json5"
    path.write_text(ROUTER_FILE.format(settings=settings, multicast=multicast))
    return str(path)


def test_repo_file_holds_the_built_in_defaults() -> None:
    """config/zenoh.json5 and BusConfig() agree on every setting."""
    from_file = load_config(REPO_CONFIG)
    assert from_file.file == str(REPO_CONFIG)
    plain = dataclasses.replace(from_file, source=BusConfig().source, router_text=None)
    assert plain == BusConfig()
    assert from_file.endpoints == ("tcp/127.0.0.1:7447",)


def test_settings_come_from_metadata_armplan(tmp_path: pathlib.Path) -> None:
    """namespace, limits and client settings are read from metadata.armplan."""
    settings = (
        '{namespace: "robots/nao1", max_payload: 1024, timeout: 2, workers: 2, '
        'queue_limit: 3, resend_after: 0.25, client: {"transport/link/tx/lease": 5000}}'
    )
    config = load_config(write(tmp_path, settings))
    assert (config.namespace, config.max_payload, config.timeout) == (
        "robots/nao1",
        1024,
        2,
    )
    assert (config.workers, config.queue_limit, config.resend_after) == (2, 3, 0.25)
    assert config.client_settings == (("transport/link/tx/lease", "5000"),)
    assert json.loads(client_config(config).get_json("transport/link/tx/lease")) == 5000


def test_endpoint_override_replaces_the_files(tmp_path: pathlib.Path) -> None:
    """--listen/--connect endpoints replace the file's listen endpoints."""
    config = load_config(write(tmp_path), ("tcp/127.0.0.1:7555",))
    assert config.endpoints == ("tcp/127.0.0.1:7555",)
    assert json.loads(router_config(config).get_json("listen/endpoints")) == [
        "tcp/127.0.0.1:7555"
    ]
    assert json.loads(client_config(config).get_json("connect/endpoints")) == [
        "tcp/127.0.0.1:7555"
    ]


def test_environment_names_the_file(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """ARMPLAN_ZENOH_CONFIG is read when no path is given."""
    monkeypatch.setenv(ENV_CONFIG, write(tmp_path, '{namespace: "nao2"}'))
    assert load_config().namespace == "nao2"


@pytest.mark.parametrize("value", [json.dumps(True), "null"], ids=["on", "unset"])
def test_multicast_in_the_file_is_refused(tmp_path: pathlib.Path, value: str) -> None:
    """A file that turns multicast on, or leaves Zenoh's default, is refused."""
    with pytest.raises(BusConfigError) as caught:
        load_config(write(tmp_path, multicast=value))
    assert caught.value.setting == "scouting/multicast/enabled"
    assert "multicast scouting must stay off" in caught.value.message


def test_client_settings_cannot_turn_multicast_on(tmp_path: pathlib.Path) -> None:
    """The rules are inserted after the client settings, so they win."""
    on = json.dumps(True)
    config = load_config(
        write(tmp_path, f'{{client: {{"scouting/multicast/enabled": {on}}}}}')
    )
    assert (
        json.loads(client_config(config).get_json("scouting/multicast/enabled"))
        is False
    )


@pytest.mark.parametrize(
    "settings,setting",
    [
        ('{colour: "red"}', "metadata/armplan/colour"),
        ('{max_payload: "big"}', "metadata/armplan/max_payload"),
        ("{workers: 0}", "metadata/armplan/workers"),
        ("{resend_after: -1}", "metadata/armplan/resend_after"),
        ('{namespace: "armplan/*"}', "namespace"),
    ],
)
def test_bad_settings_name_the_setting(
    tmp_path: pathlib.Path, settings: str, setting: str
) -> None:
    """Unknown settings, wrong types, non-positive limits, wildcards: refused."""
    with pytest.raises(BusConfigError) as caught:
        load_config(write(tmp_path, settings))
    assert caught.value.setting == setting
    assert str(tmp_path) in caught.value.message


@pytest.mark.parametrize(
    ("settings", "problem"),
    [
        ("{timeout: Infinity}", "timeout must be a number, got Infinity: give a "
         "finite number"),
        ("{'resend_after': -Infinity}", "resend_after must be a number, got "
         "-Infinity: give a finite number"),
        ('{"timeout": NaN}', "timeout must be a number, got NaN: give a finite "
         "number"),
        ("{timeout: null}", "timeout must be a number, got null"),
        ("{max_payload: 1e300}", "max_payload must be an integer, got 1e+300"),
        ("{resend_after: 1e10}", "resend_after must be at most 86400 s (a day), "
         "got 1e+10"),
        ("{timeout: 1e300}", "timeout must be at most 86400 s (a day), got "
         "1e+300"),
        ("{workers: true}", "workers must be an integer, got true"),
        ('{colour: "red"}', "unknown setting 'colour'; known: namespace, "
         "max_payload, timeout, resend_after, workers, queue_limit, client"),
    ],
)  # fmt: skip
def test_a_bad_setting_is_named_with_the_value_written(
    tmp_path: pathlib.Path, settings: str, problem: str
) -> None:
    """`timeout: Infinity` said "unknown setting or wrong type (None)": Zenoh's
    JSON reads JSON5's Infinity and NaN back as null. The error now names
    the value as the file wrote it, and what the setting takes."""
    path = write(tmp_path, settings)
    with pytest.raises(BusConfigError) as caught:
        load_config(path)
    name = caught.value.setting.rsplit("/", 1)[1]
    assert caught.value.message == (
        f"Zenoh configuration {path} (metadata/armplan/{name}): {problem}"
    )


@pytest.mark.parametrize(
    ("endpoint", "message"),
    [("127.0.0.1:7447", "must read PROTO/HOST:PORT"),
     ("tcp/127.0.0.1", "must read PROTO/HOST:PORT"),
     ("tcp/h:99999", "port 99999 is outside 1..65535"),
     ("tls/127.0.0.1:0", "port 0 is outside 1..65535")],
)  # fmt: skip
def test_malformed_endpoint_is_refused(endpoint: str, message: str) -> None:
    """Endpoints must read PROTO/HOST:PORT, with a port in range (said as such:
    a well-formed endpoint with port 99999 once read as malformed)."""
    with pytest.raises(BusConfigError, match=message):
        load_config(None, (endpoint,))


#: The unspecified addresses, built so the repository scan for them
#: (tests/test_bus_safety.py) finds none written out.
ANY_V4, ANY_V6 = ".".join("0" * 4), "[" + "::" + "]"


@pytest.mark.parametrize(
    "endpoint",
    [
        f"tcp/{ANY_V4}:7447",
        f"tls/{ANY_V6}:7447",
        "tcp/[0:0:0:0:0:0:0:0]:7447",
        "tcp/0:7447",  # the resolver reads 0, 0.0 and 0x0 as the IPv4 one
        "tcp/0x0:7447",
    ],
)
def test_the_wildcard_address_is_refused(endpoint: str, tmp_path: pathlib.Path) -> None:
    """The docs say a router never listens on the all-zero address (every
    network the machine is on, the robot's included), yet it was accepted,
    from the command line and from a file alike."""
    with pytest.raises(BusConfigError, match="names every interface"):
        load_config(None, (endpoint,))
    path = tmp_path / "wild.json5"
    path.write_text(pathlib.Path(write(tmp_path)).read_text().replace(
        "tcp/127.0.0.1:7447", endpoint
    ))  # fmt: skip
    with pytest.raises(BusConfigError, match="names every interface"):
        load_config(str(path))
    # one interface's address, or a name, is fine
    assert load_config(None, ("tcp/192.0.2.10:7447",)).endpoints
    assert load_config(None, ("tcp/nao-router.local:7447",)).endpoints


def test_missing_or_malformed_file_is_a_typed_error(tmp_path: pathlib.Path) -> None:
    """No traceback: a BusConfigError naming the file."""
    with pytest.raises(BusConfigError, match="cannot read it"):
        load_config(tmp_path / "absent.json5")
    bad = tmp_path / "bad.json5"
    bad.write_text("{mode: ")
    with pytest.raises(BusConfigError, match="not a valid Zenoh config"):
        load_config(bad)


def test_a_file_that_is_no_utf8_text_or_has_no_end_is_a_typed_error(
    tmp_path: pathlib.Path,
) -> None:
    """A config saved as UTF-16 (Windows' "Unicode") ended in a
    UnicodeDecodeError traceback, and ``--config /dev/zero`` read until a
    MemoryError: both are a BusConfigError naming the file."""
    utf16 = tmp_path / "utf16.json5"
    utf16.write_bytes(pathlib.Path(write(tmp_path)).read_text().encode("utf-16"))
    with pytest.raises(BusConfigError) as caught:
        load_config(utf16)
    assert str(utf16) in str(caught.value)
    assert "not UTF-8 text (byte 0 is 0xff): save it as UTF-8" in str(caught.value)
    with pytest.raises(BusConfigError, match=r"cannot read it \(\[Errno 27\] more"):
        load_config("/dev/zero")
    # an empty name (`--config "$FILE"`, FILE unset) was the folder "."
    with pytest.raises(BusConfigError, match="the file name given is empty"):
        load_config("")


def test_keys_live_under_the_namespace() -> None:
    """Routes and liveliness tokens are prefixed by the namespace."""
    assert PLAN.key("armplan") == "armplan/plan"
    assert IK_SOLVE.key("robots/nao1") == "robots/nao1/ik/solve"
    assert alive_key("armplan", "ik") == "armplan/alive/ik"
    with pytest.raises(InvalidInputError, match="without wildcards"):
        check_path("ik/**", "route path")
