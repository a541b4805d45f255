"""``armplan ik --remote/--connect`` against a real IK service: same output."""

from __future__ import annotations

import pathlib
import subprocess
from collections.abc import Iterator

import pytest
from armplan_cli import armplan

from armplan.launch import Launcher, free_endpoint
from shared.bus import load_config

REPO = pathlib.Path(__file__).resolve().parents[1]

#: From a bent arm, S_R E_P W_R swivelling the elbow round the held wrist to
#: 4.4 rad: RElbowYaw meets its limit at 3.52 rad.
SWIVEL_SHORT = [
    *("--target", "0.14092095", "-0.13101531", "0.09501147"),
    *("--start", "0.3", "-0.3", "1.0", "0.9", "0.0"),
    *("--primitive", "S_R E_P W_R", "--swivel", "4.4"),
]
CASES = [
    ["--target", "0.12", "-0.13", "0.05"],
    ["--arm", "left", "--target", "0.12", "0.13", "0.05", "--method", "least-norm"],
    ["--target", "0.12", "-0.13", "0.05", "--primitive", "S_R E_PR W_P"],
    ["--target", "0.12", "-0.13", "0.05", "--palm", "0", "0", "-1"],
    ["--target", "0.5", "-0.12", "0.05"],  # unreachable: the same error
    ["--target", "0.12", "-0.13", "0.05", "--primitive", "X"],  # unknown primitive
    SWIVEL_SHORT,  # RElbowYaw meets its limit short of the swivel: the same error
]


@pytest.fixture(scope="module")
def endpoint() -> Iterator[str]:
    """A router and an IK service on a free port."""
    config = load_config(endpoints=(free_endpoint(),))
    with Launcher(config, ["ik"], log=subprocess.DEVNULL):
        yield config.endpoint


#: The cases also compared as tables: the JSON of every case already holds
#: the same data; the table adds its rendering of an answer, a palm and an error.
TABLE_CASES = [CASES[0], CASES[3], CASES[4]]
OUTPUTS = [(["--json"], case) for case in CASES] + [([], c) for c in TABLE_CASES]


@pytest.mark.parametrize(
    ("json_flag", "case"),
    OUTPUTS,
    ids=[f"{'json' if j else 'table'}-{' '.join(c)}" for j, c in OUTPUTS],
)
def test_remote_output_is_the_in_process_output(
    endpoint: str, case: list[str], json_flag: list[str]
) -> None:
    """Same stdout, stderr and exit code, byte for byte, with and without --remote."""
    local = armplan("ik", *case, *json_flag)
    remote = armplan("ik", *case, *json_flag, "--remote", "--connect", endpoint)
    assert (remote.returncode, remote.stdout, remote.stderr) == (
        local.returncode,
        local.stdout,
        local.stderr,
    )


def test_connect_alone_implies_remote(endpoint: str) -> None:
    """--connect without --remote still asks the service (same answer)."""
    out = armplan("ik", *CASES[0], "--json", "--connect", endpoint)
    assert (
        out.returncode == 0 and out.stdout == armplan("ik", *CASES[0], "--json").stdout
    )


def test_no_router_is_a_clear_error() -> None:
    """Nothing listening: exit 1 naming the router and its endpoint, no traceback."""
    missing = free_endpoint()
    out = armplan("ik", *CASES[0], "--json", "--connect", missing)
    assert out.returncode == 1 and "Traceback" not in out.stderr
    assert f"no Zenoh router answers at {missing}" in out.stderr
    assert '"kind": "service_unavailable"' in out.stdout


def test_no_ik_service_names_it() -> None:
    """A router without the IK service: the error names 'ik' and its key."""
    config = load_config(endpoints=(free_endpoint(),))
    with Launcher(config, [], log=subprocess.DEVNULL):
        out = armplan("ik", *CASES[0], "--connect", config.endpoint)
    assert out.returncode == 1
    assert "service 'ik' is unavailable for armplan/ik/solve" in out.stderr


def test_a_zenoh_config_alone_implies_remote(tmp_path: pathlib.Path) -> None:
    """--zenoh-config without --remote asks the services it configures (it was
    silently ignored and the posture solved in-process): with no router at the
    file's endpoint, the clear no-router error."""
    missing = free_endpoint()
    text = (REPO / "config" / "zenoh.json5").read_text()
    config = tmp_path / "elsewhere.json5"
    config.write_text(text.replace('"tcp/127.0.0.1:7447"', f'"{missing}"'))
    out = armplan("ik", *CASES[0], "--zenoh-config", str(config))
    assert out.returncode == 1 and "Traceback" not in out.stderr
    assert f"no Zenoh router answers at {missing}" in out.stderr


def test_a_swivel_the_primitive_ignores_is_refused() -> None:
    """--swivel is S_R E_P W_R's goal; with the default primitive or a baseline
    it was silently ignored. Refused, naming the primitive or method."""
    out = armplan("ik", *CASES[0], "--swivel", "1.0")
    assert out.returncode == 1
    assert "primitive 'S_R E_PR W_P' does not use it" in out.stderr
    # the service's words for the fields, told as the options that set them
    assert "error: --swivel is the goal of" in out.stderr
    assert "(give --primitive 'S_R E_P W_R')" in out.stderr
    out = armplan("ik", *CASES[0], "--swivel", "1.0", "--method", "single")
    assert out.returncode == 1 and "method 'single' does not use it" in out.stderr


def test_a_swivel_a_joint_limit_stops_short_is_an_error() -> None:
    """From a bent arm (the wrist the target), 3.5 rad is reached and said
    beside the goal; at 4.4 rad RElbowYaw meets its limit at 3.5197 rad, once
    printed as a success: exit 1 naming the swivel reached and the joint."""
    reached = armplan("ik", *SWIVEL_SHORT[:-1], "3.5")
    assert reached.returncode == 0, reached.stderr
    assert "elbow swivel 3.5000 rad reached (asked 3.5000 rad)" in reached.stdout
    out = armplan("ik", *SWIVEL_SHORT, "--json")
    assert out.returncode == 1 and "Traceback" not in out.stderr
    assert (
        "elbow swivel 4.4000 rad not reached: the elbow stopped at 3.5197 rad"
        in out.stderr
    )
    assert "RElbowYaw is on its limit 2.08567 rad" in out.stderr
    assert '"kind": "swivel_not_reached"' in out.stdout


def test_an_empty_zenoh_config_is_refused_not_run_in_process() -> None:
    """``--zenoh-config "$FILE"`` with FILE unset implies --remote as any
    file does: it solved in-process and exited 0, with no word."""
    done = armplan("ik", "--target", "0.12", "-0.13", "0.05", "--zenoh-config", "")
    assert done.returncode == 1
    assert done.stdout == ""
    assert done.stderr == (
        "armplan: error: Zenoh configuration '': the file name given is empty: "
        "name a JSON5 file, or leave the option out for the default\n"
    )
