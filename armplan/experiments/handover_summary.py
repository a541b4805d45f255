"""Numbers of the handover experiment: posture similarity per method.

``summary`` is the JSON of ``armplan experiment handover``: for each method
the mean of S over the task's samples (each sample a 1/100 s of the
person's time), its standard deviation and minimum, the mean per movement,
and the primitives that moved NAO's arm in each movement; plus how the
SPEC's bar (the method's S above both baselines') fares.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from armplan.experiments.handover import SimilaritySeries
from armplan.experiments.human_reference import ReferenceMovement
from shared.messages import Method


def method_summary(
    series: SimilaritySeries, reference: Sequence[ReferenceMovement]
) -> dict[str, Any]:
    """The numbers of one method (see the module docstring)."""
    s = series.similarity
    return {
        "samples": len(s),
        "mean_similarity": float(s.mean()),
        "sd_similarity": float(s.std()),
        "min_similarity": float(s.min()),
        "per_movement_mean_similarity": [
            {
                "movement": move.name,
                "mean_similarity": float(s[series.movement == k].mean()),
            }
            for k, move in enumerate(reference)
        ],
        "primitives": series.primitives,
    }


def summary(
    reference: Sequence[ReferenceMovement],
    series: Sequence[SimilaritySeries],
    protocol: dict[str, Any],
) -> dict[str, Any]:
    """The experiment's JSON (see the module docstring)."""
    out: dict[str, Any] = {"protocol": protocol}
    for one in series:
        out[one.method.value] = method_summary(one, reference)
    out["bars"] = bars(out)
    return out


def bars(out: dict[str, Any]) -> dict[str, Any]:
    """The method's mean S above each baseline's, with the margin [-]."""
    if Method.MP.value not in out:
        return {}
    mine = out[Method.MP.value]["mean_similarity"]
    return {
        f"above_{m.value}": {
            "met": mine > out[m.value]["mean_similarity"],
            "margin": mine - out[m.value]["mean_similarity"],
        }
        for m in (Method.LEAST_NORM, Method.SINGLE)
        if m.value in out
    }


def movement_table(
    reference: Sequence[ReferenceMovement], series: Sequence[SimilaritySeries]
) -> list[list[Any]]:
    """Rows: movement, duration [s], then each method's mean S there."""
    rows = []
    for k, move in enumerate(reference):
        means = [float(np.mean(s.similarity[s.movement == k])) for s in series]
        rows.append([move.name, float(move.times[-1]), *means])
    return rows
