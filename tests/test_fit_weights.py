"""The measures' weights fitted by regression (services.fit.weights).

The central check is the agreement of two methods: postures made optimal
for known weights by a general constrained optimiser (scipy's SLSQP on H
with the wrist and palm held) must give those weights back from the
regression on the null-space gradient, through the whole path a recorded
demonstration takes (points and wrist frames, turned back into angles).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.optimize import minimize  # type: ignore[import-untyped]

from services.fit.weights import fit_weights, null_space_rows, regress, trial_rows
from services.ik.kernel.chain import Chain, chain_for
from services.ik.measures.ntpe import WristDiscomfortEnergy
from services.ik.measures.tpe import TotalPotentialEnergy
from services.ik.task import WristTask
from shared.demos.synthetic import synthesize
from shared.demos.trial import DemoSet, Trial
from shared.errors import InvalidInputError
from shared.geometry.palm import roll_error
from shared.messages.measure_params import MeasureParams
from shared.messages.motion_model import FittedWeights
from shared.robot import load_arm
from shared.robot.side import Side

MU, OMEGA = 0.2, 0.02


def _optimal_postures(count: int, seed: int) -> list[np.ndarray]:
    """Postures minimising H (mu = MU, omega = OMEGA) with their wrist and palm held.

    The palm held is the posture's own palm normal (as a demonstration's
    wrist frame gives it), so the optimum is found as a fixed point: hold
    the palm, optimise, hold the new posture's palm, until it stays.
    """
    arm = load_arm("right")
    chain = chain_for(arm)
    rng = np.random.default_rng(seed)
    lower, upper = arm.limits.lower, arm.limits.upper
    measure = WristDiscomfortEnergy(TotalPotentialEnergy(MU), OMEGA, 0.0)
    out = []
    while len(out) < count:
        q = lower + (upper - lower) * rng.uniform(0.25, 0.75, 5)
        wrist = np.array(chain.state(q).p_wrist)
        for _ in range(30):
            palm = np.array(chain.state(q).rot)[:, 1]
            q, held = _optimum(chain, measure, q, wrist, palm)
            if np.linalg.norm(np.array(chain.state(q).rot)[:, 1] - palm) < 1e-11:
                break
        inside = np.all(q - lower > 0.05) and np.all(upper - q > 0.05)
        if inside and held < 1e-10:
            out.append(q)
    return out


def _optimum(
    chain: Chain,
    measure: WristDiscomfortEnergy,
    q0: np.ndarray,
    wrist: np.ndarray,
    palm: np.ndarray,
) -> tuple[np.ndarray, float]:
    """SLSQP's minimum of ``measure``, the wrist on ``wrist``, the palm on ``palm``."""

    def held(q: np.ndarray) -> np.ndarray:
        st = chain.state(q)
        return np.append(np.array(st.p_wrist) - wrist, roll_error(st.rot, 1.0, palm))

    best = minimize(
        lambda q: measure.value(chain.state(q)),
        q0,
        jac=lambda q: np.array(measure.gradient(chain.state(q))),
        constraints=[{"type": "eq", "fun": held}],
        method="SLSQP",
        options={"ftol": 1e-16, "maxiter": 1000},
    )
    return best.x, float(np.max(np.abs(held(best.x))))


def _trial(postures: list[np.ndarray], frames: bool = True) -> Trial:
    """A one-subject demonstration whose samples are ``postures`` (NAO's arm)."""
    arm = load_arm("right")
    points = [arm.fk(q) for q in postures]
    wrist = np.array([p.wrist for p in points])
    return Trial(
        subject="optimal",
        trial=0,
        point=0,
        arm=Side.RIGHT,
        times=np.arange(len(postures)) * 0.01,
        shoulder=np.array([p.shoulder for p in points]),
        elbow=np.array([p.elbow for p in points]),
        wrist=wrist,
        wrist_frame=np.array([arm.rotation(q, "wrist") for q in postures])
        if frames
        else None,
        target=wrist[-1],
        labels=None,
    )


@pytest.fixture(scope="module")
def optimal() -> list[np.ndarray]:
    return _optimal_postures(12, seed=4)


def test_recovers_the_weights_its_postures_are_optimal_for(
    optimal: list[np.ndarray],
) -> None:
    demos = DemoSet({}, [_trial(optimal)])
    fitted = fit_weights(demos, stride=1)
    assert fitted is not None
    assert fitted.samples == len(optimal)
    assert fitted.mu == pytest.approx(MU, rel=1e-3)
    assert fitted.omega == pytest.approx(OMEGA, rel=1e-3)
    assert fitted.explained > 0.999


