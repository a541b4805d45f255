"""A native and a docker-compose bundle are kept apart; the compose recipe is whole.

README's Security block ran `armplan certs --out secure --compose` into the
native setup's folder: every client file then named /run/armplan/secure, the
router tls/router:7447, and the reissued certificate lost the earlier --host
names, without a word. The README and the compose file's header also left
out the `--build-arg ARMPLAN_UID=$(id -u)` step, and from a root shell that
step gives uid 0, which the image's useradd refuses.
"""

from __future__ import annotations

import os
import pathlib
import re
import subprocess

import pytest

from armplan.cli.main import main

ROOT = pathlib.Path(__file__).resolve().parent.parent
#: Every file that shows the secured compose recipe.
RECIPES = [
    "README.md",
    "docs/services.md",
    "docker-compose.yml",
    "docker-compose.secure.yml",
]


def test_certs_refuses_to_turn_a_native_bundle_into_a_compose_one(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "secure"
    argv = ["certs", "--out", str(folder), "--host", "planner-pc.lab"]
    assert main(argv) == 0
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    capsys.readouterr()
    assert main(["certs", "--out", str(folder), "--compose"]) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {folder} holds a native bundle (its files named in "
        f"{folder.resolve()}): this run would rewrite it as a docker-compose "
        "bundle (files named in /run/armplan/secure) and reissue its router "
        "certificate. Write the docker-compose bundle to a folder of its own "
        f"(--out), or remove {folder / 'router.json5'} to turn this one over\n"
    )
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before


def test_certs_refuses_to_turn_a_compose_bundle_into_a_native_one(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["certs", "--out", str(tmp_path), "--compose"]) == 0
    capsys.readouterr()
    assert main(["certs", "--out", str(tmp_path)]) == 1
    assert "holds a docker-compose bundle" in capsys.readouterr().err
    (tmp_path / "router.json5").unlink()  # turned over on purpose
    assert main(["certs", "--out", str(tmp_path)]) == 0


def test_a_bundle_of_the_same_kind_is_rewritten(tmp_path: pathlib.Path) -> None:
    """Another endpoint, a moved folder: the same kind, no refusal."""
    assert main(["certs", "--out", str(tmp_path / "a")]) == 0
    assert (
        main(
            ["certs", "--out", str(tmp_path / "a"), "--endpoint", "tls/127.0.0.1:7555"]
        )
        == 0
    )
    (tmp_path / "a").rename(tmp_path / "b")
    assert main(["certs", "--out", str(tmp_path / "b")]) == 0
    assert (
        str(tmp_path / "b" / "ca.pem") in (tmp_path / "b" / "client.json5").read_text()
    )


@pytest.mark.parametrize("name", RECIPES)
def test_every_compose_recipe_builds_with_the_owner_of_the_files(name: str) -> None:
    text = (ROOT / name).read_text()
    assert re.search(r"armplan certs --out \S+ --compose", text)
    assert "--build-arg ARMPLAN_UID=$(id -u)" in text
    assert "root shell" in text


def dockerfile_uid_check() -> str:
    """The Dockerfile's RUN line that checks ARMPLAN_UID, as a shell command."""
    text = (ROOT / "Dockerfile").read_text()
    found = re.search(r'^RUN (test "\$\{ARMPLAN_UID\}" != 0 .*)$', text, re.M)
    assert found is not None
    assert text.index(found.group(0)) < text.index("useradd --uid")
    return found.group(1)


@pytest.mark.parametrize(("uid", "code"), [("0", 1), ("1000", 0), ("4242", 0)])
def test_the_image_refuses_uid_0_with_a_message(uid: str, code: int) -> None:
    """The check runs as the build would run it: sh, the build argument in env."""
    done = subprocess.run(
        ["sh", "-c", dockerfile_uid_check()],
        env={**os.environ, "ARMPLAN_UID": uid},
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == code
    if code:
        assert done.stderr.startswith("ARMPLAN_UID is 0 (id -u of a root shell)")
        assert "chown -R 1000" in done.stderr


def test_a_relative_paths_is_written_absolute(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`--paths relative/dir` went into the configurations as it was, to be
    looked up from each process's own folder; it is made absolute against
    the folder `armplan certs` runs in, `..` folded."""
    monkeypatch.chdir(tmp_path)
    argv = ["certs", "--out", "secure", "--paths", "elsewhere/../relative/dir"]
    assert main(argv) == 0
    files = tmp_path / "relative" / "dir"
    client = (tmp_path / "secure" / "client.json5").read_text()
    assert f'"{files / "ca.pem"}"' in client
    router = (tmp_path / "secure" / "router.json5").read_text()
    for name in ("ca.pem", "router.pem", "router.key", "passwords.txt"):
        assert f'"{files / name}"' in router, name
    assert "elsewhere" not in router + client
