"""The posterior of a bearing's constants: the thinned draws a Bayesian fit leaves beside the
point estimate of a bearing file.

A NUTS run (`identification.bayes.fit_bayes`) samples some constants of the bearing (the
friction constants of Eq. 1 `f_max`, `delta_f`, `rate_a`; `yield_disp` of Eq. 3;
`breakaway_ratio` of Eq. 17; ...). `BearingPosterior` keeps K of its draws (every `thinning`-th
of the `draws_before_thinning` draws of all chains), each constant's bulk effective sample
size (Vehtari et al. 2021, of the unthinned run) and the sampler's settings, and puts draw k
into a bearing: the point bearing's other constants stay as they are. Constants are named as
the fitter names them; `POSTERIOR_FIELDS` says which `(part, constant)` of the bearing each is.
SI units.
"""

import dataclasses
import math
import operator

import numpy as np

from ..bearing import PARAMETER_BOUNDS, SlidingBearing

MIN_POSTERIOR_ESS = 100.0
"""Fewest effective draws (bulk ESS of the unthinned run) of every sampled constant that a
posterior must have: with fewer, the Monte Carlo error of its 5 % and 95 % quantiles is more
than about a tenth of the posterior's spread."""

POSTERIOR_FIELDS = {name: b.field for name, b in PARAMETER_BOUNDS.items() if b.field is not None}
"""Constant name -> `(part, constant)` of the bearing model and the bearing file (the `field`
column of `teflon_jax.bearing.PARAMETER_BOUNDS`)."""


def _getter(name):
    """The function that reads constant `name` from a `SlidingBearing` (None: part absent)."""
    part, constant = POSTERIOR_FIELDS[name]
    if part == "breakaway":
        return lambda b: b.breakaway_ratio
    return lambda b: None if getattr(b, part) is None else getattr(getattr(b, part), constant)


def posterior_constant(bearing: SlidingBearing, name: str):
    """Constant `name` (a key of `POSTERIOR_FIELDS`) of `bearing` [SI], or `None` when the
    bearing lacks its part."""
    if name not in POSTERIOR_FIELDS:
        raise ValueError(f"posterior: unknown constant {name!r}; the constants a posterior can "
                         f"hold are {', '.join(POSTERIOR_FIELDS)}.")
    return _getter(name)(bearing)


def _count(value, key, minimum):
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise ValueError(f"posterior.{key}: must be an integer >= {minimum}, got {value!r}.")
    return int(value)


def _check_names(names):
    if isinstance(names, str) or not names:
        raise ValueError("posterior.names: give the sampled constants as a non-empty list of "
                         f"names (e.g. ['f_max', 'delta_f', 'rate_a']), got {names!r}.")
    names = tuple(names)
    for name in names:
        if name not in POSTERIOR_FIELDS:
            raise ValueError(f"posterior: unknown constant {name!r}; the constants a posterior "
                             f"can hold are {', '.join(POSTERIOR_FIELDS)}.")
    if len(set(names)) != len(names):
        raise ValueError(f"posterior.names: a constant is listed twice in {list(names)}.")
    return names


def _check_draws(names, draws):
    missing = [n for n in names if n not in draws]
    if missing:
        raise ValueError(f"posterior.draws: no draws for {', '.join(missing)}, which the "
                         "posterior lists among its constants; give a list of draws for each.")
    extra = [n for n in draws if n not in names]
    if extra:
        raise ValueError(f"posterior.draws: draws for {', '.join(map(str, extra))}, which the "
                         "posterior does not list among its constants; list them or remove them.")
    out = {}
    for name in names:
        try:
            x = np.array(draws[name], dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"posterior.draws.{name}: must be a list of numbers.") from None
        if x.ndim != 1 or x.size == 0:
            raise ValueError(f"posterior.draws.{name}: must be a non-empty list of numbers, got "
                             f"an array of shape {x.shape}.")
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            raise ValueError(f"posterior.draws.{name}: draw {int(bad[0])} is {x[bad[0]]}; every "
                             f"draw must be a finite number ({bad.size} are not).")
        x.setflags(write=False)
        out[name] = x
    sizes = {name: x.size for name, x in out.items()}
    if len(set(sizes.values())) > 1:
        raise ValueError("posterior.draws: every constant needs the same number of draws (one "
                         "bearing per draw); got " + ", ".join(f"{n} {k}" for n, k in sizes.items())
                         + ".")
    return out


