"""What a discovery says while it runs (the `callback` of `discover_effects` and
`discover_series_effects`): the work up front with a rough time derived from its size, each
round's candidates as they are tried and, as the round's batched fit returns, each one's residual
and evidence, then the time the round took and the time the rounds left would take at its pace.

A search is a few batched Levenberg-Marquardt calls of the same shape (the baseline, then one per
round), so its time is one compile of that call plus, per call, the time of its fits, which grows
with the fits in the batch times the samples of the record (`Cost`)."""

import time
from typing import NamedTuple

from ._result import gain_text


class Cost(NamedTuple):
    """What one batched call costs on two CPU cores, as timed there (JAX on the CPU): `compile_s`
    the compile of the call, once per shape and process [s]; `member_sample_s` a call's time per
    fit of the batch and per sample of the record, at the usual 20-100 solver steps [s]."""

    compile_s: float
    member_sample_s: float


FLAT_COST = Cost(compile_s=30.0, member_sample_s=4e-4)
"""The flat slider's augmented model (`discover_effects`). On two cores the README tour's record
(1201 samples, 18 fits a call) took 30 s for the compile with the baseline's call, then 20 s and
2 s for its two rounds (a call's time follows the steps its slowest fit takes); the compile
alone took 10-15 s on idle cores and up to a minute on busy ones."""

SERIES_COST = Cost(compile_s=60.0, member_sample_s=0.01)
"""The series model of a triple or double pendulum (`discover_series_effects`), about 25 times
the flat slider's per sample: a double pendulum's record (201 samples, 6 fits, 90-100 solver
steps) took 57 s for the compile with its one call on two idle cores, and 100 s and 17 s a
call on busy ones."""

_COMPILED = set()
"""The call shapes compiled in this process (JAX keeps them), whose compile a plan leaves out."""


def duration(seconds: float) -> str:
    """`seconds` [s] in words a person reads at a glance: 'under a second', 'about 8 s',
    'about 40 s' (to 10 s), 'about 2.5 min'."""
    if seconds < 1:
        return "under a second"
    if seconds < 10:
        return f"about {seconds:.0f} s"
    if seconds < 90:
        return f"about {10 * round(seconds / 10):.0f} s"
    return f"about {seconds / 60:.1f} min"


class Progress:
    """The progress lines of one search, said through `say(text)`.

    **Arguments:** `cost` (`FLAT_COST` or `SERIES_COST`); `shape` the hashable shape of its
    batched call (compiled once per process); `n_members` fits per call; `n_samples` samples of
    the record as fitted; `label` the baseline's name."""

    def __init__(self, say, cost: Cost, shape, n_members: int, n_samples: int, label: str):
        self.say, self.cost, self.shape, self.label = say, cost, shape, label
        self.n_members, self.n_samples = n_members, n_samples
        self.started = self.call_started = time.perf_counter()
        self.compiling = shape not in _COMPILED
        self.warm_s = None  # the measured time of a call that did not compile [s]

    def call_estimate(self) -> float:
        """Time of one call that does not compile [s]: the last one measured, else `cost`'s."""
        if self.warm_s is not None:
            return self.warm_s
        return self.cost.member_sample_s * self.n_members * self.n_samples

    def plan(self, work: str, n_calls: int, skipped) -> None:
        """Say what the search will do (`work`), in `n_calls` batched calls at most, and roughly
        how long it takes; then the candidates it leaves out (`skipped`), if any."""
        estimate = n_calls * self.call_estimate()
        compile_note = ""
        if self.compiling:
            estimate += self.cost.compile_s
            compile_note = f", {duration(self.cost.compile_s)} of it compiling the fit once"
        self.say(f"plan: {self.n_samples} samples; {work}; at most {n_calls} batched "
                 f"call{'s' if n_calls != 1 else ''} of {self.n_members} fits: "
                 f"{duration(estimate)} on two CPU cores{compile_note}")
        if skipped:
            self.say(f"not tried: {', '.join(skipped)} (the report says why)")

    def calling(self, text: str) -> None:
        """Say that a batched call starts (`text` what it fits)."""
        self.say(text + (" (compiling first)..." if self.compiling else "..."))
        self.call_started = time.perf_counter()

    def called(self) -> float:
        """The call that `calling` started has returned: its time [s]."""
        took = time.perf_counter() - self.call_started
        if not self.compiling:
            self.warm_s = took
        self.compiling = False
        _COMPILED.add(self.shape)
        return took

    def took(self, what: str, took: float, calls_left: int) -> None:
        """Say that `what` took `took` [s] and, with `calls_left` batched calls at most still to
        come, what they would take at the pace measured so far."""
        left = ""
        if calls_left > 0:
            left = (f"; at most {calls_left} more call{'s' if calls_left != 1 else ''}: "
                    f"{duration(calls_left * self.call_estimate())} more")
        self.say(f"{what} took {took:.1f} s{left}")

    def done(self) -> None:
        """Say the search's time since the plan."""
        self.say(f"search done in {time.perf_counter() - self.started:.1f} s")


def candidate_lines(evid: dict, pool) -> list:
    """A line per candidate of a round: its residual before and after it was added, and its
    evidence (delta_bic, the held-out gain), strongest first."""
    ranked = sorted(pool, key=lambda c: -evid[c]["delta_bic"])
    return [f"  {c}: nrmse {evid[c]['nrmse_before']:.4f} -> {evid[c]['nrmse_after']:.4f}, "
            f"delta_bic {evid[c]['delta_bic']:.1f}, held-out gain {gain_text(evid[c])}"
            for c in ranked]
