"""The stochastic motions of a Monte Carlo run: motion i drawn from `fold_in(key, i)`, with one
or two horizontal components and optionally a vertical one, as the `Signal`s a structure takes."""

import equinox as eqx
import jax

from ..excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    VerticalGroundMotion,
    num_time_steps,
    sample,
    sample_two_components,
    sample_with_vertical,
    uniform_signal,
)


def monte_carlo_motion(model: StochasticGroundMotion | TwoComponentGroundMotion | VerticalGroundMotion, key, index):
    """The `index`-th motion [m/s^2] that `monte_carlo(structure, model, n, key=key)` draws
    (one sample from `jax.random.fold_in(key, index)`), e.g. to run it through another program:
    shape (nt,), or (2, nt) (x, y) for a `TwoComponentGroundMotion`, whose major component is
    then the one-component motion `index` of `model.model`; (2, nt) (horizontal, vertical)
    for a `VerticalGroundMotion`, or (3, nt) (x, y, vertical) for one with two horizontal
    components, whose first rows are then motion `index` of its `TwoComponentGroundMotion`."""
    if isinstance(model, VerticalGroundMotion):
        return sample_with_vertical(model, jax.random.fold_in(key, index), 1)[0]
    if isinstance(model, TwoComponentGroundMotion):
        return sample_two_components(model, jax.random.fold_in(key, index), 1)[0]
    return sample(model, jax.random.fold_in(key, index), 1)[0]


def motions_at_level(model, level):
    """`model` with the expected peak ground acceleration `level` [m/s^2] of its (major)
    horizontal component (a float or a traced scalar: one compiled run serves every level);
    with a vertical component (`VerticalGroundMotion`) the vertical one's peak,
    `vertical_ratio` times the horizontal one's, scales with it."""
    if isinstance(model, VerticalGroundMotion):
        return eqx.tree_at(lambda m: m.model, model, motions_at_level(model.model, level))
    if isinstance(model, TwoComponentGroundMotion):
        return eqx.tree_at(lambda m: m.model.peak_ground_acceleration, model, level)
    return eqx.tree_at(lambda m: m.peak_ground_acceleration, model, level)


def level_of(model) -> float:
    """The expected peak ground acceleration [m/s^2] of `model`'s (major) horizontal component."""
    if isinstance(model, VerticalGroundMotion):
        model = model.model
    if isinstance(model, TwoComponentGroundMotion):
        model = model.model
    return float(model.peak_ground_acceleration)


def stochastic_grid(motions) -> tuple[float, int, int]:
    """(time step [s], samples, components: the rows of a motion) of a stochastic motion model."""
    if isinstance(motions, VerticalGroundMotion):
        model = motions.horizontal_model
        return model.time_step, num_time_steps(model), motions.horizontal_components + 1
    model = motions.model if isinstance(motions, TwoComponentGroundMotion) else motions
    return model.time_step, num_time_steps(model), 2 if model is not motions else 1


def motion_attributes(motions) -> dict:
    """What a results file says of two-component motions (empty for one component)."""
    if isinstance(motions, VerticalGroundMotion):
        return {**motion_attributes(motions.model), "vertical_ratio": float(motions.vertical_ratio),
                "vertical_frequency_ratio": float(motions.frequency_ratio),
                "uplift": "uplift_time: time with N = W (1 + a_v / g) <= 0, isolators without shear"}
    if not isinstance(motions, TwoComponentGroundMotion):
        return {}
    return {"components": 2, "principal_angle_rad": float(motions.principal_angle),
            "minor_ratio": float(motions.minor_ratio),
            "peaks": "resultants: base_disp = max |(d_x, d_y)|, base_shear_ratio = max |(V_x, V_y)| / W "
                     "with V the force on the structure above the bearings; pga = max |(a_x, a_y)|"}


class _Source(eqx.Module):
    model: StochasticGroundMotion | TwoComponentGroundMotion | VerticalGroundMotion | None
    key: jax.Array | None
    time_step: float = eqx.field(static=True)
    samples: int = eqx.field(static=True)

    @property
    def components(self) -> int:
        """Horizontal components of each motion: 1 or 2."""
        if isinstance(self.model, VerticalGroundMotion):
            return self.model.horizontal_components
        return 2 if isinstance(self.model, TwoComponentGroundMotion) else 1

    @property
    def vertical(self) -> bool:
        """Whether each motion has a vertical component (`VerticalGroundMotion`)."""
        return isinstance(self.model, VerticalGroundMotion)

    def signal(self, index, values, level=None):
        """The motion's `Signal`, or its (x, y) pair of `Signal`s for two components; with a
        vertical component the pair (horizontal, vertical), horizontal either of those.
        `level` [m/s^2]: the expected peak ground acceleration of a generated motion
        (`motions_at_level`; default the model's)."""
        if self.model is not None:
            model = self.model if level is None else motions_at_level(self.model, level)
            values = monte_carlo_motion(model, self.key, index)
        if self.vertical:
            vertical = uniform_signal(values[-1], self.time_step)
            if self.components == 2:
                return (uniform_signal(values[0], self.time_step), uniform_signal(values[1], self.time_step)), vertical
            return uniform_signal(values[0], self.time_step), vertical
        if self.components == 2:
            return uniform_signal(values[0], self.time_step), uniform_signal(values[1], self.time_step)
        return uniform_signal(values, self.time_step)
