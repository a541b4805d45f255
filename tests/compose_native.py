"""Run a docker-compose model's containers as native processes on loopback.

Compose names become loopback addresses: the router's endpoints
(``tcp/router:7447``, ``tls/router:7447``) a free port, the sim's NAOqi
address another. A file a container reads (its Zenoh config, the router's
config) is found through the container's volumes, or in the image (the
Dockerfile's ``ENV ARMPLAN_ZENOH_CONFIG``), and copied with the same
names replaced; paths under ``/run/armplan/secure`` become the folder
``armplan certs --compose`` wrote. A container's working folder (the image's
``WORKDIR``) is a new folder of its own, as a new container's is; each named
volume mounted elsewhere is one local folder that outlives the containers,
its mount point replaced by that folder in the commands. The router
container (eclipse/zenoh) runs as the Python router with the same file.
"""

from __future__ import annotations

import pathlib
import re
import subprocess
from typing import Any

from native_processes import ROOT, Native, stop_all

from armplan.launch import catalog, free_endpoint

#: The image's folder holding the sources (Dockerfile ``WORKDIR``).
IMAGE_SOURCES = "/opt/armplan"
#: Where the secured containers find their files.
SECURE_PATHS = "/run/armplan/secure"
#: The simulated NAO's address on the compose network.
SIM_HOST, SIM_PORT = "sim", 9559


def image_workdir() -> str:
    """The image's last WORKDIR (where the processes run)."""
    lines = (ROOT / "Dockerfile").read_text().splitlines()
    return [line.split()[1] for line in lines if line.startswith("WORKDIR")][-1]


def image_config() -> pathlib.Path:
    """The repository file the image's ARMPLAN_ZENOH_CONFIG names."""
    text = (ROOT / "Dockerfile").read_text()
    match = re.search(r"^ENV ARMPLAN_ZENOH_CONFIG=(\S+)$", text, re.M)
    assert match is not None and match.group(1).startswith(IMAGE_SOURCES + "/")
    return ROOT / match.group(1).removeprefix(IMAGE_SOURCES + "/")


