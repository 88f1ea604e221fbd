"""The posterior of a triple or double friction pendulum's surface friction: the thinned draws
a Bayesian fit (`identification.bayes.fit_series_bayes`) leaves in the isolator file beside
the least-squares constants, under the key `posterior`:

    "posterior": {
        "constants": {"bottom_f_max": {"unit": "1"}, "bottom_rate_a": {"unit": "s/m"}, ...},
        "draws": {"bottom_f_max": [0.0601, 0.0599, ...], ...},
        "effective_sample_size": {"bottom_f_max": 812.0, ...},
        "draws_before_thinning": 4000, "thinning": 4,
        "sampler": {"method": "NUTS", "chains": 4, "seed": 0}}

Each constant is `<surface>_<constant>`, a surface of the file and one of the Eq. 1 constants
f_max, delta_f, rate_a; its unit any of that quantity's. Draw k put into the file's pendulum
(its other constants as the file gives them) must be a pendulum the series model takes
(`check_series_pendulum`), and each effective sample size at least `MIN_POSTERIOR_ESS`, as in
a bearing file's posterior (`BearingPosterior`). SI inside.
"""

import dataclasses

import jax
import numpy as np

from ..bearing import SeriesPendulum, check_series_pendulum
from ..units import unit_factor
from ._bearing_posterior import BearingPosterior, posterior_from_entry

SURFACE_CONSTANTS = {"f_max": "dimensionless", "delta_f": "dimensionless", "rate_a": "slowness"}
"""The constants of a surface a posterior may hold, and their dimensions."""

SI_UNIT = {"dimensionless": "1", "slowness": "s/m"}


def _split(name: str) -> tuple[str, str]:
    surface, _, constant = str(name).partition("_")
    if constant not in SURFACE_CONSTANTS:
        raise ValueError(f"posterior: unknown constant {name!r}; a series pendulum's posterior holds "
                         f"<surface>_<constant> with the constant one of {', '.join(SURFACE_CONSTANTS)} "
                         "(e.g. bottom_f_max).")
    return surface, constant


@dataclasses.dataclass(frozen=True, eq=False)
class IsolatorPosterior(BearingPosterior):
    """Draws of a series pendulum's surface friction constants (`<surface>_f_max`,
    `<surface>_delta_f`, `<surface>_rate_a`) [SI], checked as a `BearingPosterior`'s; draw k
    put into a `TriplePendulum` or `DoublePendulum` (`bearing`, `bearings`)."""

    @staticmethod
    def checked_names(names) -> tuple:
        if isinstance(names, str) or not names:
            raise ValueError("posterior.names: give the sampled constants as a non-empty list of "
                             f"names (e.g. ['bottom_f_max', 'top_f_max']), got {names!r}.")
        names = tuple(names)
        for name in names:
            _split(name)
        if len(set(names)) != len(names):
            raise ValueError(f"posterior.names: a constant is listed twice in {list(names)}.")
        return names

    def _check_point(self, point: SeriesPendulum):
        getters = {}
        for name in self.names:
            surface, constant = _split(name)
            if surface not in point.slider_names:
                raise ValueError(f"posterior: the {point.description[:-1]} has no surface '{surface}', which "
                                 f"the draws of {name} belong to (its surfaces: {', '.join(point.slider_names)}).")
            getters[name] = lambda b, s=surface, c=constant: getattr(getattr(b, f"{s}_friction"), c)
        return getters

    def check_draws(self, point: SeriesPendulum) -> None:
        """`ValueError` naming the first draw that, put into `point`, the series model cannot take."""
        stacked = jax.tree_util.tree_map(np.asarray, self.bearings(point))  # draw k read in NumPy: no dispatch
        for k in range(self.size):
            try:
                check_series_pendulum(jax.tree_util.tree_map(lambda leaf, k=k: leaf[k], stacked))
            except ValueError as error:
                raise ValueError(f"posterior: draw {k}: {error}") from None


def isolator_posterior_to_dict(posterior: IsolatorPosterior) -> dict:
    """The `posterior` object of an isolator file (module docstring), SI."""
    return {
        "constants": {n: {"unit": SI_UNIT[SURFACE_CONSTANTS[_split(n)[1]]]} for n in posterior.names},
        "draws": {n: posterior.draws[n].tolist() for n in posterior.names},
        "effective_sample_size": dict(posterior.effective_sample_size),
        "draws_before_thinning": posterior.draws_before_thinning, "thinning": posterior.thinning,
        "sampler": {"method": posterior.method, "chains": posterior.chains, "seed": posterior.seed}}


def _surface_factors(constants, where: str) -> dict:
    """name -> SI factor of an isolator file's `posterior.constants` (`<surface>_<constant>`)."""
    at = f"{where}: posterior.constants"
    if not isinstance(constants, dict) or not constants:
        raise ValueError(f'{at}: must name the sampled constants, e.g. {{"bottom_f_max": {{"unit": "1"}}}}.')
    factors = {}
    for name, value in constants.items():
        try:
            dimension = SURFACE_CONSTANTS[_split(name)[1]]
        except ValueError as error:
            raise ValueError(f"{where}: {error}") from None
        if not isinstance(value, dict) or set(value) != {"unit"} or not isinstance(value["unit"], str):
            raise ValueError(f'{at}.{name}: write {{"unit": "{SI_UNIT[dimension]}"}}; got {value!r}.')
        factors[name] = unit_factor(value["unit"], dimension, where=f"{at}.{name}.unit")
    return factors


def isolator_posterior_from_dict(entry, point: SeriesPendulum, where: str) -> IsolatorPosterior:
    """The `IsolatorPosterior` of an isolator file's `posterior` object (`posterior_from_entry`),
    its draws checked in the file's pendulum `point`; `ValueError` naming `where` and the key."""
    posterior = posterior_from_entry(entry, _surface_factors, where, IsolatorPosterior)
    try:
        posterior.check_draws(point)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    return posterior
