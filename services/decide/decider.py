"""The decision of eq. 10 at one moment, from precomputed tables (fast path).

At a path point the five motion variables fall into states z (``discretize``)
and the primitive before was m_prev. For every motion primitive m the
network (``services.fit.network``) gives

    P(m, z) = P(m | m_prev) P(s_r | m) P(e_p, e_r | s_r, m) P(w_p, w_r | e_r, m)

and the primitive's g is the transient mutual information of the primitive
node and the arm's state (eq. 5 with X = M, Y = Z):

    g_m = P(m, z) log[ P(m, z) / (P(m) P(z)) ],   P(m) = P(m | m_prev).

Its logarithm splits along the network into the AMI's terms: serial from
shoulder to elbow to wrist (eq. 7), each node's two attributes together
given the nodes before (the TCMI of eq. 6 in the parallel form of eq. 8);
``accumulate`` computes them one by one and the tests check that they add
up to this g. The largest g wins (eq. 10). Primitives the demonstrations
never show have no tables: their g is 0 and they are not candidates.

Without a wanted palm direction W_R is not observed: the wrist's table is
summed over it. Everything here is plain Python on nested lists, built once
per model: a decision costs a few microseconds.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from services.fit.model import MotionModel
from shared.errors import InvalidInputError
from shared.primitives import MOTION_PRIMITIVES

#: Deciders for other steps than the model's kept by ``Decider.with_step``.
KEPT_STEPS = 8
#: The candidates of eq. 10, in the paper's order.
CANDIDATES: tuple[str, ...] = tuple(p.name for p in MOTION_PRIMITIVES)


class Choice(NamedTuple):
    """The decision at one moment.

    Attributes:
        candidate: The winner, index into ``CANDIDATES``.
        state: The winner, index into the model's primitives (the M node).
        g: g of every candidate, in ``CANDIDATES`` order [nat].
    """

    candidate: int
    state: int
    g: tuple[float, ...]

    @property
    def name(self) -> str:
        """The winner's name, e.g. ``"S_R E_P W_P"``."""
        return CANDIDATES[self.candidate]


def _log(values: np.ndarray, name: str) -> list[Any]:
    """Natural log as nested lists, with the primitive axis last."""
    return list(_finite_log(np.moveaxis(values, 0, -1), name).tolist())


