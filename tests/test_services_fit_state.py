"""Which model the fit service serves across restarts, and a model from a file.

Real processes: the router and the fit service (``armplan.launch.Launcher``),
``python -m services.fit`` and ``armplan up`` on their own, and the CLI's
``plan --model`` in-process.
"""

from __future__ import annotations

import json
import os
import pathlib
import signal
import subprocess
import sys
from collections.abc import Iterator

import pytest

from armplan.cli.main import main
from armplan.launch import Launcher, free_endpoint
from services.fit import default_model, fit_model, save_model
from services.fit.demo_dir import DEMOS_DIR_ENV
from services.fit.model_state import STATE_FILE, digest, state_file
from services.planner.pipeline import plan
from services.planner.stages import LocalStages
from shared.bus import Bus, NoArguments, load_config
from shared.bus.routes import FIT, FIT_MODEL
from shared.demos import read_demos, synthesize, write_demos
from shared.errors import InvalidInputError
from shared.messages import FitRequest, MotionModel, PlanRequest, Trajectory, parse

DEMOS = "demos.mcap"
TARGET = (0.12, -0.1, 0.05)


@pytest.fixture(scope="module")
def demos_dir(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """A directory holding a small synthetic demonstration file (seed 9)."""
    root = tmp_path_factory.mktemp("demos")
    write_demos(root / DEMOS, synthesize(9, subjects=3, trials=1))
    return root


@pytest.fixture(scope="module")
def fitted(demos_dir: pathlib.Path) -> MotionModel:
    """The model a fit of ``demos_dir``'s file gives (bins 10)."""
    return fit_model(read_demos(demos_dir / DEMOS), bins=10, sources=[DEMOS])


@pytest.fixture(scope="module")
def vanishing(demos_dir: pathlib.Path) -> MotionModel:
    """A model of the same file whose tables hold probabilities of 0: fitted
    with a smoothing of 5e-324, it cannot decide (``Decider`` refuses it)."""
    demos = read_demos(demos_dir / DEMOS)
    return fit_model(demos, bins=10, smoothing=5e-324, sources=[DEMOS])


@pytest.fixture
def log(tmp_path: pathlib.Path) -> pathlib.Path:
    """The children's log file."""
    return tmp_path / "children.log"


@pytest.fixture
def stack(
    demos_dir: pathlib.Path, log: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> Iterator[Launcher]:
    """Router and fit, reading ``demos_dir`` and keeping its state there."""
    for old in demos_dir.glob("*.json"):
        old.unlink()
    monkeypatch.setenv(DEMOS_DIR_ENV, str(demos_dir))
    config = load_config(endpoints=(free_endpoint(),))
    with log.open("w") as out, Launcher(config, ["fit"], log=out) as stack:
        yield stack


def restart_fit(stack: Launcher, bus: Bus) -> None:
    stack.services["fit"].signal(signal.SIGTERM)
    stack.services["fit"].process.wait(30.0)
    stack.start_service("fit")
    assert bus.wait_alive(["fit"], 60.0) == []


def test_a_restarted_fit_service_serves_the_model_it_fitted(
    stack: Launcher, demos_dir: pathlib.Path, fitted: MotionModel, log: pathlib.Path
) -> None:
    """The fitted model is kept in the state file and served after a restart,
    not replaced by the shipped default; the log says which model and whence."""
    with Bus.connect(stack.config) as bus:
        assert bus.call(FIT_MODEL, NoArguments()) == default_model()
        assert not (demos_dir / STATE_FILE).exists()  # the default is not written
        assert bus.call(FIT, FitRequest(files=[DEMOS], bins=10), timeout=300) == fitted
        assert (demos_dir / STATE_FILE).exists()
        restart_fit(stack, bus)
        assert bus.call(FIT_MODEL, NoArguments()) == fitted
    said = log.read_text()
    assert f"serving model {digest(default_model())} " in said
    assert f"serving model {digest(fitted)} " in said
    assert f"from state {demos_dir / STATE_FILE}" in said


def test_a_fit_whose_model_cannot_decide_is_refused_and_not_kept(
    stack: Launcher, demos_dir: pathlib.Path
) -> None:
    """A fit with a smoothing of 5e-324 gives tables the decision cannot
    use: it is refused, naming why; the model served stays and nothing is
    kept (it was served, kept and published while decide ignored it)."""
    request = FitRequest(files=[DEMOS], bins=10, smoothing=5e-324)
    with Bus.connect(stack.config) as bus:
        with pytest.raises(InvalidInputError) as refused:
            bus.call(FIT, request, timeout=300)
        assert bus.call(FIT_MODEL, NoArguments()) == default_model()
    assert refused.value.message.startswith(
        f"the model fitted on {DEMOS} (bins 10, smoothing 5e-324) is not served, "
        "the current one stays: the motion model cannot decide: its "
    )
    assert refused.value.field == "smoothing"
    assert not (demos_dir / STATE_FILE).exists()


def test_fit_service_starts_from_a_model_file(
    demos_dir: pathlib.Path,
    fitted: MotionModel,
    tmp_path: pathlib.Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``--model FILE`` (as ``armplan up --model`` passes it) is served from
    the start, and kept: a restart without it serves it too."""
    file, state = tmp_path / "lab.json", tmp_path / "state"
    state.mkdir()
    save_model(fitted, file)
    monkeypatch.setenv(DEMOS_DIR_ENV, str(demos_dir))
    config = load_config(endpoints=(free_endpoint(),))
    with (
        Launcher(
            config,
            ["fit"],
            log=subprocess.DEVNULL,
            service_args={"fit": ["--model", str(file), "--state-dir", str(state)]},
        ) as stack,
        Bus.connect(stack.config) as bus,
    ):
        assert bus.call(FIT_MODEL, NoArguments()) == fitted
    with (
        Launcher(
            config,
            ["fit"],
            log=subprocess.DEVNULL,
            service_args={"fit": ["--state-dir", str(state)]},
        ) as stack,
        Bus.connect(stack.config) as bus,
    ):
        assert bus.call(FIT_MODEL, NoArguments()) == fitted


NAMESPACED = """{{
  mode: "router",
  listen: {{ endpoints: ["{endpoint}"] }},
  scouting: {{ multicast: {{ enabled: false }} }},
  metadata: {{ armplan: {{ namespace: "{namespace}" }} }},
}}"""


def test_state_files_of_two_namespaces_are_two_files(tmp_path: pathlib.Path) -> None:
    """The default namespace keeps the old name; others get their own, and
    ``a/b`` and ``a-b`` (or ``a_b``) never share one."""
    names = ["armplan", "lab/nao1", "lab-nao1", "lab_nao1", "lab/nao1/x"]
    files = [state_file(tmp_path, name) for name in names]
    assert files[0] == tmp_path / STATE_FILE
    assert files[1] == tmp_path / "armplan-fit-model.lab.nao1.json"
    assert len(set(files)) == len(names)


def test_a_robot_of_another_namespace_does_not_serve_the_first_ones_model(
    demos_dir: pathlib.Path,
    fitted: MotionModel,
    tmp_path: pathlib.Path,
    log: pathlib.Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Two fit services in one folder, the second in namespace ``lab/nao1``
    without ``--model``: it served the first one's model from its state
    file (and a fit of either overwrote the other's). Now it serves the
    shipped default, says why it passed the file over, and keeps its own."""
    lab, shared = tmp_path / "lab.json", tmp_path / STATE_FILE
    save_model(fitted, lab)
    monkeypatch.setenv(DEMOS_DIR_ENV, str(demos_dir))
    first = load_config(endpoints=(free_endpoint(),))
    state = ("--state-dir", str(tmp_path))
    with Launcher(
        first,
        ["fit"],
        log=subprocess.DEVNULL,
        service_args={"fit": ["--model", str(lab), *state]},
    ):
        assert shared.exists()
    path = tmp_path / "lab-nao1.json5"
    path.write_text(NAMESPACED.format(endpoint=free_endpoint(), namespace="lab/nao1"))
    with (
        log.open("w") as out,
        Launcher(
            load_config(path), ["fit"], log=out, service_args={"fit": state}
        ) as stack,
        Bus.connect(stack.config) as bus,
    ):
        assert bus.call(FIT_MODEL, NoArguments()) == default_model()
        refit = bus.call(FIT, FitRequest(files=[DEMOS], bins=8), timeout=300)
    assert refit != fitted
    own = tmp_path / "armplan-fit-model.lab.nao1.json"
    assert MotionModel.model_validate_json(own.read_text()) == refit
    assert MotionModel.model_validate_json(shared.read_text()) == fitted
    said = log.read_text()
    assert "from shipped default " in said
    assert (
        f"not reading {shared}: it is the state file of namespace 'armplan'; "
        f"this fit service (namespace 'lab/nao1') keeps its model in {own.name}"
    ) in said


def run_fit_service(*args: str) -> subprocess.CompletedProcess[str]:
    """``python -m services.fit`` against a router that is not there."""
    return subprocess.run(
        [sys.executable, "-m", "services.fit", "--connect", free_endpoint(), *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


def test_a_bad_model_file_stops_the_fit_service_naming_it(
    tmp_path: pathlib.Path,
) -> None:
    """Exit 1 before connecting, the file and its problem logged."""
    bad = tmp_path / "bad.json"
    bad.write_text('{"version": 1, "bins"')
    out = run_fit_service("--model", str(bad), "--wait", "0.5")
    assert out.returncode == 1
    assert f"{bad}: the motion-model file is truncated" in out.stderr


def test_a_bad_state_file_is_not_passed_over(tmp_path: pathlib.Path) -> None:
    """A damaged state file stops the service: serving the shipped default
    instead would throw the lab's model away without a word."""
    (tmp_path / STATE_FILE).write_text("{}")
    out = run_fit_service("--state-dir", str(tmp_path), "--wait", "0.5")
    assert out.returncode == 1
    assert "delete it to start from the shipped default" in out.stderr


def test_a_model_file_that_cannot_decide_stops_the_fit_service(
    tmp_path: pathlib.Path, vanishing: MotionModel
) -> None:
    """``--model`` of a model the decision cannot use: exit 1 naming the
    file and the table, before serving it (decide could not start on it)."""
    file = tmp_path / "vanishing.json"
    save_model(vanishing, file)
    state = ("--state-dir", str(tmp_path))  # not kept where the tests run
    out = run_fit_service("--model", str(file), *state, "--wait", "0.5")
    assert out.returncode == 1
    assert f"{file}: the motion model cannot decide: its " in out.stderr


def test_a_state_file_that_cannot_decide_is_not_passed_over(
    tmp_path: pathlib.Path, vanishing: MotionModel
) -> None:
    """A state file holding a model the decision cannot use (kept by an
    older fit service) stops the service as a damaged one does."""
    save_model(vanishing, tmp_path / STATE_FILE)
    out = run_fit_service("--state-dir", str(tmp_path), "--wait", "0.5")
    assert out.returncode == 1
    assert f"{tmp_path / STATE_FILE}: the motion model cannot decide" in out.stderr
    assert "delete it to start from the shipped default" in out.stderr


def run_up_with_model(model: pathlib.Path) -> subprocess.CompletedProcess[str]:
    """``armplan up --model MODEL``, expected to stop before starting."""
    return subprocess.run(
        [
            *(sys.executable, "-m", "armplan", "up", "--listen", free_endpoint()),
            *("--model", str(model)),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


def test_up_refuses_a_bad_model_before_starting(tmp_path: pathlib.Path) -> None:
    """``armplan up --model`` checks the file first: nothing starts."""
    out = run_up_with_model(tmp_path / "missing.json")
    assert out.returncode == 1
    assert "no such motion-model file" in out.stderr
    assert "router" not in out.stdout


def test_up_refuses_a_model_that_cannot_decide_before_starting(
    tmp_path: pathlib.Path, vanishing: MotionModel
) -> None:
    """``armplan up --model`` checks the file as the fit service does: a
    model the decision cannot use stops it before anything starts."""
    file = tmp_path / "vanishing.json"
    save_model(vanishing, file)
    out = run_up_with_model(file)
    assert out.returncode == 1
    assert f"{file}: the motion model cannot decide: its " in out.stderr
    assert "router" not in out.stdout


def test_plan_model_plans_with_the_given_model(
    capsys: pytest.CaptureFixture[str], fitted: MotionModel, tmp_path: pathlib.Path
) -> None:
    """``armplan plan --model FILE`` decides with that model, in-process."""
    file = tmp_path / "lab.json"
    save_model(fitted, file)
    request = PlanRequest.model_validate({"targets": [{"position": TARGET}]})
    wanted = plan(request, LocalStages(fitted)).trajectory
    assert wanted != plan(request).trajectory  # the test can fail
    target = [str(v) for v in TARGET]
    assert main(["plan", "--target", *target, "--model", str(file), "--json"]) == 0
    assert parse(Trajectory, capsys.readouterr().out) == wanted
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"version": 1}))
    assert main(["plan", "--target", *target, "--model", str(bad)]) == 1
    assert "malformed motion model" in capsys.readouterr().err


@pytest.mark.parametrize("problem", ["missing", "file"])
def test_a_state_dir_that_cannot_keep_the_model_stops_the_service(
    tmp_path: pathlib.Path, problem: str
) -> None:
    """``--state-dir`` missing or a file: exit 1 naming it, before connecting
    (it started, and each fit's model was lost at the next restart)."""
    where = tmp_path / "state"
    if problem == "file":
        where.write_text("not a folder\n")
    out = run_fit_service("--state-dir", str(where), "--wait", "0.5")
    assert out.returncode == 1
    said = "no such folder" if problem == "missing" else "not a folder"
    assert f"--state-dir {where}: {said}; the fit service keeps" in out.stderr
    assert "router" not in out.stderr.split(said)[0]


def test_a_default_state_dir_that_cannot_keep_the_model_is_warned_of(
    tmp_path: pathlib.Path,
) -> None:
    """The default folder ($ARMPLAN_DEMOS_DIR) missing: the service still
    starts (it is not the operator's choice) but says at once that a fitted
    model will not survive a restart."""
    missing = tmp_path / "no-demos-here"
    command = [sys.executable, "-m", "services.fit", "--wait", "0.5"]
    out = subprocess.run(
        [*command, "--connect", free_endpoint()],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        env={**os.environ, "ARMPLAN_DEMOS_DIR": str(missing)},
    )
    assert (
        f"a fitted model will be served but not kept for a restart: {missing}: "
        "no such folder (give --state-dir DIR)" in out.stderr
    )


def test_namespace_option_names_the_state_file(
    fitted: MotionModel, tmp_path: pathlib.Path, caplog: pytest.LogCaptureFixture
) -> None:
    """``python -m services.fit --namespace lab/nao1`` (as ``armplan up
    --namespace lab/nao1`` starts it) keeps its own state file: it read the
    namespace from the file alone, so it served, and overwrote, the default
    namespace's ``armplan-fit-model.json``."""
    from services.fit.service import OPTIONS
    from shared.bus.runner import _parser

    save_model(fitted, tmp_path / STATE_FILE)
    parser = _parser("fit")
    OPTIONS.add(parser)
    args = parser.parse_args(["--namespace", "lab/nao1", "--state-dir", str(tmp_path)])
    with caplog.at_level("WARNING"):
        OPTIONS.endpoints(args)
    own = "armplan-fit-model.lab.nao1.json"
    assert f"this fit service (namespace 'lab/nao1') keeps its model in {own}" in (
        caplog.text
    )
