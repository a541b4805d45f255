"""Numbers of the pace experiment: how the ratios to human pace spread.

``summary`` is the JSON of ``armplan experiment pace``: per method and kind
of task (``reaches``, ``chains``) how many were planned and refused, the
median, mean and largest ratio of the trajectory's duration to the human
one (1 is human pace), how many took over ``SLOW`` times, how many of those
brought a joint near a limit and how many (of the others) were short (the
human law asking under ``SHORT``: a hand that moves little, its joints
perhaps much), every ratio, and the refusals' messages.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from armplan.experiments.pace import PaceRun

#: A task slower than this many times the human duration counts as slow [-].
SLOW = 1.5
#: A task the human law gives less than this is short [s] (its floor is 0.3 s).
SHORT = 0.4
#: The kinds of task, in the order of the tables.
KINDS = {"reach": "reaches", "chain": "chains"}


def kind_summary(runs: Sequence[PaceRun]) -> dict[str, Any]:
    """The numbers of one method's tasks of one kind (see the module docstring)."""
    ratios = [r.ratio for r in runs if r.ratio is not None]
    slow = [r for r in runs if r.ratio is not None and r.ratio > SLOW]
    return {
        "tasks": len(runs),
        "planned": len(ratios),
        "refused": len(runs) - len(ratios),
        "median_ratio": float(np.median(ratios)) if ratios else None,
        "mean_ratio": float(np.mean(ratios)) if ratios else None,
        "max_ratio": float(np.max(ratios)) if ratios else None,
        "slow": len(slow),
        "slow_near_limit": sum(r.near_limit for r in slow),
        "slow_short": sum(
            not r.near_limit and r.asked is not None and r.asked < SHORT for r in slow
        ),
        "ratios": ratios,
        "errors": [r.error for r in runs if r.error is not None],
    }


def summary(
    runs: Mapping[str, Sequence[PaceRun]], protocol: dict[str, Any]
) -> dict[str, Any]:
    """The experiment's JSON: ``runs`` maps each method's name to its runs."""
    out: dict[str, Any] = {
        "protocol": {**protocol, "slow_above": SLOW, "short_below_s": SHORT}
    }
    for method, mine in runs.items():
        out[method] = {
            name: kind_summary([r for r in mine if r.task.kind == kind])
            for kind, name in KINDS.items()
        }
    return out
