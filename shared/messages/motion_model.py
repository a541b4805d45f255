"""The motion model as a message: what fitting writes and the decision reads.

The fitted densities, states and network tables (``services.fit`` fits
them, ``services.decide`` decides with them). It is a message in ``shared/``
because it crosses processes: the fit service serves it (``<ns>/fit/model``)
and publishes each new one (``<ns>/fit/model/update``), which the decide
service swaps in, and the recorder gives that topic the model's schema.
``MODEL_VERSION`` changes whenever the meaning of a field changes; a model
of another version is refused.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydantic import Field, model_validator

from shared.messages.base import Message
from shared.messages.measure_params import MOST, MeasureParams
from shared.messages.model_tables import CONDITIONED, Conditionals, conditionals
from shared.primitives import MOTION_PRIMITIVES

#: Version of the model format.
MODEL_VERSION = 1
#: The motion variables in the network's order (the arm's serial chain).
VARIABLES: tuple[str, ...] = ("S_R", "E_P", "E_R", "W_P", "W_R")
_MOTION_NAMES = [p.name for p in MOTION_PRIMITIVES]

Table = list[float]


#: Largest pseudo-count per table cell: far above any demonstration set's
#: counts (it would drown them), far below where the tables' sums overflow.
MAX_SMOOTHING = 1e6


#: Range of a model's demonstration sample rate [Hz]: a rate of 1e300 once
#: passed and made every later decision NaN.
MIN_SAMPLE_RATE, MAX_SAMPLE_RATE = 1.0, 10_000.0


class VariableFit(Message):
    """One motion variable's exponential density and its states.

    Attributes:
        name: The variable, e.g. ``"S_R"``.
        unit: ``"rad"`` or ``"arm lengths"`` (distances over L_u + L_f).
        rate: Rate gamma of the density, by maximum likelihood [1/unit].
        samples: Samples it was fitted on; 0 if never observed (W_R without
            wrist orientations), when ``rate`` is a fixed default
            (``services.fit.model.UNOBSERVED_RATE``).
        log_likelihood: Mean log-density of those samples (``None`` if 0).
        loo_log_likelihood: Mean leave-one-out (cross-validated) log-density.
        edges: Inner edges of the variable's states (equal-probability
            quantiles of the density) [unit], increasing.
    """

    name: str
    unit: str
    rate: float = Field(gt=0.0)
    samples: int = Field(ge=0)
    log_likelihood: float | None
    loo_log_likelihood: float | None
    edges: list[float] = Field(min_length=1)


class ArmLengths(Message):
    """The arm the variables were normalised for (NAO's, after retargeting).

    Attributes:
        upper_arm: Shoulder-to-elbow length L_u [m].
        forearm: Elbow-to-wrist length L_f [m].
    """

    upper_arm: float = Field(gt=0.0)
    forearm: float = Field(gt=0.0)


#: Least share of the gravity term's unbalance fitted weights must explain to
#: be planned with: below half, the fitted measure leaves more of the
#: postures unexplained than it explains (left-arm recordings read as a
#: right arm gave 0 %, wrongly mapped axes 1.2 %; the default set 70 %).
MIN_EXPLAINED = 0.5
#: Fewest regression equations fitted weights must rest on to be planned
#: with: 15 per weight (the default set has 3043, 16 reaches about 40).
MIN_EQUATIONS = 30


class FittedWeights(Message):
    """The IK measures' weights fitted to the demonstrations (``services.fit.weights``).

    Attributes:
        mu: Swivel spring stiffness mu [J/rad^2] (eq. 17).
        omega: Wrist discomfort weight omega [J/rad^2] (eq. 19), or ``None``
            if the demonstrations have no wrist roll (not fitted).
        samples: Regression equations (null directions over kept samples).
        explained: 1 - |residual| / |gravity term|: how far the weights
            account for the postures, 0..1.
    """

    mu: float = Field(ge=0.0, le=MOST)
    omega: float | None = Field(ge=0.0, le=MOST)
    samples: int = Field(ge=1)
    explained: float = Field(ge=0.0, le=1.0)

    @property
    def trusted(self) -> bool:
        """Whether to plan with them: ``MIN_EQUATIONS`` and ``MIN_EXPLAINED``.

        If not, the model keeps them (as evidence) and the IK uses the
        shipped weights (``MotionModel.measures``).
        """
        return self.samples >= MIN_EQUATIONS and self.explained >= MIN_EXPLAINED

    def untrusted(self) -> str:
        """Why they are not planned with, with the weights used instead; or ``""``."""
        if self.trusted:
            return ""
        shipped = MeasureParams()
        return (
            f"too little to plan with ({self.samples} equations, "
            f"{100 * self.explained:.1f} % explained; at least {MIN_EQUATIONS} and "
            f"{100 * MIN_EXPLAINED:.0f} % needed): plans keep "
            f"the shipped mu = {shipped.mu:g}, omega = {shipped.omega:g}"
        )


class MotionModel(Message):
    """The fitted motion model (densities, states and the network's tables).

    Attributes:
        version: File format version (``MODEL_VERSION``).
        arm: Arm lengths of the demonstrations after retargeting [m].
        sample_rate: Sample rate of the demonstrations [Hz], 1 to 10 000
            (motion capture runs at 50-1000 Hz); the transition table is per
            sample at this rate.
        bins: States per variable.
        smoothing: Pseudo-count added to every table cell.
        variables: The five variables' densities, in ``VARIABLES`` order.
        primitives: The primitives the demonstrations show (the network's M
            states), in ``MOTION_PRIMITIVES`` order.
        prior, start, transition, shoulder, elbow, wrist: The network's
            tables as counts (demonstration samples plus ``smoothing`` per
            cell, ``services.fit.conditionals``), nested lists; the
            probabilities are their normalised rows (``conditionals()``).
        subjects: Subjects fitted on.
        sources: Demonstration files fitted on.
        samples: Samples fitted on.
        weights: The IK measures' weights fitted on the same
            demonstrations, or ``None`` (a model fitted without them, or
            written before they were): the IK then uses the shipped weights,
            as it does for weights that are not ``trusted``.
    """

    version: int
    arm: ArmLengths
    sample_rate: float = Field(ge=MIN_SAMPLE_RATE, le=MAX_SAMPLE_RATE)
    bins: int = Field(ge=2, le=64)
    smoothing: float = Field(gt=0.0, le=MAX_SMOOTHING)
    variables: list[VariableFit] = Field(min_length=5, max_length=5)
    primitives: list[str] = Field(min_length=1, max_length=8)
    prior: Table
    start: Table
    transition: list[Table]
    shoulder: list[Table]
    elbow: list[list[list[Table]]]
    wrist: list[list[list[Table]]]
    subjects: list[str] = Field(default_factory=list)
    sources: list[str] = Field(default_factory=list)
    samples: int = Field(ge=1)
    weights: FittedWeights | None = None

    @model_validator(mode="after")
    def _consistent(self) -> MotionModel:
        if self.version != MODEL_VERSION:
            raise ValueError(
                f"version {self.version}; this armplan reads version {MODEL_VERSION}"
            )
        names = [v.name for v in self.variables]
        if names != list(VARIABLES):
            raise ValueError(f"variables must be {list(VARIABLES)}, got {names}")
        for v in self.variables:
            if len(v.edges) != self.bins - 1 or np.any(np.diff(v.edges) <= 0):
                raise ValueError(
                    f"{v.name}: needs {self.bins - 1} increasing edges, "
                    f"got {len(v.edges)}"
                )
        unknown = [p for p in self.primitives if p not in _MOTION_NAMES]
        if unknown or len(set(self.primitives)) != len(self.primitives):
            raise ValueError(
                f"primitives must be distinct motion primitives, got {self.primitives}"
            )
        m, k = len(self.primitives), self.bins
        shapes = {
            "prior": (m,),
            "start": (m,),
            "transition": (m, m),
            "shoulder": (m, k),
            "elbow": (m, k, k, k),
            "wrist": (m, k, k, k),
        }
        for name, shape in shapes.items():
            _check_counts(name, getattr(self, name), shape, CONDITIONED[name])
        return self

    def counts(self) -> Conditionals:
        """The tables' counts as numpy arrays."""
        return Conditionals(
            tuple(self.primitives),
            np.array(self.prior),
            np.array(self.start),
            np.array(self.transition),
            np.array(self.shoulder),
            np.array(self.elbow),
            np.array(self.wrist),
        )

    def conditionals(self) -> Conditionals:
        """The network's probability tables as numpy arrays."""
        return conditionals(self.counts())

    def measures(self) -> MeasureParams:
        """The IK measures' weights to plan with: the fitted ones over the shipped.

        Fitted weights that are not ``trusted`` (too few equations, too
        little explained) give the shipped ones.
        """
        if self.weights is None or not self.weights.trusted:
            return MeasureParams()
        fitted: dict[str, float] = {"mu": self.weights.mu}
        if self.weights.omega is not None:
            fitted["omega"] = self.weights.omega
        return MeasureParams(**fitted)

    def edges(self) -> list[list[float]]:
        """Each variable's state edges, in ``VARIABLES`` order."""
        return [list(v.edges) for v in self.variables]


def _check_counts(
    name: str, value: Any, shape: tuple[int, ...], conditioned: int
) -> None:
    """Raise ValueError unless ``value`` is a table of counts of ``shape``.

    A fitted table holds demonstration samples plus the smoothing in every
    cell (``services.fit.conditionals``), so every count is positive and
    finite, and so is every row's sum. A hand-edited table with one zero
    count, or counts of 1e308 whose sums overflow, once passed and made
    every decision NaN.
    """
    try:
        table = np.array(value, dtype=float)
    except ValueError:
        raise ValueError(f"{name}: ragged table, expected shape {shape}") from None
    if table.shape != shape:
        raise ValueError(f"{name}: shape {table.shape}, expected {shape}")
    bad = ~(np.isfinite(table) & (table > 0))
    if np.any(bad):
        at = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(
            f"{name}: count {table[at]:g} at {list(at)}; counts must be positive "
            "and finite (a fitted table holds its samples plus the smoothing in "
            "every cell)"
        )
    with np.errstate(over="ignore"):
        sums = table.sum(axis=tuple(range(conditioned, table.ndim)))
    if not np.all(np.isfinite(sums)):
        raise ValueError(
            f"{name}: counts too large: a row's sum overflows (largest count "
            f"{table.max():g})"
        )