def _finite_log(values: np.ndarray, name: str) -> np.ndarray:
    """Natural log of the probabilities ``values`` of table ``name``, all finite.

    Raises:
        InvalidInputError: (field ``model``) if a probability is 0 (a count
            too small beside its row's sum) or not finite, which would make
            every g there NaN.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        logs = np.log(values)
    if not np.all(np.isfinite(logs)):
        raise InvalidInputError(
            f"the motion model cannot decide: its {name} table holds a "
            f"probability of {float(values[~np.isfinite(logs)][0]):g}; every "
            "probability must be positive (refit with a larger smoothing)",
            field="model",
            table=name,
        )
    return logs


def transition_for(transition: np.ndarray, ratio: float) -> np.ndarray:
    """The per-sample transition table for a step ``ratio`` samples long.

    Whole samples by matrix powers, the fraction by a linear step towards it
    (exact for ratio integer): T^floor(r) (I + (r - floor(r)) (T - I)).
    """
    whole = math.floor(ratio)
    power = np.linalg.matrix_power(transition, whole)
    part = np.eye(len(transition)) + (ratio - whole) * (
        transition - np.eye(len(transition))
    )
    return power @ part


class Decider:
    """A motion model compiled for fast decisions at path points.

    Args:
        model: The fitted motion model.
        step: Time between two decisions [s]; the transition table is scaled
            to it. Default: the demonstrations' sample interval.
        like: A decider of the same model whose step-free tables (all but
            the transition table) this one shares instead of building its own.

    Raises:
        InvalidInputError: (field ``model``) if a table's probability is 0
            or not finite (a model fitted with a smoothing of 5e-324); its
            decisions would all be NaN.
    """

    def __init__(
        self,
        model: MotionModel,
        step: float | None = None,
        like: Decider | None = None,
    ) -> None:
        self.model = model
        self.primitives = tuple(model.primitives)
        self.candidate: list[int] = [CANDIDATES.index(n) for n in self.primitives]
        tables = model.conditionals()
        self.edges: list[list[float]] = model.edges()
        self.step = 1.0 / model.sample_rate if step is None else float(step)
        moved = transition_for(tables.transition, self.step * model.sample_rate)
        self.log_next: list[list[float]] = _finite_log(moved, "transition").tolist()
        self._steps: dict[float, Decider] = {}
        if like is not None:  # the same tables: share them (about 100 000 floats)
            self.log_start: list[float] = like.log_start
            self.shoulder: list[list[float]] = like.shoulder
            self.elbow: list[list[list[list[float]]]] = like.elbow
            self.wrist: list[list[list[list[float]]]] = like.wrist
            self.wrist_any: list[list[list[float]]] = like.wrist_any
            return
        # Typed nested lists, indexed [state]...[primitive] (shoulder [s_r],
        # elbow [s_r][e_p][e_r], wrist [e_r][w_p][w_r]): compiled, their
        # entries are read and added as machine floats, not Python objects.
        self.log_start = _finite_log(tables.start, "start").tolist()
        self.shoulder = _log(tables.shoulder, "shoulder")
        self.elbow = _log(tables.elbow, "elbow")
        self.wrist = _log(tables.wrist, "wrist")
        self.wrist_any = _log(tables.wrist.sum(axis=3), "wrist")

    def with_step(self, step: float) -> Decider:
        """The same model for decisions ``step`` seconds apart [s].

        Each step's decider is kept for the next path at that step, the
        ``KEPT_STEPS`` most recently used: a path's step is its times'
        median interval, so callers with jittery clocks ask for a new one
        nearly every time (each kept one held 4 MB before they shared their
        tables, and they were never dropped).
        """
        key = round(float(step), 12)
        found = self._steps.pop(key, None)
        if found is None:
            found = Decider(self.model, step, self)
        self._steps[key] = found  # the most recently used last
        while len(self._steps) > KEPT_STEPS:
            del self._steps[next(iter(self._steps))]
        return found

    def states(self, values: tuple[float, ...]) -> tuple[int, int, int, int, int]:
        """The states of the five variables' values."""
        e = self.edges
        return (
            _bisect_right(e[0], values[0]),
            _bisect_right(e[1], values[1]),
            _bisect_right(e[2], values[2]),
            _bisect_right(e[3], values[3]),
            _bisect_right(e[4], values[4]),
        )

    def decide(
        self,
        values: tuple[float, ...],
        oriented: bool,
        previous: int | None = None,
    ) -> Choice:
        """The winner and every g for the variables' ``values``.

        Args:
            values: (S_R, E_P, E_R, W_P, W_R) at this moment.
            oriented: Whether W_R is observed (a palm direction is wanted).
            previous: The primitive decided at the point before, as an index
                into the model's primitives (``Choice.state``); ``None`` at a
                movement's start.

        Raises:
            InvalidInputError: (field ``model``) if a g is not finite: a
                typed error, never a NaN handed on to a message.
        """
        s, ep, er, wp, wr = self.states(values)
        prior = self.log_start if previous is None else self.log_next[previous]
        shoulder, elbow = self.shoulder[s], self.elbow[s][ep][er]
        wrist = self.wrist[er][wp][wr] if oriented else self.wrist_any[er][wp]
        joint = [
            prior[m] + shoulder[m] + elbow[m] + wrist[m] for m in range(len(prior))
        ]
        top = joint[0]
        for v in joint:
            top = max(top, v)
        total = 0.0  # in order, as sum() adds floats
        for v in joint:
            total += math.exp(v - top)
        evidence = top + math.log(total)
        g = [0.0] * len(CANDIDATES)
        best, best_g, every = 0, -math.inf, 0.0
        for m, log_p in enumerate(joint):
            value = math.exp(log_p) * (log_p - prior[m] - evidence)
            g[self.candidate[m]] = value
            every += value  # NaN or inf in any g stays in the sum
            if value > best_g:
                best, best_g = m, value
        if not math.isfinite(every):
            raise InvalidInputError(
                f"the motion model gave no finite g at states {[s, ep, er, wp, wr]} "
                f"(g = {[round(v, 6) for v in g]}): its tables cannot be decided with",
                field="model",
                states=[s, ep, er, wp, wr],
            )
        return Choice(self.candidate[best], best, tuple(g))


def _bisect_right(edges: list[float], value: float) -> int:
    """``bisect.bisect_right`` on floats, compiled (no Python objects per call)."""
    lo, hi = 0, len(edges)
    while lo < hi:
        mid = (lo + hi) // 2
        if value < edges[mid]:
            hi = mid
        else:
            lo = mid + 1
    return lo