def test_the_fit_beats_any_other_weights_on_its_rows() -> None:
    """Least squares: the fitted weights leave the smallest residual."""
    demos = synthesize(0, subjects=2, trials=1, points=(1, 6, 11, 16))
    stacked = np.concatenate([r for t in demos.trials for r in trial_rows(t, 8)])
    fitted = regress(stacked, True)
    assert fitted.omega is not None
    assert 0.0 <= fitted.explained <= 1.0

    def residual(mu: float, omega: float) -> float:
        return float(
            np.linalg.norm(stacked[:, 0] + mu * stacked[:, 1] + omega * stacked[:, 2])
        )

    best = residual(fitted.mu, fitted.omega)
    shipped = MeasureParams()
    assert best <= residual(shipped.mu, shipped.omega) + 1e-12
    for mu, omega in [
        (fitted.mu + 0.01, fitted.omega),
        (fitted.mu, fitted.omega * 1.5 + 1e-4),
    ]:
        assert best < residual(mu, omega)
    assert fit_weights(demos) == fitted  # the same rows, deterministic


def test_without_the_wrist_roll_omega_is_not_fitted(optimal: list[np.ndarray]) -> None:
    fitted = fit_weights(DemoSet({}, [_trial(optimal, frames=False)]), stride=1)
    assert fitted is not None
    assert fitted.omega is None
    assert fitted.samples == 2 * len(optimal)  # two null directions per sample


def test_null_space_rows_are_zero_at_an_optimum(optimal: list[np.ndarray]) -> None:
    """The identity the regression rests on: N^T grad H = 0 at the optimum."""
    arm = load_arm("right")
    chain = chain_for(arm)
    for q in optimal:
        st = chain.state(q)
        task = WristTask.make(st.p_wrist, np.array(st.rot)[:, 1], 1.0)
        rows = null_space_rows(chain, q, task, 0.0)
        assert rows.shape == (1, 3)
        assert abs(rows[0, 0] + MU * rows[0, 1] + OMEGA * rows[0, 2]) < 1e-7


def test_a_stride_below_one_is_refused() -> None:
    with pytest.raises(InvalidInputError, match="stride"):
        fit_weights(DemoSet({}, []), stride=0)


def test_postures_at_the_limits_give_no_weights() -> None:
    arm = load_arm("right")
    at_limit = [arm.limits.lower.copy() for _ in range(3)]
    assert fit_weights(DemoSet({}, [_trial(at_limit)]), stride=1) is None


def test_model_measures_take_the_fitted_weights_over_the_shipped() -> None:
    from services.fit import default_model

    model = default_model()
    bare = model.model_copy(update={"weights": None})
    assert bare.measures() == MeasureParams()
    fitted = FittedWeights(mu=0.5, omega=0.25, samples=100, explained=0.5)
    assert model.model_copy(update={"weights": fitted}).measures() == MeasureParams(
        mu=0.5, omega=0.25
    )
    no_roll = FittedWeights(mu=0.5, omega=None, samples=100, explained=0.5)
    kept = model.model_copy(update={"weights": no_roll}).measures()
    assert (kept.mu, kept.omega) == (0.5, MeasureParams().omega)


def test_a_model_file_without_weights_still_reads(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from services.fit import default_model, load_model

    data = json.loads(default_model().to_json())
    data.pop("weights", None)
    path = tmp_path / "old.json"
    path.write_text(json.dumps(data))
    assert load_model(path).weights is None


def test_the_shipped_weights_are_the_shipped_models_fit() -> None:
    from services.fit import default_model

    weights = default_model().weights
    assert weights is not None and weights.omega is not None
    assert MeasureParams() == default_model().measures()
    assert 0.0 < weights.explained <= 1.0


@pytest.mark.parametrize(
    "samples,explained,trusted",
    [(22, 0.0, False), (3043, 0.012, False), (29, 0.9, False), (30, 0.5, True)],
    ids=["left-as-right", "wrong-axes", "few-equations", "at-the-floor"],
)
def test_weights_that_explain_too_little_keep_the_shipped_ones(
    samples: int, explained: float, trusted: bool
) -> None:
    """Weights from 22 equations explaining 0 % once replaced the shipped
    omega with 0: below the floor a model plans with the shipped weights."""
    from services.fit import default_model

    fitted = FittedWeights(mu=0.0, omega=0.0, samples=samples, explained=explained)
    model = default_model().model_copy(update={"weights": fitted})
    assert fitted.trusted is trusted
    assert model.measures() == (
        MeasureParams(mu=0.0, omega=0.0) if trusted else MeasureParams()
    )
    assert ("too little to plan with" in fitted.untrusted()) is not trusted
    shipped = default_model().weights
    assert shipped is not None and shipped.trusted  # the default model's are used
