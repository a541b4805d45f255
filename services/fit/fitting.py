"""Fitting the motion model to demonstrations.

For every trial: its labels (the generator's, or ``labelling`` for recorded
data) and its five motion variables (``demo_variables``). Then, per
variable, the exponential density (rate by maximum likelihood, checked by
leave-one-out cross-validation) and its equal-probability states; then
the network's tables (``conditionals``), counted over all samples; finally
the IK measures' weights mu and omega, by regression on the same postures
(``weights``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from services.fit.conditionals import count_tables
from services.fit.demo_variables import trial_variables
from services.fit.discretize import bin_edges, bin_indices
from services.fit.exponential import MIN_NONZERO, ExponentialFit, fit_exponential
from services.fit.labelling import infer_labels
from services.fit.model import (
    MODEL_VERSION,
    UNITS,
    UNOBSERVED_RATE,
    ArmLengths,
    MotionModel,
    VariableFit,
    rounded,
)
from services.fit.variables import E_P, E_R, S_R, VARIABLES, W_P, W_R
from services.fit.weights import fit_weights
from shared.demos.reach_span import not_a_reach_problem
from shared.demos.retarget import nao_arm_size
from shared.demos.sample_rate import check_one_rate, check_seconds
from shared.demos.trial import DemoSet
from shared.errors import InvalidInputError, TooFewSamplesError
from shared.messages.motion_model import MAX_SMOOTHING
from shared.primitives import MOTION_PRIMITIVES

#: States per variable.
BINS = 20
#: Pseudo-count in every table cell.
SMOOTHING = 1.0
#: Fewest and most states per variable (as ``FitRequest.bins`` allows).
MIN_BINS, MAX_BINS = 2, 64
#: Fewest samples, over all trials, that are not their trial's last. A trial
#: ends at its goal (a sample's ``target`` is the wrist's position at the
#: reach's end; the roll's goal is the last wrist frame), so its last
#: sample's variables are 0, up to rounding, and add nothing to a rate's sum.
#: Leave-one-out cross-validation fits each rate without one sample: with one
#: sample before the trials' ends, leaving it out leaves only zeros (or
#: rounding noise), an infinite rate, and log-likelihoods near -1e307. Two is
#: the fewest for which every leave-one-out fit keeps a sample that moves: a
#: floor for the model's numbers to be defined, not a size for a good model.
MIN_MOVING = 2
#: Fewest trials (reaches) fitted on: one reach to each of the paper's 16
#: board points (Section V.A; ``armplan demos synth --subjects 1 --trials
#: 1``), the smallest set that shows the arm's habits across the workspace.
#: The network's transition table counts how primitives follow each other
#: within reaches, and a handful of reaches shows a handful of sequences: a
#: one-trial, 30 ms recording once gave a one-primitive model that every
#: running plan then used; so did 16 two-frame trials, which is why every
#: trial counted must be a reach (``_check_reaches``).
MIN_TRIALS = 16
#: A motion variable moves in a sample when it is farther than this from
#: its goal [rad or arm lengths]: the onset threshold of the demonstrations'
#: labels (``shared.demos.reach_model.SETTLED``), above marker noise.
MOVES = 0.025
#: The variables every reach moves (W_R may be unobserved): each must move in
#: at least ``MIN_MOVING`` samples, or its rate only measures rounding (an
#: elbow-only recording gave S_R a rate of 1e11 /rad).
MUST_MOVE = (S_R, E_P, E_R, W_P)

#: Called with (steps done, steps in all): one step per trial for the
#: variables, one per trial for the weights.
Progress = Callable[[int, int], None]


def fit_model(
    demos: DemoSet,
    *,
    bins: int = BINS,
    smoothing: float = SMOOTHING,
    sources: Sequence[str] = (),
    progress: Progress | None = None,
) -> MotionModel:
    """The motion model of ``demos``.

    Args:
        demos: Retargeted demonstrations (at least one trial).
        bins: States per variable (2..64).
        smoothing: Pseudo-count added to every table cell (> 0).
        sources: Names of the files the demonstrations came from.
        progress: Told after each trial's variables, then its weights' rows.

    Raises:
        InvalidInputError: if there are no trials, the options are out of
            range, the times are not in seconds (``check_seconds``, before
            any fitting) or at several sample rates (``check_one_rate``), a
            trial is no reach (``not_a_reach_problem``: naming its file,
            subject and trial), or a variable cannot be fitted (e.g. all
            zero: naming the trials).
        TooFewSamplesError: with fewer than ``MIN_TRIALS`` trials or
            ``MIN_MOVING`` samples before their trials' ends (before any
            fitting), or a variable of ``MUST_MOVE`` that moves in fewer
            than ``MIN_MOVING`` samples (naming it).
    """
    if not demos.trials:
        raise InvalidInputError("no demonstrations to fit", field="demos")
    check_options(bins, smoothing)
    _check_enough(demos)
    rate = check_seconds([t.times for t in demos.trials], "the demonstrations")
    check_one_rate(demos.trials)
    _check_reaches(demos)
    size = nao_arm_size(demos.trials[0].arm)
    values, names, first, oriented = [], [], [], []
    for done, trial in enumerate(demos.trials, start=1):
        n = len(trial.times)
        values.append(trial_variables(trial, size.upper_arm, size.forearm))
        names.extend(trial.labels if trial.labels is not None else infer_labels(trial))
        first.extend([True] + [False] * (n - 1))
        oriented.extend([trial.wrist_frame is not None] * n)
        if progress is not None:
            progress(done, 2 * len(demos.trials))
    data, seen = np.vstack(values), np.array(oriented)
    _check_moving(data, demos)
    fits = [_fit(data, seen, i) for i in range(len(VARIABLES))]
    edges = [bin_edges(fit.rate, bins) for fit in fits]
    states = np.stack([bin_indices(data[:, i], e) for i, e in enumerate(edges)], 1)
    states[~seen, W_R] = -1
    shown = tuple(p.name for p in MOTION_PRIMITIVES if p.name in set(names))
    labels = np.array([shown.index(name) for name in names])
    tables = count_tables(states, labels, np.array(first), shown, bins, smoothing)
    count = len(demos.trials)
    weights = fit_weights(
        demos,
        progress=None
        if progress is None
        else lambda done, _: progress(count + done, 2 * count),
    )
    return MotionModel(
        version=MODEL_VERSION,
        arm=ArmLengths(upper_arm=size.upper_arm, forearm=size.forearm),
        sample_rate=rate,
        bins=bins,
        smoothing=smoothing,
        variables=[
            _variable(i, fit, e)
            for i, (fit, e) in enumerate(zip(fits, edges, strict=True))
        ],
        primitives=list(shown),
        prior=rounded(tables.prior),
        start=rounded(tables.start),
        transition=rounded(tables.transition),
        shoulder=rounded(tables.shoulder),
        elbow=rounded(tables.elbow),
        wrist=rounded(tables.wrist),
        subjects=sorted({t.subject for t in demos.trials}),
        sources=list(sources),
        samples=len(data),
        weights=weights,
    )


def check_options(bins: int, smoothing: float) -> None:
    """Refuse a fit's options out of range, before any demonstration is read.

    ``armplan fit`` calls it first: the full synthetic set took 10 s to read
    before ``--bins 1`` was refused, and ``--remote`` raised pydantic's
    ValidationError (a traceback) building the request.

    Args:
        bins: States per variable (``MIN_BINS``..``MAX_BINS``).
        smoothing: Pseudo-count per table cell, in (0, ``MAX_SMOOTHING``].

    Raises:
        InvalidInputError: naming the option (field ``bins`` or ``smoothing``).
    """
    if not MIN_BINS <= bins <= MAX_BINS:
        raise InvalidInputError(
            f"bins must be {MIN_BINS}..{MAX_BINS}, got {bins}", field="bins"
        )
    if not 0.0 < smoothing <= MAX_SMOOTHING:  # NaN too
        raise InvalidInputError(
            f"smoothing must be in (0, {MAX_SMOOTHING:g}], got {smoothing}",
            field="smoothing",
        )


def _check_enough(demos: DemoSet) -> None:
    """Refuse fewer than ``MIN_TRIALS`` trials or ``MIN_MOVING`` moving samples.

    Raises:
        TooFewSamplesError: naming the samples, the trials, how many are
            before their trial's end and how many are needed.
    """
    samples, trials = demos.samples, len(demos.trials)
    moving = samples - trials
    if moving < MIN_MOVING:
        raise TooFewSamplesError(
            f"{samples} sample{'' if samples == 1 else 's'} in {trials} "
            f"trial{'' if trials == 1 else 's'} are too few to fit: a fit needs "
            f"at least {MIN_MOVING} samples that are not their trial's last, "
            f"{moving} here (a trial's last sample is at its goal, where every "
            "motion variable is 0, and leave-one-out cross-validation must keep "
            "one that moves to fit each rate on)",
            field="demos",
            found=moving,
            needed=MIN_MOVING,
        )
    if trials < MIN_TRIALS:
        raise TooFewSamplesError(
            f"{trials} trial{' is' if trials == 1 else 's are'} too few to fit "
            f"({samples} samples): a fit needs at least {MIN_TRIALS} reaches (one to "
            "each of the paper's 16 board points), or its tables rest on a "
            "handful of primitive sequences",
            field="demos",
            found=trials,
            needed=MIN_TRIALS,
        )


def _check_reaches(demos: DemoSet) -> None:
    """Refuse a trial that is no reach (``not_a_reach_problem``).

    Every trial counts towards ``MIN_TRIALS`` and every sample is fitted as
    part of a reach: a still take beside reaches doubled every rate, and 16
    two-frame trials passed the count and gave a one-primitive model.

    Raises:
        InvalidInputError: naming the file, the subject and the trial.
    """
    for trial in demos.trials:
        problem = not_a_reach_problem(trial)
        if problem is None:
            continue
        where = f"{trial.source}: " if trial.source else ""
        raise InvalidInputError(
            f"{where}{problem}. armplan fit counts only reaches, each from its "
            "start to its goal (its last sample), and fits every sample of a "
            "trial as reaching: leave this one out",
            field="demos",
            source=trial.source,
            subject=trial.subject,
            trial=trial.trial,
        )


def _check_moving(data: np.ndarray, demos: DemoSet) -> None:
    """Refuse demonstrations in which a variable of ``MUST_MOVE`` stays still.

    ``data``: the samples' variables, shape (n, 5). Every variable is 0 at a
    trial's goal, so a part of the arm that stays as it is at the goal (the
    shoulder and upper arm of an elbow-only recording; a still trial is
    refused before, by ``_check_reaches``) moves none: a variable no sample
    moves that far names the demonstrations' files.

    Raises:
        TooFewSamplesError: naming each such variable and its moving samples.
    """
    counts = {i: int(np.count_nonzero(data[:, i] > MOVES)) for i in MUST_MOVE}
    still = {i: n for i, n in counts.items() if n < MIN_MOVING}
    if not still:
        return
    named = ", ".join(f"{VARIABLES[i]} in {n}" for i, n in still.items())
    message = (
        f"the demonstrations do not move every part of the arm: {named} of "
        f"{len(data)} samples moves by more than {MOVES:g} (rad or arm lengths) "
        f"from its goal, and a fit needs at least {MIN_MOVING} for each of "
        f"{', '.join(VARIABLES[i] for i in MUST_MOVE)}; a variable that never "
        "moves gets a rate that only measures rounding"
    )
    never = [VARIABLES[i] for i, n in still.items() if n == 0]
    if never:
        files = sorted({t.source for t in demos.trials if t.source})
        where = f" in {', '.join(files)}" if files else ""
        message += (
            f". No sample of the {len(demos.trials)} trials{where} moves "
            f"{' or '.join(never)} that far: each trial must be one "
            "reach, from its start to its goal (its last sample); a trial "
            "still at its goal throughout changes nothing: check that it holds "
            "the reach"
        )
    raise TooFewSamplesError(
        message, field="demos", found=min(still.values()), needed=MIN_MOVING
    )


def _fit(data: np.ndarray, seen: np.ndarray, index: int) -> ExponentialFit:
    """The variable's density; W_R only from samples that observe it.

    W_R is unobserved (a fixed rate) unless ``MIN_NONZERO`` samples show a
    roll: recordings without a thumb marker, or a roll that never changes.
    """
    if index != W_R:
        return fit_exponential(data[:, index], VARIABLES[index])
    if np.count_nonzero(data[seen, W_R] > 0) < MIN_NONZERO:
        return ExponentialFit(UNOBSERVED_RATE, 0, math.nan, math.nan)
    return fit_exponential(data[seen, W_R], VARIABLES[W_R])


def _variable(index: int, fit: ExponentialFit, edges: np.ndarray) -> VariableFit:
    return VariableFit(
        name=VARIABLES[index],
        unit=UNITS[index],
        rate=fit.rate,
        samples=fit.samples,
        log_likelihood=None if fit.samples == 0 else fit.log_likelihood,
        loo_log_likelihood=None if fit.samples == 0 else fit.loo_log_likelihood,
        edges=rounded(edges, 12),
    )