def _check_ess(names, ess):
    missing = [n for n in names if n not in ess]
    if missing:
        raise ValueError(f"posterior.effective_sample_size: missing for {', '.join(missing)}.")
    out = {}
    for name in names:
        value = ess[name]
        if isinstance(value, bool) or not isinstance(value, int | float | np.number):
            raise ValueError(f"posterior.effective_sample_size.{name}: must be a number, got "
                             f"{value!r}.")
        value = float(value)
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"posterior.effective_sample_size.{name}: must be a finite number "
                             f"> 0, got {value}.")
        if value < MIN_POSTERIOR_ESS:
            raise ValueError(
                f"posterior.effective_sample_size.{name}: {value:.4g} effective draws is below "
                f"the floor of {MIN_POSTERIOR_ESS:.0f} (MIN_POSTERIOR_ESS): its quantiles would be "
                "mostly sampling noise. Sample longer (more draws or chains).")
        out[name] = value
    return out


@dataclasses.dataclass(frozen=True, eq=False)
class BearingPosterior:
    """Draws of a bearing's sampled constants (SI), checked when made.

    **Fields:**

    - `names`: the sampled constants by their fit-parameter names (`f_max`, `delta_f`,
      `rate_a`, `yield_disp`, `breakaway_ratio`, ...; keys of `POSTERIOR_FIELDS`).
    - `draws`: name -> read-only array of shape (K,) [SI], all of the same length K.
    - `effective_sample_size`: name -> bulk ESS of the unthinned run, each at least
      `MIN_POSTERIOR_ESS`.
    - `draws_before_thinning`: draws of all chains together N; `thinning`: every `thinning`-th
      of them is kept, so K = ceil(N / thinning).
    - `chains`, `seed`, `method`: the sampler's settings (`method` "NUTS").

    Refused with a `ValueError` naming the key: an unknown or repeated name, a name without
    draws (or draws without a name), draws of unequal lengths, a NaN or infinite draw, an ESS
    that is missing, not a number, <= 0 or below `MIN_POSTERIOR_ESS`, and K that does not
    follow from N and the thinning.
    """

    names: tuple[str, ...]
    draws: dict
    effective_sample_size: dict
    draws_before_thinning: int
    thinning: int
    chains: int
    seed: int
    method: str = "NUTS"

    def __post_init__(self):
        names = self.checked_names(self.names)
        draws = _check_draws(names, self.draws)
        ess = _check_ess(names, self.effective_sample_size)
        total = _count(self.draws_before_thinning, "draws_before_thinning", 1)
        thinning = _count(self.thinning, "thinning", 1)
        size = next(iter(draws.values())).size
        if size != -(-total // thinning):
            raise ValueError(
                f"posterior: {size} draws kept, but every {thinning}-th of "
                f"{total} draws (draws_before_thinning, thinning) is {-(-total // thinning)}.")
        _count(self.chains, "sampler.chains", 1)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int | np.integer):
            raise ValueError(f"posterior.sampler.seed: must be an integer, got {self.seed!r}.")
        if not isinstance(self.method, str) or not self.method:
            raise ValueError(f"posterior.sampler.method: must be a name such as 'NUTS', got "
                             f"{self.method!r}.")
        for key, value in (("names", names), ("draws", draws), ("effective_sample_size", ess),
                           ("draws_before_thinning", total), ("thinning", thinning),
                           ("chains", int(self.chains)), ("seed", int(self.seed))):
            object.__setattr__(self, key, value)

    @staticmethod
    def checked_names(names) -> tuple:
        """The sampled constants' names as a tuple; `ValueError` for an unknown or repeated one."""
        return _check_names(names)

    @property
    def size(self) -> int:
        """K, the number of draws kept."""
        return next(iter(self.draws.values())).size

    def quantile(self, name: str, q: float) -> float:
        """The `q`-quantile (0 <= q <= 1) of constant `name`'s draws [SI]."""
        if name not in self.draws:
            raise ValueError(f"quantile: {name!r} is not among the sampled constants "
                             f"({', '.join(self.names)}).")
        if not 0.0 <= float(q) <= 1.0:
            raise ValueError(f"quantile: q must be between 0 and 1, got {q}.")
        return float(np.quantile(self.draws[name], float(q)))

    def _check_point(self, point: SlidingBearing):
        getters = {name: _getter(name) for name in self.names}
        for name, get in getters.items():
            if get(point) is None:
                part = POSTERIOR_FIELDS[name][0]
                raise ValueError(f"posterior: the bearing has no part '{part}', which the draws "
                                 f"of {name} belong to; give the bearing the posterior came with.")
        return getters

    def bearing(self, point: SlidingBearing, k: int) -> SlidingBearing:
        """`point` with draw `k`'s constants put in (0 <= k < K; negative counts from the end)."""
        import equinox as eqx
        import jax.numpy as jnp

        k = operator.index(k)
        if not -self.size <= k < self.size:
            raise IndexError(f"posterior: draw {k} of {self.size} (0 to {self.size - 1}).")
        getters = self._check_point(point)
        return eqx.tree_at(lambda b: tuple(get(b) for get in getters.values()), point,
                           tuple(jnp.asarray(self.draws[n][k]) for n in getters))

    def bearings(self, point: SlidingBearing) -> SlidingBearing:
        """All K bearings as one `SlidingBearing` whose every leaf has a leading axis K (the
        point's constants repeated, the sampled ones drawn): a batch for `jax.vmap`."""
        import equinox as eqx
        import jax
        import jax.numpy as jnp

        getters = self._check_point(point)
        size = self.size
        batch = jax.tree_util.tree_map(
            lambda x: jnp.broadcast_to(jnp.asarray(x), (size, *jnp.shape(x))), point)
        return eqx.tree_at(lambda b: tuple(get(b) for get in getters.values()), batch,
                           tuple(jnp.asarray(self.draws[n]) for n in getters))


