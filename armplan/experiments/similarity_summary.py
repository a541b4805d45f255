"""Numbers of the similarity experiment: per method, per point, per primitive count.

All errors in metres. ``summary`` is the JSON of ``armplan experiment
similarity``: for each method its mean elbow error over all reaches (one
reach = one subject at one point, its trials averaged), their standard
deviation, the mean per point (Fig. 15) and the mean by the number of
primitives NAO's ``mp`` reach used (the paper's three/two/one-MP groups);
plus how each bar of the SPEC fares. With a palm (``--palm``) each method
also has its mean posture similarity S (eq. 22-23) and its standard
deviation, and the bars include S above each baseline's.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from armplan.experiments.similarity import ReachError
from armplan.experiments.subject_reach import point_label
from shared.messages import Method

#: The SPEC's bar: mean elbow error on NAO below this [m].
ELBOW_BAR = 0.01


def errors_by_point(
    rows: Sequence[ReachError], method: Method
) -> dict[int, list[float]]:
    """Each point's elbow errors (one per subject) of ``method`` [m]."""
    out: dict[int, list[float]] = defaultdict(list)
    for row in rows:
        if row.method is method:
            out[row.point].append(row.elbow_error)
    return dict(sorted(out.items()))


def method_summary(rows: Sequence[ReachError], method: Method) -> dict[str, Any]:
    """The numbers of one method (see the module docstring)."""
    mine = [r for r in rows if r.method is method]
    elbow = np.array([r.elbow_error for r in mine])
    return {
        **_posture(mine),
        "reaches": len(mine),
        "mean_elbow_error_m": float(elbow.mean()),
        "sd_elbow_error_m": float(elbow.std()),
        "max_elbow_error_m": float(elbow.max()),
        "mean_wrist_error_m": float(np.mean([r.wrist_error for r in mine])),
        "per_point_mean_elbow_error_m": {
            point_label(p): float(np.mean(e))
            for p, e in errors_by_point(rows, method).items()
        },
    }


def _posture(rows: Sequence[ReachError]) -> dict[str, float]:
    """Mean and sd of the rows' posture similarity, if they have one."""
    values = [r.posture_similarity for r in rows if r.posture_similarity is not None]
    if not values:
        return {}
    return {
        "mean_posture_similarity": float(np.mean(values)),
        "sd_posture_similarity": float(np.std(values)),
    }


#: The group of reaches whose count is not known (unlabelled demonstrations).
UNKNOWN = "unknown"


def by_count(
    rows: Sequence[ReachError], count: Callable[[ReachError], int | None]
) -> dict[str, dict[str, float]]:
    """Mean elbow error per method, grouped by ``count`` of the mp reach.

    Each reach falls in the group of ``count`` of its ``mp`` row;
    every method's error there is averaged, so the groups compare methods on
    the same reaches. Keys: the count as text, ``UNKNOWN`` (last) where
    ``count`` is None; values: ``{"reaches": n, method: mean error [m], ...}``.
    """
    group = {r.reach: count(r) for r in rows if r.method is Method.MP}
    sums: dict[int | None, dict[str, list[float]]] = defaultdict(
        lambda: defaultdict(list)
    )
    for row in rows:
        if row.reach in group:
            sums[group[row.reach]][row.method.value].append(row.elbow_error)
    order = sorted(sums, key=lambda k: (k is None, k or 0))
    return {
        UNKNOWN if k is None else str(k): {
            "reaches": len(sums[k]["mp"]),
            **{m: float(np.mean(e)) for m, e in sums[k].items()},
        }
        for k in order
    }


def _human_count(row: ReachError) -> int | None:
    """How many primitives the subject's reach used; None if unlabelled."""
    return len(row.human_primitives) if row.human_primitives else None


def summary(rows: Sequence[ReachError], protocol: dict[str, Any]) -> dict[str, Any]:
    """The experiment's JSON (see the module docstring)."""
    methods = sorted({r.method for r in rows}, key=list(Method).index)
    out: dict[str, Any] = {"protocol": protocol}
    for method in methods:
        out[method.value] = method_summary(rows, method)
    out["by_mp_primitive_count"] = by_count(rows, lambda r: len(r.primitives))
    out["by_human_primitive_count"] = by_count(rows, _human_count)
    out["bars"] = bars(out, methods)
    return out


def bars(out: dict[str, Any], methods: Sequence[Method]) -> dict[str, Any]:
    """The SPEC's bars on these numbers: each with the measured margin [m]."""
    if Method.MP not in methods:
        return {}
    mp = out[Method.MP.value]["mean_elbow_error_m"]
    result: dict[str, Any] = {
        "below_1cm": {"met": mp < ELBOW_BAR, "margin_m": ELBOW_BAR - mp}
    }
    for method in methods:
        if method is not Method.MP:
            other = out[method.value]["mean_elbow_error_m"]
            result[f"below_{method.value}"] = {
                "met": mp < other,
                "margin_m": other - mp,
            }
    s_mp = out[Method.MP.value].get(POSTURE)
    if s_mp is None:
        return result
    for method in methods:
        if method is not Method.MP:
            other = out[method.value][POSTURE]
            result[f"posture_above_{method.value}"] = {
                "met": s_mp > other,
                "margin": s_mp - other,
            }
    return result


#: The summary's key of a method's mean posture similarity.
POSTURE = "mean_posture_similarity"
