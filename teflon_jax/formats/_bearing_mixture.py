"""A mixture of bearings of different compositions: what the evidence of a test record says
about which parts (effects) the bearing has, and about their constants.

`diagnose` fits several compositions of effects to one record (the baseline, every candidate
of every round). They differ in their parts (one has breakaway, another heating), so their
bearings cannot be draws of one posterior. A `BearingMixture` holds C of them, each a
`MixtureComposition`: its effects, its weight w_c, its point bearing and a `BearingPosterior`
of its constants' draws. The weights of the criterion `"bic"` are the Schwarz (1978)
approximation of the compositions' posterior probabilities under equal prior odds
(Kass & Raftery 1995; Burnham & Anderson 2002, Sec. 6.4):

    w_c = exp(-dBIC_c / 2) / sum_j exp(-dBIC_j / 2),   dBIC_c = BIC_c - min_j BIC_j.

A Monte Carlo draws from the mixture by giving each composition a share of the motions in
proportion to its weight (`motion_counts`: systematic sampling, unbiased, each count the
floor or the ceiling of N w_c) and running, on those motions, that composition's draws.
SI units.
"""

import dataclasses
import math

import numpy as np

from ..bearing import SlidingBearing
from ._bearing_posterior import BearingPosterior

MIXTURE_CRITERIA = {
    "bic": "w_c = exp(-dBIC_c / 2) / sum_j exp(-dBIC_j / 2), dBIC_c = BIC_c - min_j BIC_j "
           "(Schwarz 1978; Kass & Raftery 1995)",
}
"""The criteria a mixture's weights can come from, with their formula."""

WEIGHT_SUM_TOLERANCE = 1e-9
"""How far the weights' sum may be from 1 (rounding of the written decimals)."""

BIC_WEIGHT_RTOL = 1e-6
"""How far a `"bic"` mixture's weight ratios may be from exp(-(dBIC_c - dBIC_j) / 2)."""


MIXTURE_KEYS = {"criterion": str, "min_weight": float, "compositions": list, "left_out": list}
"""The keys of a bearing file's `mixture` object, with the type of each value."""

COMPOSITION_KEYS = {"effects": list, "weight": float, "delta_bic": float, "parts": dict,
                    "posterior": dict, "note": str}
"""The keys of each of its `compositions`, with the type of each value."""


def object_keys(entry, keys: dict, at) -> None:
    """`ValueError` at `at` for an entry that is not an object of exactly `keys`, or whose
    lists are not lists (the other values are checked where they are read)."""
    if not isinstance(entry, dict) or set(entry) != set(keys):
        found = sorted(entry) if isinstance(entry, dict) else type(entry).__name__
        raise ValueError(f"{at}: must be an object with the keys {', '.join(keys)}; got {found}.")
    for key, kind in keys.items():
        if kind is list and not isinstance(entry[key], list):
            raise ValueError(f"{at}.{key}: must be a list, got {entry[key]!r}.")


def _effects(effects, where):
    if isinstance(effects, str) or not isinstance(effects, list | tuple):
        raise ValueError(f"{where}: must be a list of effect names (empty for the baseline "
                         f"alone), got {effects!r}.")
    if not all(isinstance(e, str) and e for e in effects):
        raise ValueError(f"{where}: every effect is a name, got {list(effects)!r}.")
    if len(set(effects)) != len(effects):
        raise ValueError(f"{where}: an effect is listed twice in {list(effects)}.")
    return tuple(effects)


def _number(value, where, *, low, high, closed_low=True):
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise ValueError(f"{where}: must be a number, got {value!r}.")
    value = float(value)
    inside = (value >= low if closed_low else value > low) and value <= high
    if not (math.isfinite(value) and inside):
        bounds = f"{'[' if closed_low else '('}{low:g}, {high:g}]"
        raise ValueError(f"{where}: must be a finite number in {bounds}, got {value}.")
    return value


@dataclasses.dataclass(frozen=True, eq=False)
class MixtureComposition:
    """One composition of a `BearingMixture` (a bad field is refused with a `ValueError` naming it).

    **Fields:** `effects` (names, as the search gives them; empty for the baseline alone),
    `weight` w_c in (0, 1], `bearing` its point estimate (`SlidingBearing`), `posterior` the
    draws of its constants (`BearingPosterior`: a composition without draws is refused),
    `delta_bic` its BIC above the lowest (>= 0; `None` where the criterion has none),
    `standard_errors` (part, constant) -> standard error [SI] of the point estimate, `note`
    free text (e.g. which constants are held at the point)."""

    effects: tuple
    weight: float
    bearing: SlidingBearing
    posterior: BearingPosterior
    delta_bic: float | None = None
    standard_errors: dict = dataclasses.field(default_factory=dict)
    note: str = ""

    def __post_init__(self):
        object.__setattr__(self, "effects", _effects(self.effects, "effects"))
        object.__setattr__(self, "weight", _number(self.weight, "weight", low=0.0, high=1.0,
                                                   closed_low=False))
        if self.delta_bic is not None:
            object.__setattr__(self, "delta_bic", _number(self.delta_bic, "delta_bic", low=0.0,
                                                          high=math.inf))
        if not isinstance(self.bearing, SlidingBearing):
            raise ValueError(f"parts: must be a SlidingBearing, got {type(self.bearing).__name__}.")
        if not isinstance(self.posterior, BearingPosterior):
            raise ValueError("posterior: every composition carries draws of its constants "
                             "(a BearingPosterior); got "
                             f"{'none' if self.posterior is None else type(self.posterior).__name__}.")

    @property
    def label(self) -> str:
        """The effects joined by '+' ('baseline' for none)."""
        return "+".join(self.effects) or "baseline"


