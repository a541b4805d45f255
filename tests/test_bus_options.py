"""The router and namespace options read the same in every command."""

from __future__ import annotations

import pytest

from armplan.cli.main import build_parser
from shared.bus.options import bus_config
from shared.errors import BusConfigError

#: Commands that join a running system, and whether they take --namespace.
JOINING = {"stop": True, "status": False, "record": True, "replay": True}


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
def test_namespace_is_taken_only_where_it_is_offered(command: str) -> None:
    extra = ["x.mcap"] if command == "replay" else []
    parser = build_parser()
    if not JOINING[command]:
        with pytest.raises(SystemExit):
            parser.parse_args([command, "--namespace", "lab1", *extra])
        return
    config = bus_config(parser.parse_args([command, "--namespace", "lab1", *extra]))
    assert config.namespace == "lab1"
    assert config.source.endswith("+ --namespace")


def test_without_namespace_the_configs_is_kept() -> None:
    config = bus_config(build_parser().parse_args(["stop"]))
    assert config.namespace == "armplan"
    assert "--namespace" not in config.source


@pytest.mark.parametrize("namespace", ["lab/*", "", "a//b", "lab?"])
def test_a_malformed_namespace_is_a_config_error_naming_it(namespace: str) -> None:
    args = build_parser().parse_args(["stop", "--namespace", namespace])
    with pytest.raises(BusConfigError) as raised:
        bus_config(args)
    assert raised.value.setting == "namespace"
    assert "--namespace" in raised.value.source
