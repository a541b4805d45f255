"""`armplan certs` keeps the certificate authority every machine trusts.

Machine B's folder holds A's ca.pem and passwords.txt but not ca.key (the
docs keep the key where bundles are made). Rerunning `armplan certs` there
replaced ca.pem with a new authority, and B no longer trusted A's router;
the only hint was "(new)". Now half an authority is refused, and nothing is
written.
"""

from __future__ import annotations

import pathlib
import re
import shutil

import pytest

from armplan.cli.main import main


@pytest.fixture
def machine_b(tmp_path: pathlib.Path) -> pathlib.Path:
    """A's bundle in tmp/a; B's folder with A's ca.pem and passwords.txt."""
    assert main(["certs", "--out", str(tmp_path / "a")]) == 0
    folder = tmp_path / "b"
    folder.mkdir()
    for name in ("ca.pem", "passwords.txt"):
        shutil.copy2(tmp_path / "a" / name, folder / name)
    return folder


def test_a_ca_without_its_key_is_not_replaced(
    machine_b: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    capsys.readouterr()
    before = (machine_b / "ca.pem").read_bytes()
    argv = ["certs", "--out", str(machine_b), "--connect", "tls/192.0.2.10:7447"]
    assert main(argv) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {machine_b / 'ca.pem'} exists without ca.key: its key is "
        "needed to sign the router's certificate. Copy ca.key here (or make this "
        "bundle on the machine that holds it and copy the bundle), or remove "
        "ca.pem to make a new authority (every machine then needs the new one)\n"
    )
    assert (machine_b / "ca.pem").read_bytes() == before
    assert sorted(p.name for p in machine_b.iterdir()) == ["ca.pem", "passwords.txt"]


def test_a_key_without_its_ca_is_not_replaced(
    machine_b: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (machine_b / "ca.pem").rename(machine_b / "ca.key")
    capsys.readouterr()
    assert main(["certs", "--out", str(machine_b)]) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {machine_b / 'ca.key'} exists without ca.pem: copy "
        "ca.pem here, or remove ca.key to make a new authority\n"
    )


@pytest.mark.parametrize("name", ["ca.pem", "ca.key"])
def test_a_folder_in_the_authoritys_place_is_named_as_such(
    name: str, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A folder named ca.pem, ca.key beside it or not, was "ca.pem exists
    without ca.key" (or, with both, a bundle signed by nothing openssl could
    read); it is named for what it is, and nothing is written."""
    out = tmp_path / "c"
    (out / name).mkdir(parents=True)
    assert main(["certs", "--out", str(out)]) == 1
    what = "certificate" if name == "ca.pem" else "key"
    assert capsys.readouterr().err == (
        f"armplan: error: {out / name} is not a file (a folder?): it must be the "
        f"authority's {what}; remove it or give another --out\n"
    )
    assert [p.name for p in out.iterdir()] == [name]


def test_with_its_key_the_authority_is_kept(
    machine_b: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The documented way: A's ca.key copied too, the authority is kept."""
    shutil.copy2(machine_b.parent / "a" / "ca.key", machine_b / "ca.key")
    before = (machine_b / "ca.pem").read_bytes()
    assert main(["certs", "--out", str(machine_b)]) == 0
    assert "certificate authority (kept)" in capsys.readouterr().out
    assert (machine_b / "ca.pem").read_bytes() == before


def test_a_kept_ca_key_open_to_others_is_made_owner_only(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A kept ca.key of mode 0644 stayed 0644 (passwords.txt was tightened)."""
    assert main(["certs", "--out", str(tmp_path)]) == 0
    key = tmp_path / "ca.key"
    key.chmod(0o644)
    capsys.readouterr()
    assert main(["certs", "--out", str(tmp_path)]) == 0
    assert key.stat().st_mode & 0o777 == 0o600
    assert capsys.readouterr().err == (
        f"armplan certs: warning: {key} was readable by others (mode 0644): made "
        "owner-only (0600); if others could read it, anyone with it can sign a "
        "router certificate\n"
    )
    assert main(["certs", "--out", str(tmp_path)]) == 0
    assert "warning" not in capsys.readouterr().err  # already owner-only


def test_a_bad_password_line_is_named_before_any_file_is_written(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The error named the line, but a new CA and router certificate were
    already written beside the broken file."""
    passwords = tmp_path / "passwords.txt"
    passwords.write_text("planner:abc\nno password here\n")
    assert main(["certs", "--out", str(tmp_path)]) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {passwords} line 2 is not user:password\n"
    )
    assert [p.name for p in tmp_path.iterdir()] == ["passwords.txt"]


def test_a_password_file_that_is_no_text_is_named_before_any_file_is_written(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A passwords.txt saved as UTF-16 ended `armplan certs` in a
    UnicodeDecodeError traceback."""
    passwords = tmp_path / "passwords.txt"
    passwords.write_bytes("planner:abc\n".encode("utf-16"))
    assert main(["certs", "--out", str(tmp_path)]) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {passwords} is not UTF-8 text (byte 0): it must hold "
        "user:password lines\n"
    )
    assert [p.name for p in tmp_path.iterdir()] == ["passwords.txt"]


def test_a_host_the_rerun_leaves_out_is_warned_of(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Each run issues the router's certificate for its own --host names: the
    same names again, in other forms, pass quietly; a rerun without one
    warns naming it (clients reaching the router by it would be refused)."""
    out = str(tmp_path / "bundle")
    assert main(["certs", "--out", out, "--host", "nao-router", "--host", "::1"]) == 0
    capsys.readouterr()
    again = ["--host", "NAO-ROUTER", "--host", "0:0:0:0:0:0:0:1"]
    assert main(["certs", "--out", out, *again]) == 0
    assert "warning" not in capsys.readouterr().err
    assert main(["certs", "--out", out, "--host", "::1"]) == 0
    dropped = re.search(
        r"named (.*), which the new one does not", capsys.readouterr().err
    )
    assert dropped is not None and dropped.group(1) == "nao-router"


@pytest.mark.parametrize(
    ("option", "message"),
    [
        ("--paths", "--paths is empty: name the folder of the files"),
        ("--endpoint", "endpoint '' must read PROTO/HOST:PORT"),
    ],
)
def test_an_empty_option_is_refused_not_taken_for_the_default(
    tmp_path: pathlib.Path,
    capsys: pytest.CaptureFixture[str],
    option: str,
    message: str,
) -> None:
    """``--paths "$DEST"`` with DEST unset wrote the --out folder's paths
    into every configuration, and ``--endpoint ""`` made a bundle for
    tls/127.0.0.1:7447, both without a word."""
    assert main(["certs", "--out", str(tmp_path), option, ""]) == 1
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