@dataclasses.dataclass(frozen=True, eq=False)
class BearingMixture:
    """Bearings of C compositions with their weights (module docstring), checked when made.

    **Fields:** `compositions` (`MixtureComposition`s, at least one, distinct effect sets,
    weights summing to 1 within `WEIGHT_SUM_TOLERANCE`), `criterion` (a key of
    `MIXTURE_CRITERIA`; for `"bic"` every composition has `delta_bic` and the weights follow
    from them within `BIC_WEIGHT_RTOL`), `left_out` the compositions not kept (a list of
    objects with `effects` and `weight`, their weights before the kept ones were normalised) and
    `min_weight` the weight below which a composition was left out (0: none was)."""

    compositions: tuple
    criterion: str = "bic"
    left_out: tuple = ()
    min_weight: float = 0.0

    def __post_init__(self):
        compositions = tuple(self.compositions)
        if not compositions or not all(isinstance(c, MixtureComposition) for c in compositions):
            raise ValueError("mixture.compositions: give one or more compositions (each its effects, "
                             "weight, parts and posterior draws).")
        if self.criterion not in MIXTURE_CRITERIA:
            raise ValueError(f"mixture.criterion: unknown {self.criterion!r}; the criteria are "
                             f"{', '.join(MIXTURE_CRITERIA)}.")
        sets = [frozenset(c.effects) for c in compositions]
        if len(set(sets)) != len(sets):
            twice = next(c.label for c, s in zip(compositions, sets) if sets.count(s) > 1)
            raise ValueError(f"mixture.compositions: the composition {twice} is listed twice.")
        total = math.fsum(c.weight for c in compositions)
        if abs(total - 1.0) > WEIGHT_SUM_TOLERANCE:
            raise ValueError(f"mixture.compositions: the weights sum to {total:.12g}; they are "
                             "shares of one whole and must sum to 1.")
        if self.criterion == "bic":
            _check_bic_weights(compositions)
        object.__setattr__(self, "min_weight", _number(self.min_weight, "mixture.min_weight",
                                                       low=0.0, high=1.0))
        object.__setattr__(self, "left_out", _checked_left_out(self.left_out))
        object.__setattr__(self, "compositions", compositions)

    @property
    def size(self) -> int:
        """C, the number of compositions."""
        return len(self.compositions)

    @property
    def weights(self) -> np.ndarray:
        """(C,) the compositions' weights."""
        return np.array([c.weight for c in self.compositions])

    def motion_counts(self, n_motions: int, *, seed: int = 0) -> np.ndarray:
        """How many of `n_motions` motions each composition runs: systematic sampling (Kitagawa
        1996) of the weights, n_c = floor(N W_c + u) - floor(N W_(c-1) + u) with W_c the
        cumulative weights and u ~ U[0, 1) seeded by `seed`: E[n_c] = N w_c, and each n_c is
        floor(N w_c) or ceil(N w_c); they sum to N.

        **Returns:** (C,) int array."""
        if isinstance(n_motions, bool) or not isinstance(n_motions, int | np.integer) or n_motions < 1:
            raise ValueError(f"n_motions: must be a positive integer, got {n_motions!r}.")
        if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
            raise ValueError(f"seed: must be an integer >= 0, got {seed!r}.")
        cumulative = np.cumsum(self.weights)
        cumulative[-1] = 1.0
        u = np.random.default_rng(int(seed)).random()
        edges = np.floor(int(n_motions) * cumulative + u).astype(int)
        return np.diff(np.concatenate([[0], edges]))

    def composition_of_motions(self, n_motions: int, *, seed: int = 0) -> np.ndarray:
        """(N,) the composition each motion runs: composition c takes the `motion_counts(...)[c]`
        motions after those of compositions 0..c-1 (motions are independent, so a block of them
        is as random a share as any)."""
        counts = self.motion_counts(n_motions, seed=seed)
        return np.repeat(np.arange(self.size), counts)


def _check_bic_weights(compositions) -> None:
    """The weights of a `"bic"` mixture are exp(-dBIC / 2), normalised."""
    missing = [c.label for c in compositions if c.delta_bic is None]
    if missing:
        raise ValueError(f"mixture.compositions[{missing[0]}].delta_bic: a 'bic' mixture gives every "
                         "composition its BIC above the lowest.")
    best = max(compositions, key=lambda c: c.weight)
    for c in compositions:
        expected = best.weight * math.exp(-(c.delta_bic - best.delta_bic) / 2.0)
        if not math.isclose(c.weight, expected, rel_tol=BIC_WEIGHT_RTOL):
            raise ValueError(f"mixture.compositions[{c.label}].weight: {c.weight:.9g} does not follow "
                             f"from its delta_bic {c.delta_bic:.6g} (exp(-delta_bic / 2), normalised, "
                             f"gives {expected:.9g}).")


def _checked_left_out(left_out) -> tuple:
    out = []
    for i, entry in enumerate(left_out):
        where = f"mixture.left_out[{i}]"
        if not isinstance(entry, dict) or set(entry) != {"effects", "weight"}:
            raise ValueError(f"{where}: write {{\"effects\": [...], \"weight\": ...}}; got {entry!r}.")
        out.append({"effects": list(_effects(entry["effects"], f"{where}.effects")),
                    "weight": _number(entry["weight"], f"{where}.weight", low=0.0, high=1.0)})
    return tuple(out)
