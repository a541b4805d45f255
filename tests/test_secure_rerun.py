"""A failed or interrupted `armplan certs` rerun leaves the bundle as it was.

Renewal is a rerun into the same folder. openssl wrote the new router.key
and router.pem straight over the old ones: when signing failed (a ca.key
that does not match ca.pem), router.key was new and router.pem empty, and
the router no longer started. Now every file is written under a temporary
name, owner-only from its creation, and renamed over the old one only when
all are written; the scratch files of openssl never land in the folder.
"""

from __future__ import annotations

import os
import pathlib
import shutil
import stat
import subprocess
import sys

import pytest

from armplan.cli.main import main
from armplan.secure.certificates import openssl

ROOT = pathlib.Path(__file__).resolve().parent.parent


def snapshot(folder: pathlib.Path) -> dict[str, tuple[bytes, int]]:
    """Every file of ``folder``: its bytes and its mode."""
    return {
        p.name: (p.read_bytes(), stat.S_IMODE(p.stat().st_mode))
        for p in sorted(folder.iterdir())
    }


@pytest.fixture
def bundle(tmp_path: pathlib.Path) -> pathlib.Path:
    """A working bundle in tmp/secure."""
    folder = tmp_path / "secure"
    assert main(["certs", "--out", str(folder), "--host", "nao-router"]) == 0
    return folder


def test_a_rerun_with_a_ca_key_of_another_ca_changes_nothing(
    bundle: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """openssl refuses to sign; the old certificate, key and files stay whole."""
    key = bundle / "ca.key"
    key.unlink()
    openssl(["ecparam", "-name", "prime256v1", "-genkey", "-noout", "-out", str(key)])
    key.chmod(0o600)
    before = snapshot(bundle)
    capsys.readouterr()
    assert main(["certs", "--out", str(bundle), "--host", "nao-router"]) == 1
    err = capsys.readouterr().err
    assert "CA certificate and CA private key do not match" in err
    assert err.endswith(f"; nothing in {bundle} was changed\n")
    assert snapshot(bundle) == before


def test_a_rerun_stopped_by_ctrl_c_while_signing_changes_nothing(
    bundle: pathlib.Path, tmp_path: pathlib.Path
) -> None:
    """Ctrl-C lands while openssl signs: exit 130, the old bundle whole.

    A stand-in ``openssl`` on PATH runs the real one, except for the signing
    step: there it notes the modes of the files being written, sends SIGINT
    to `armplan certs` and waits to be killed.
    """
    real = shutil.which("openssl")
    assert real is not None
    tools = tmp_path / "bin"
    tools.mkdir()
    modes = tmp_path / "modes.txt"
    fake = tools / "openssl"
    fake.write_text(
        "#!/bin/sh\n"
        'if [ "$1" = x509 ] && [ "$2" = -req ]; then\n'
        f'  stat -c "%n %a" {bundle}/*.partial > {modes}\n'
        "  kill -INT $PPID\n"
        "  exec sleep 60\n"
        "fi\n"
        f'exec {real} "$@"\n'
    )
    fake.chmod(0o755)
    (bundle / "router.key.partial").write_text("left by a killed run\n")
    (bundle / "router.key.partial").chmod(0o644)
    before = snapshot(bundle)
    del before["router.key.partial"]
    argv = ["certs", "--out", str(bundle), "--host", "nao-router"]
    done = subprocess.run(
        [sys.executable, "-m", "armplan", *argv],
        cwd=ROOT,
        env={**os.environ, "PATH": f"{tools}{os.pathsep}{os.environ['PATH']}"},
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert (done.returncode, done.stderr) == (130, "armplan: interrupted\n")
    assert modes.read_text() == f"{bundle / 'router.key.partial'} 600\n"
    assert snapshot(bundle) == before


def test_a_rerun_replaces_every_file_owner_only(bundle: pathlib.Path) -> None:
    """A successful rerun: a new router certificate and key, the authority and
    the passwords kept, secrets 0600 even if they were open before."""
    before = snapshot(bundle)
    (bundle / "passwords.txt").chmod(0o644)
    (bundle / "ik.json5").chmod(0o644)
    assert main(["certs", "--out", str(bundle), "--host", "nao-router"]) == 0
    after = snapshot(bundle)
    assert sorted(after) == sorted(before)
    for name in ("ca.pem", "ca.key", "passwords.txt", "ik.json5", "router.json5"):
        assert after[name] == before[name], name
    assert after["router.pem"][0] != before["router.pem"][0]
    assert after["router.key"][0] != before["router.key"][0]
    secrets = [n for n in after if n.endswith((".key", ".json5", ".txt"))]
    assert {n: after[n][1] for n in secrets} == dict.fromkeys(secrets, 0o600)
