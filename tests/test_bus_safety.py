"""No multicast scouting and no listening beyond loopback, in files and at runtime."""

from __future__ import annotations

import json
import pathlib
import re

import pytest

from shared.bus import BusConfig, load_config
from shared.bus.config_file import REPO_CONFIG
from shared.bus.zenoh_config import client_config, router_config

ROOT = pathlib.Path(__file__).parent.parent
SKIP = {".venv", ".git", "node_modules", "__pycache__", ".mypy_cache", ".ruff_cache"}
CONFIG_SUFFIXES = {".json5", ".json", ".yaml", ".yml", ".toml", ".env", ".conf"}
#: Multicast switched on, in any spelling (JSON5, JSON, insert_json5).
MULTICAST_ON = re.compile(
    r"multicast[\s\S]{0,80}?enabled[\s\S]{0,10}?" + "tr" + "ue", re.I
)
#: Listening on every interface: the IPv4 and IPv6 wildcard addresses.
WILDCARD = re.compile(r"\b0\.0\.0\." + r"0\b|\[" + r"::\]")
#: The bus layer's code, its services, launcher, commands and tests.
OURS = [
    "shared/bus",
    "armplan/launch",
    "armplan/cli/remote.py",
    "armplan/cli/commands/up.py",
    "armplan/cli/commands/status.py",
    "armplan/cli/commands/ik.py",
    "armplan/bench/service_latency.py",
    *(
        f"services/{s}/{f}"
        for s in ("fit", "decide", "ik", "timing", "planner")
        for f in ("service.py", "__main__.py")
    ),
]


def files(suffixes: set[str]) -> list[pathlib.Path]:
    return sorted(
        p
        for p in ROOT.rglob("*")
        if p.is_file()
        and not SKIP & set(p.relative_to(ROOT).parts)
        and (
            p.suffix in suffixes or p.name.startswith(("docker-compose", "Dockerfile"))
        )
    )


def our_code() -> list[pathlib.Path]:
    paths = [ROOT / p for p in OURS]
    paths = [q for p in paths for q in (sorted(p.rglob("*.py")) if p.is_dir() else [p])]
    return [*paths, *sorted((ROOT / "tests").glob("test_*.py"))]


def offences(paths: list[pathlib.Path]) -> list[str]:
    found = []
    for path in paths:
        text = path.read_text(errors="replace")
        for pattern in (MULTICAST_ON, WILDCARD):
            found += [
                f"{path.relative_to(ROOT)}: {m.group(0)!r}"
                for m in pattern.finditer(text)
            ]
    return found


def test_the_repo_config_files_are_loopback_only() -> None:
    """No config file in the repository enables multicast or a wildcard listen."""
    checked = files(CONFIG_SUFFIXES)
    assert REPO_CONFIG in checked
    assert offences(checked) == []


def test_our_code_and_the_tests_are_loopback_only() -> None:
    """The bus layer, its commands and every test: no multicast, no wildcard."""
    assert offences(our_code()) == []


@pytest.mark.parametrize(
    "config", [BusConfig(), load_config(REPO_CONFIG)], ids=["defaults", "repo-file"]
)
def test_generated_zenoh_configs_scout_nowhere_and_stay_on_loopback(
    config: BusConfig,
) -> None:
    """The router listens on 127.0.0.1 only; clients connect there; no scouting."""
    router, client = router_config(config), client_config(config)
    for zenoh_config in (router, client):
        assert json.loads(zenoh_config.get_json("scouting/multicast/enabled")) is False
        assert json.loads(zenoh_config.get_json("scouting/gossip/enabled")) is False
    assert json.loads(router.get_json("listen/endpoints")) == ["tcp/127.0.0.1:7447"]
    assert json.loads(client.get_json("connect/endpoints")) == ["tcp/127.0.0.1:7447"]
    assert json.loads(client.get_json("listen/endpoints")) == []


def test_the_patterns_catch_what_they_should() -> None:
    """The scan is not vacuous: it flags a multicast switch and wildcard listens."""
    on = "tr" + "ue"
    assert MULTICAST_ON.search("scouting: { multicast: { enabled: " + on + " } }")
    assert MULTICAST_ON.search(
        'insert_json5("scouting/multicast/enabled", "' + on + '")'
    )
    assert not MULTICAST_ON.search("multicast: { enabled: false }")
    assert WILDCARD.search("tcp/0.0.0." + "0:7447") and WILDCARD.search(
        "tcp/[" + "::]:7447"
    )
    assert not WILDCARD.search("tcp/127.0.0.1:7447")