def thinned_posterior(samples: dict, effective_sample_size: dict, *, max_draws: int,
                      chains: int, seed: int, method: str = "NUTS", kind=BearingPosterior) -> BearingPosterior:
    """A `BearingPosterior` (or the subclass `kind`) of at most `max_draws` draws from
    `samples`, name -> (chains, draws) arrays [SI]: the chains one after the other, every
    `thinning`-th draw kept with `thinning = ceil(chains * draws / max_draws)`."""
    max_draws = _count(max_draws, "max_draws", 1)
    flat = {name: np.asarray(x, dtype=float).reshape(-1) for name, x in samples.items()}
    total = next(iter(flat.values())).size
    thinning = -(-total // max_draws)
    return kind(
        names=tuple(flat), draws={n: x[::thinning] for n, x in flat.items()},
        effective_sample_size=dict(effective_sample_size), draws_before_thinning=total,
        thinning=thinning, chains=chains, seed=seed, method=method)


POSTERIOR_KEYS = ("constants", "draws", "effective_sample_size", "draws_before_thinning", "thinning",
                  "sampler")
"""The keys of a file's `posterior` object (a bearing file's or an isolator file's)."""


def posterior_from_entry(entry, factors_of, where: str, kind=BearingPosterior) -> BearingPosterior:
    """The `kind` (`BearingPosterior` or a subclass) of a file's `posterior` object: its keys
    (`POSTERIOR_KEYS`), the SI factor of each sampled constant from `factors_of(constants,
    where)` (the file's own check of `constants`), each draw list a list of numbers, scaled to
    SI, and the sampler's settings; checked as `kind` checks them. `ValueError` naming `where`
    and the key."""
    if not isinstance(entry, dict):
        raise ValueError(f"{where}: posterior: must be an object with the keys {', '.join(POSTERIOR_KEYS)}.")
    unknown = sorted(set(entry) - set(POSTERIOR_KEYS))
    missing = [key for key in POSTERIOR_KEYS if key not in entry]
    if unknown or missing:
        raise ValueError(f"{where}: posterior: " + "; ".join(
            ([f"unknown key(s) {unknown}"] if unknown else [])
            + ([f"missing key(s) {missing}"] if missing else []))
            + f" (the keys are {', '.join(POSTERIOR_KEYS)}).")
    factors = factors_of(entry["constants"], where)
    draws, sampler = entry["draws"], entry["sampler"]
    if not isinstance(draws, dict):
        raise ValueError(f"{where}: posterior.draws: must be an object, name -> list of draws.")
    if not isinstance(entry["effective_sample_size"], dict):
        raise ValueError(f"{where}: posterior.effective_sample_size: must be an object, name -> "
                         "effective sample size.")
    if not isinstance(sampler, dict) or set(sampler) != {"method", "chains", "seed"}:
        raise ValueError(f'{where}: posterior.sampler: write {{"method": "NUTS", "chains": 4, "seed": 0}}; '
                         f"got {sampler!r}.")
    try:
        scaled = {}
        for name, x in draws.items():
            if not isinstance(x, list) or not all(isinstance(v, int | float) and not isinstance(v, bool)
                                                  for v in x):
                raise ValueError(f"posterior.draws.{name}: must be a list of numbers.")
            scaled[name] = [v * factors.get(name, 1.0) for v in x]
        return kind(names=tuple(factors), draws=scaled, effective_sample_size=entry["effective_sample_size"],
                    draws_before_thinning=entry["draws_before_thinning"], thinning=entry["thinning"],
                    chains=sampler["chains"], seed=sampler["seed"], method=sampler["method"])
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
