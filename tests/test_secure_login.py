"""Each process refuses to start with another user's login file.

On the secured router a process with another user's file connected, said it
was ready, and was cut off by the access rules without a word: a bridge with
the client's file played every trajectory while nobody received its frames,
an ik with timing's file was absent from `armplan status`. Now every process
checks the user of its file before it connects (no router is needed to see
the refusal); a file without a login, the unsecured set's, passes.
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import pytest

from armplan.cli.main import main
from armplan.secure import Bundle, write_bundle
from shared.bus import BusConfig, load_config
from shared.bus.config_file import REPO_CONFIG
from shared.bus.login import check_login, login_user
from shared.errors import WrongLoginError

ROOT = pathlib.Path(__file__).resolve().parent.parent
#: A loopback port nothing listens on: the processes must fail before it matters.
ENDPOINT = "tls/127.0.0.1:9"


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Bundle:
    return write_bundle(tmp_path_factory.mktemp("secure"), endpoint=ENDPOINT)


def run_process(module: str, *args: str) -> subprocess.CompletedProcess[str]:
    """``python -m MODULE ARGS`` with the repository importable; its output."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-m", module, *args, "--wait", "0"],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


@pytest.mark.parametrize(
    ("module", "user", "other", "extra"),
    [
        ("bridge.serve", "bridge", "client", ["--follow"]),
        ("bridge.serve", "bridge", "recorder", []),
        ("services.ik", "ik", "timing", []),
        ("services.recorder", "recorder", "client", ["--output", "{tmp}/r.mcap"]),
    ],
    ids=["bridge-as-client", "bridge-as-recorder", "ik-as-timing", "recorder"],
)
def test_a_process_refuses_another_users_file(
    bundle: Bundle,
    tmp_path: pathlib.Path,
    module: str,
    user: str,
    other: str,
    extra: list[str],
) -> None:
    """Exit 1 at once, the error naming the file, the expected and given user."""
    argv = [a.format(tmp=tmp_path) for a in extra]
    done = run_process(module, "--config", str(bundle.clients[other]), *argv)
    assert done.returncode == 1, done.stderr
    assert (
        f"Zenoh configuration {bundle.clients[other]} (transport/auth/usrpwd/user): "
        f"logs in as user {other!r}, but this is the {user} process, which must "
        f"log in as {user!r}: give it {user}'s own file ({user}.json5"
    ) in done.stderr
    assert "ready" not in done.stderr
    assert not (tmp_path / "r.mcap").exists()


def test_a_process_with_its_own_file_passes_the_check(bundle: Bundle) -> None:
    """ik with ik's file goes on to connect (and finds no router on port 9)."""
    done = run_process("services.ik", "--config", str(bundle.clients["ik"]))
    assert done.returncode == 1
    assert "no Zenoh router answers at tls/127.0.0.1:9" in done.stderr
    assert "logs in as" not in done.stderr


def test_armplan_record_refuses_another_users_file(
    bundle: Bundle, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`armplan record` records as the recorder: the client's file is refused."""
    out = tmp_path / "r.mcap"
    argv = ["record", "--config", str(bundle.clients["client"]), "-o", str(out)]
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert "logs in as user 'client', but this is the recorder process" in err
    assert not out.exists()


def test_every_user_passes_with_its_own_file_only(bundle: Bundle) -> None:
    """check_login: each client file is its own user's, and no other's."""
    for user, path in bundle.clients.items():
        config = load_config(path)
        assert login_user(config) == user
        check_login(config, user)
        others = [u for u in bundle.clients if u != user]
        with pytest.raises(WrongLoginError) as raised:
            check_login(config, others[0])
        assert raised.value.evidence["expected"] == others[0]
        assert raised.value.evidence["given"] == user


def test_a_file_without_a_login_passes() -> None:
    """The unsecured set (the repository's file, built-in defaults): no user."""
    for config in (load_config(REPO_CONFIG), BusConfig()):
        assert login_user(config) is None
        check_login(config, "bridge")
