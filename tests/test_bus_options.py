"""The router and namespace options read the same in every command."""

from __future__ import annotations

import logging
import os
import pwd
import subprocess
import sys
from pathlib import Path

import pytest

from armplan.cli.main import build_parser
from armplan.launch import free_endpoint
from shared.bus.named_files import check_named_files
from shared.bus.options import bus_config
from shared.bus.zenoh_config import client_config
from shared.errors import BusConfigError

#: Commands that join a running system (each takes --namespace).
JOINING = ("stop", "status", "record", "replay")


@pytest.mark.parametrize("command", sorted(JOINING))
def test_connect_endpoints_reach_the_config_in_order(command: str) -> None:
    extra = ["x.mcap"] if command == "replay" else []
    args = build_parser().parse_args(
        [
            command,
            *("--connect", "tcp/127.0.0.1:7501"),
            *("--connect", "tcp/127.0.0.1:7502"),
            *extra,
        ]
    )
    config = bus_config(args)
    assert config.endpoints == ("tcp/127.0.0.1:7501", "tcp/127.0.0.1:7502")
    assert config.endpoints_from


@pytest.mark.parametrize("command", sorted(JOINING))
def test_namespace_is_taken_by_every_joining_command(command: str) -> None:
    extra = ["x.mcap"] if command == "replay" else []
    parser = build_parser()
    config = bus_config(parser.parse_args([command, "--namespace", "lab1", *extra]))
    assert config.namespace == "lab1"
    assert config.namespace_from == "--namespace"


def test_without_namespace_the_configs_is_kept() -> None:
    config = bus_config(build_parser().parse_args(["stop"]))
    assert config.namespace == "armplan"
    assert "--namespace" not in config.source
    assert config.namespace_from == ""


@pytest.mark.parametrize("namespace", ["lab/*", "", "a//b", "lab?"])
def test_a_malformed_namespace_is_a_config_error_naming_it(namespace: str) -> None:
    args = build_parser().parse_args(["stop", "--namespace", namespace])
    with pytest.raises(BusConfigError) as raised:
        bus_config(args)
    assert raised.value.setting == "namespace"
    assert "--namespace" in raised.value.source


def _config_with_password(folder: Path) -> Path:
    """The repo's config with a client password, copied at mode 0644."""
    text = (Path(__file__).parents[1] / "config" / "zenoh.json5").read_text()
    login = '"transport/auth/usrpwd/user": "u", "transport/auth/usrpwd/password": "p"'
    path = folder / "client.json5"
    path.write_text(text.replace("client: {}", "client: {" + login + "}"))
    path.chmod(0o644)
    return path


@pytest.mark.parametrize("command", ["stop", "record", "replay"])
def test_namespace_keeps_the_config_file_known(
    command: str, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """With --namespace the settings still name their file: a config file
    holding a password that others may read is warned of, and a recorder
    started on these settings gets the file (`source` became "FILE +
    --namespace", no file: the warning was skipped)."""
    path = _config_with_password(tmp_path)
    extra = ["x.mcap"] if command == "replay" else []
    args = [command, "--config", str(path), "--namespace", "lab1", *extra]
    config = bus_config(build_parser().parse_args(args))
    assert (config.namespace, config.file) == ("lab1", str(path))
    caplog.set_level(logging.WARNING, logger="armplan.bus")
    check_named_files(client_config(config), config)
    assert [r.getMessage() for r in caplog.records] == [
        f"{path} holds a password and is open to other users (mode 0644, "
        f"owner {pwd.getpwuid(os.geteuid()).pw_name}): make it readable by its "
        f"owner only: chmod 600 {path}"
    ]


@pytest.mark.parametrize("module", ["services.ik", "bridge.serve", "services.recorder"])
@pytest.mark.parametrize("wait", ["nan", "-1", "inf"])
def test_a_wait_for_the_router_that_is_no_wait_is_refused(
    module: str, wait: str
) -> None:
    """``--wait nan`` waited for ever with no router there, saying nothing
    (no deadline is passed by NaN); ``-1`` tried once, as 0 does. Exit 2
    naming the option, as for any malformed option. (The 60 s cap only
    ends the old endless wait: the refusal takes no wait at all.)"""
    argv = [sys.executable, "-m", module, "--connect", free_endpoint()]
    done = subprocess.run(
        [*argv, "--wait", wait], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 2
    assert (
        f"argument --wait: '{wait}' is not a number of seconds from 0 to 86400"
        in done.stderr
    )
