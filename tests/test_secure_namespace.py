"""A secured deployment under another namespace: `armplan certs --namespace`.

The access rules named `armplan/**` only, and certs had no namespace option:
a secured robot given its own namespace (to share machines with another) got
"no liveliness token ..." with nothing naming access control. Now certs
writes the rules and every client file for the namespace given; a real
router shows the planner publishing there and a client refused.
"""

from __future__ import annotations

import pathlib
import threading
import time
from collections.abc import Iterator

import pytest
import zenoh
from native_processes import Native

from armplan.cli.main import main
from armplan.launch import catalog, free_endpoint
from armplan.secure import AccessControl, Bundle, write_bundle
from shared.bus import Bus, load_config
from shared.bus.routes import IK_SOLVE, ROUTES, TRAJECTORY_TOPIC
from shared.bus.topics import TOPICS
from shared.errors import ServiceUnavailableError
from shared.messages import IKRequest

NS = "lab/nao1"
#: How long a message that should not come is waited for [s].
QUIET = 1.0


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Bundle:
    port = free_endpoint().rsplit(":", 1)[1]
    folder = tmp_path_factory.mktemp("secure")
    return write_bundle(folder, endpoint=f"tls/127.0.0.1:{port}", namespace=NS)


def test_the_rules_and_the_files_name_the_namespace(bundle: Bundle) -> None:
    acl = AccessControl.from_file(bundle.router_config)
    for route in ROUTES:
        for user in ("client", "planner", "ik"):
            serves = user == route.service
            key = route.key(NS)
            assert acl.allows(user, "declare_queryable", "ingress", key) is serves
            assert not acl.allows(
                user, "declare_queryable", "ingress", route.key("armplan")
            )
    for topic in TOPICS:
        assert acl.allows(topic.publisher, "put", "ingress", topic.key(NS))
        assert not acl.allows("client", "put", "ingress", topic.key(NS))
    assert '"armplan/' not in bundle.router_config.read_text()  # no key left
    assert load_config(bundle.router_config).namespace == NS
    for path in bundle.clients.values():
        assert load_config(path).namespace == NS


def test_a_bad_namespace_is_refused_before_anything_is_written(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    assert main(["certs", "--out", str(out), "--namespace", "nao/*"]) == 1
    assert capsys.readouterr().err == (
        "armplan: error: namespace 'nao/*' must be chunks of letters, digits, "
        "'_' or '-' joined by '/', without wildcards\n"
    )
    assert not out.exists()


@pytest.fixture(scope="module")
def router(bundle: Bundle) -> Iterator[Native]:
    argv = ["python", "-m", catalog.ROUTER_MODULE, "--config"]
    folder = bundle.directory
    process = Native("router", [*argv, str(bundle.router_config)], folder / "r.log")
    try:
        yield process
    finally:
        process.stop()


def test_the_secured_router_serves_the_namespace(
    bundle: Bundle, router: Native
) -> None:
    """The planner's trajectory reaches the recorder, the client's does not;
    ik's token under the namespace is seen by `status` (the client)."""
    key = f"{NS}/{TRAJECTORY_TOPIC}"
    got: list[bytes] = []
    lock = threading.Lock()

    def on_sample(sample: zenoh.Sample) -> None:
        with lock:
            got.append(sample.payload.to_bytes())

    def arrived(payload: bytes, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with lock:
                if payload in got:
                    return True
            time.sleep(0.02)
        return False

    with (
        Bus.connect(load_config(bundle.clients["recorder"]), wait=30) as recorder,
        Bus.connect(load_config(bundle.clients["planner"])) as planner,
        Bus.connect(load_config(bundle.clients["client"])) as client,
        Bus.connect(load_config(bundle.clients["ik"])) as ik,
    ):
        subscriber = recorder.session.declare_subscriber(f"{NS}/**", on_sample)
        number = 0
        while True:  # until the recorder's subscription is routed
            number += 1
            probe = f"planned {number}".encode()
            planner.session.put(key, probe)
            if arrived(probe, 0.2):
                break
            assert number < 100, router.output()
        client.session.put(key, b"forged")
        assert not arrived(b"forged", QUIET)
        token = ik.session.liveliness().declare_token(f"{NS}/alive/ik")
        deadline = time.monotonic() + 10
        while "ik" not in client.alive():
            assert time.monotonic() < deadline
            time.sleep(0.1)
        token.undeclare()  # type: ignore[no-untyped-call]
        subscriber.undeclare()  # type: ignore[no-untyped-call]


def test_a_refused_look_elsewhere_leaves_the_hint_out(
    bundle: Bundle, router: Native
) -> None:
    """The client may not ask for ``**/alive/ik``: the error for an ik not
    running is the plain one, not another error, and comes at once."""
    with (
        Bus.connect(load_config(bundle.clients["client"]), wait=30) as client,
        pytest.raises(ServiceUnavailableError) as info,
    ):
        client.call(IK_SOLVE, IKRequest(target=(0.12, -0.13, 0.05)), timeout=2.0)
    assert info.value.elsewhere == {}
    assert info.value.reason == (
        f"no liveliness token at {NS}/alive/ik (is it started, e.g. by `armplan "
        "up` or `python -m services.ik`?)"
    )