class Localized:
    """One compose model's names and files, mapped to this machine.

    Attributes:
        endpoint: The router's loopback port (``tcp/127.0.0.1:PORT``).
        sim_port: The sim's loopback port.
    """

    def __init__(self, tmp: pathlib.Path, secure: pathlib.Path | None = None) -> None:
        self.endpoint = free_endpoint()
        self.sim_port = int(free_endpoint().rsplit(":", 1)[1])
        self._files = tmp / "files"
        self._files.mkdir()
        self._volumes = tmp / "volumes"
        self._copies: dict[pathlib.Path, pathlib.Path] = {}
        address = self.endpoint.split("/", 1)[1]
        self._names = {
            "tcp/router:7447": f"tcp/{address}",
            "tls/router:7447": f"tls/{address}",
            f"{SIM_HOST}:{SIM_PORT}": f"127.0.0.1:{self.sim_port}",
            f"('{SIM_HOST}', {SIM_PORT})": f"('127.0.0.1', {self.sim_port})",
        }
        if secure is not None:
            self._names[SECURE_PATHS] = str(secure)

    def text(self, value: str) -> str:
        """``value`` with every compose name replaced."""
        for name, local in self._names.items():
            value = value.replace(name, local)
        return value

    def volumes(self, service: dict[str, Any]) -> dict[str, pathlib.Path]:
        """The local folder of each named volume the container mounts, by target.

        One folder per volume name, kept across containers (a recreated
        container finds what the last one left); its mount point is replaced
        by the folder in every command from now on. A volume at the image's
        working folder is left out: the container's own folder stands for it.
        """
        found = {}
        for volume in service.get("volumes", []):
            if volume["type"] != "volume" or volume["target"] == image_workdir():
                continue
            folder = self._volumes / volume["source"]
            folder.mkdir(parents=True, exist_ok=True)
            self._names[volume["target"]] = str(folder)
            found[volume["target"]] = folder
        return found

    def file(self, service: dict[str, Any], inside: str) -> pathlib.Path:
        """A local copy of the file the container sees at ``inside``.

        The file must be mounted into the container, or be the image's config.
        Every secure file it names must be mounted too.
        """
        sources = {v["target"]: v["source"] for v in service.get("volumes", [])}
        if inside in sources:
            source = pathlib.Path(sources[inside])
        else:
            assert inside == str(
                pathlib.PurePosixPath(IMAGE_SOURCES) / image_config().relative_to(ROOT)
            ), f"{inside} is neither mounted nor in the image"
            source = image_config()
        for named in re.findall(
            re.escape(SECURE_PATHS) + r"/[\w.-]+", source.read_text()
        ):
            assert named in sources, f"{named} is named by {inside} but not mounted"
        return self.copy(source)

    def copy(self, source: pathlib.Path) -> pathlib.Path:
        """A copy of the host file ``source`` with every compose name replaced."""
        if source not in self._copies:
            local = self._files / f"{len(self._copies)}-{source.name}"
            local.write_text(self.text(source.read_text()))
            self._copies[source] = local
        return self._copies[source]

    def zenoh_config(self, service: dict[str, Any]) -> pathlib.Path:
        """The local copy of the container's ARMPLAN_ZENOH_CONFIG file."""
        inside = (service.get("environment") or {}).get("ARMPLAN_ZENOH_CONFIG")
        return self.file(service, inside or self.image_config_inside())

    @staticmethod
    def image_config_inside() -> str:
        relative = image_config().relative_to(ROOT)
        return str(pathlib.PurePosixPath(IMAGE_SOURCES) / relative)

    def argv(self, command: list[str]) -> list[str]:
        """A container command (or healthcheck) as a native one."""
        if command[:1] == ["CMD"]:
            command = command[1:]
        if command[0] == "armplan":  # the installed project's console script
            command = ["python", "-m", "armplan", *command[1:]]
        return [self.text(part) for part in command]

    def env(self, service: dict[str, Any], config: pathlib.Path) -> dict[str, str]:
        """The container's environment, localized, with its Zenoh config."""
        given = service.get("environment") or {}
        env = {k: self.text(v) for k, v in given.items()}
        return {**env, "ARMPLAN_ZENOH_CONFIG": str(config)}


def start_router(
    router: dict[str, Any], local: Localized, logs: pathlib.Path
) -> Native:
    """The router container as the Python router, reading the same file."""
    command = router["command"]
    assert command[0] == "-c", f"the router reads one config file: {command}"
    config = local.file(router, command[1])
    argv = ["python", "-m", catalog.ROUTER_MODULE, "--config", str(config)]
    return Native("router", argv, logs / "router.log")


def start_container(
    name: str, service: dict[str, Any], local: Localized, logs: pathlib.Path
) -> Native:
    """An armplan container's command, in a folder of its own, its volumes mounted.

    ``logs / name`` is the container's working folder: another ``logs``
    makes a recreated container, whose files are gone but for its volumes.
    """
    folder = logs / name
    folder.mkdir(exist_ok=True)
    local.volumes(service)
    config = local.zenoh_config(service)
    return Native(
        name,
        local.argv(service["command"]),
        logs / f"{name}.log",
        env=local.env(service, config),
        cwd=folder,
    )


def healthy(
    containers: dict[str, dict[str, Any]], local: Localized, logs: pathlib.Path
) -> set[str]:
    """The containers whose healthcheck passes now (the checks run side by side)."""
    checks = {
        name: Native(
            f"{name}-health",
            local.argv(service["healthcheck"]["test"]),
            logs / f"{name}-health.log",
            env=local.env(service, local.zenoh_config(service)),
        )
        for name, service in containers.items()
    }
    try:
        return {name for name, check in checks.items() if _passes(check)}
    finally:
        stop_all(list(checks.values()))


def _passes(check: Native, timeout: float = 30.0) -> bool:
    """Whether ``check`` exits 0 within ``timeout`` [s]."""
    try:
        return check.process.wait(timeout) == 0
    except subprocess.TimeoutExpired:
        return False
