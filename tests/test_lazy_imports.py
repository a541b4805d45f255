"""Where scipy is not used, it is not loaded.

``scipy.optimize`` takes about 0.6 s to import, ``scipy.interpolate``
about 0.7 s, and every process of the stack pays its imports at each
start. So each is imported where it is called, when nothing else of the
process needs it:

- the IK imports ``shared.demos.posture_from_points`` for its elbow turns,
  whose least-squares fallback needs ``scipy.optimize``;
- every reader of a motion model imports ``services.fit``, whose weight
  regression needs ``scipy.optimize`` (``nnls``), as its filter needs
  ``scipy.signal``;
- the IK and decide services import the planner's stages, whose timing
  stage (``services.planner.timing_stage``, apart) needs
  ``scipy.interpolate``, and ``services.planner.build``, which names the
  timing's ``TimedTrajectory`` for its types only.

``armplan ik`` loads no scipy at all (1.7-2.0 s a call before, 1.1-1.2 s
after, on a 2-CPU machine); the ik, decide and fit services start without
it (imports 1.4, 1.4 and 1.2 s before, 0.6, 0.7 and 0.8 s after)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from shared.demos.posture_from_points import joints_from_points
from shared.robot import load_arm

ROOT = Path(__file__).resolve().parent.parent


def _scipy_loaded_by(code: str) -> list[str]:
    """The scipy modules a fresh interpreter holds after running ``code``."""
    report = (
        "import sys\nprint(' '.join(m for m in sys.modules if m.startswith('scipy')))"
    )
    out = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code) + "\n" + report],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert out.returncode == 0, out.stderr
    return out.stdout.split()


def test_armplan_ik_loads_no_scipy() -> None:
    """A whole ``armplan ik`` command, in this interpreter, imports no scipy."""
    loaded = _scipy_loaded_by(
        """
        import contextlib, io
        from armplan.cli.main import main
        with contextlib.redirect_stdout(io.StringIO()) as out:
            code = main(["ik", "--target", "0.12", "-0.13", "0.05", "--json"])
        assert code == 0 and '"joints"' in out.getvalue(), out.getvalue()
        """
    )
    assert loaded == []


@pytest.mark.parametrize("service", ["ik", "decide", "fit"])
def test_a_service_that_does_not_time_starts_without_scipy(service: str) -> None:
    """Importing the ik, decide or fit service loads no scipy module."""
    assert _scipy_loaded_by(f"import services.{service}.service") == []


def test_the_least_squares_fallback_still_solves() -> None:
    """Points off NAO's lengths have no closed form: the fallback (which
    imports scipy.optimize when called) puts elbow and wrist on them as
    nearly as the arm allows, within the joint ranges."""
    arm = load_arm("right")
    q = np.array([0.6, -0.4, 0.8, 0.9, 0.0])
    points = arm.fk(q)
    elbow = points.elbow + np.array([0.0, 0.0, 0.004])  # 4 mm off the arm's lengths
    solved = joints_from_points(arm, elbow, points.wrist, guess=q)
    reached = arm.fk(solved)
    assert np.all(solved >= arm.limits.lower) and np.all(solved <= arm.limits.upper)
    wrist_error = np.linalg.norm(reached.wrist - points.wrist)
    elbow_error = np.linalg.norm(reached.elbow - elbow)
    assert 1e-4 < wrist_error + elbow_error < 0.004  # no exact posture; the nearest
