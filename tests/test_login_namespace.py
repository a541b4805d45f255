"""A process with a login file refuses a --namespace other than the file's.

The secured router's access rules name one namespace, the one ``armplan
certs --namespace`` wrote into them and into every client file. A service
process, the bridge or a recorder started with its own login file and
another ``--namespace`` connected, said it was ready and then held no
token and served or recorded nothing: the router dropped every key without
a word. Now each exits 1 at start naming both namespaces. Real processes
with a real ``armplan certs`` bundle; no router is needed, as the refusal
comes before connecting (with the file's own namespace they go on to wait
for the router, which is not there).
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from armplan.launch import free_endpoint
from armplan.secure import Bundle, write_bundle

NS = "lab/nao1"
#: (user, the command after ``python -m``) of each process with a login.
PROCESSES = [
    ("ik", ["services.ik"]),
    ("planner", ["services.planner"]),
    ("bridge", ["bridge.serve"]),
    ("recorder", ["services.recorder", "--overwrite"]),
    ("recorder", ["armplan", "record", "--overwrite"]),
]


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Bundle:
    port = free_endpoint().rsplit(":", 1)[1]
    folder = tmp_path_factory.mktemp("secure")
    return write_bundle(folder, endpoint=f"tls/127.0.0.1:{port}", namespace=NS)


def run(bundle: Bundle, user: str, command: list[str], namespace: str) -> str:
    """Run the process with ``user``'s file and ``--namespace``; its stderr."""
    out = bundle.directory / f"{user}.mcap"
    argv = [*command, "--config", str(bundle.clients[user])]
    argv += ["--namespace", namespace]
    if user == "recorder":
        argv += ["-o", str(out)]
    if command[0] != "armplan":
        argv += ["--wait", "0.5"]
    done = subprocess.run(
        [sys.executable, "-m", *argv],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 1, done.stderr
    return done.stderr


@pytest.mark.parametrize(("user", "command"), PROCESSES)
def test_another_namespace_is_refused_at_start(
    bundle: Bundle, user: str, command: list[str]
) -> None:
    err = run(bundle, user, command, "lab2")
    assert f"logs in as user {user!r}" in err
    assert f"made for the namespace {NS!r}" in err
    assert "--namespace is 'lab2'" in err
    assert "armplan certs --namespace lab2" in err


@pytest.mark.parametrize(("user", "command"), PROCESSES[:1])
def test_the_files_own_namespace_goes_on(
    bundle: Bundle, user: str, command: list[str]
) -> None:
    err = run(bundle, user, command, NS)
    assert "--namespace is" not in err
    assert "router" in err  # it went on to wait for one
