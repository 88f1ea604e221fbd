"""Stochastic ground motions: Kanai-Tajimi / Clough-Penzien filtered white noise.

The stationary part is white noise at bedrock passed through two linear filters:

1. The Kanai-Tajimi soil filter (Kanai 1957; Tajimi 1960), a damped oscillator with the
   site's predominant frequency `omega_g` and damping `zeta_g`;
2. The Clough-Penzien high-pass filter (Clough & Penzien, *Dynamics of Structures*,
   1975 and 2nd ed. 1993), a second oscillator `omega_f`, `zeta_f` that removes the
   low-frequency content the Kanai-Tajimi spectrum keeps at zero frequency, so that the
   ground velocity and displacement have finite spectra at zero frequency.

The two-sided power spectral density of the ground acceleration is

    S(omega) = S0 * (omega_g^4 + 4 zeta_g^2 omega_g^2 omega^2)
                  / ((omega_g^2 - omega^2)^2 + 4 zeta_g^2 omega_g^2 omega^2)
                  * omega^4 / ((omega_f^2 - omega^2)^2 + 4 zeta_f^2 omega_f^2 omega^2),

with the last factor left out for plain Kanai-Tajimi. The stationary record is then
multiplied by the Jennings, Housner & Tsai (1968, "Simulated earthquake motions",
EERL report, Caltech) envelope: a parabolic rise, a constant strong phase and an
exponential decay.

Samples are drawn with the spectral representation method (Shinozuka & Deodatis 1991,
"Simulation of stochastic processes by spectral representation", Applied Mechanics
Reviews 44(4)), evaluated with one inverse FFT per record.
"""

import functools
import math
import operator

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float, PRNGKeyArray

from ..validation import concrete

_QUANTITY_ORDER = {"acceleration": 0, "velocity": 1, "displacement": 2}


def _float(x) -> Array:
    return jnp.asarray(x, dtype=jnp.result_type(float))


def _check_value(name: str, value, *, allow_zero: bool = False) -> None:
    """`ValueError` naming `name` unless `value` is positive (non-negative) and finite.

    Traced values (a model built inside `jit` or `vmap`) cannot be checked here.
    """
    array = concrete(value)
    if array is None:
        return
    bad = ~np.isfinite(array) | ((array < 0) if allow_zero else (array <= 0))
    if bool(np.any(bad)):
        sign = "non-negative" if allow_zero else "positive"
        raise ValueError(
            f"StochasticGroundMotion: `{name}` must be {sign} and finite, got {value}."
        )


class StochasticGroundMotion(eqx.Module):
    """Clough-Penzien (or Kanai-Tajimi) filtered white noise with a Jennings-Housner-Tsai
    envelope.

    The physical parameters are scalar arrays (differentiable; `vmap` over models to
    batch them); `duration`, `time_step` and `high_pass_filter` are static Python values.

    **Fields:**

    - `peak_ground_acceleration`: nominal expected peak of a record [m/s^2]. It fixes
      the stationary standard deviation `sigma = peak_ground_acceleration / peak_factor`,
      and through it the white-noise intensity `S0` (see `white_noise_intensity`), so
      changing the site parameters reshapes the spectrum at constant `sigma`.
    - `peak_factor`: ratio of the expected peak to `sigma` [-]. The default 3.0 is the
      usual value for records with a strong phase of about ten seconds: Davenport's
      (1964) peak factor `sqrt(2 ln(nu T)) + 0.5772 / sqrt(2 ln(nu T))` is 3.0 to 3.2
      for `nu T` = 50 to 100 zero up-crossings. The realised mean peak depends on the
      envelope and `time_step`; with the defaults it is about 7 % above
      `peak_ground_acceleration` (between about 0 and +14 % for strong phases of 5 to
      20 s). Set `peak_factor` to calibrate; `sigma` is the exact scale.
    - `site_frequency`: Kanai-Tajimi predominant frequency `omega_g` [rad/s]. Default
      15.6 rad/s (firm soil, the values usually quoted after Kanai and Tajimi).
    - `site_damping`: Kanai-Tajimi damping ratio `zeta_g` [-]. Default 0.6.
    - `high_pass_frequency`: Clough-Penzien filter frequency `omega_f` [rad/s]. Default
      1.56 rad/s, the common choice `omega_f = omega_g / 10`.
    - `high_pass_damping`: Clough-Penzien damping ratio `zeta_f` [-]. Default 0.6.
    - `rise_time`: end of the parabolic rise `t1` of the envelope [s].
    - `strong_motion_duration`: length `t2 - t1` of the constant strong phase [s].
    - `decay_rate`: `c` of the exponential decay `exp(-c (t - t2))` [1/s].
    - `duration`: length of the record [s] (static: it fixes the array shape); the
      samples are `t_j = j time_step` for `t_j <= duration`.
    - `time_step`: sampling interval [s] (static). The samples cover frequencies up to
      the Nyquist frequency `pi / time_step` [rad/s].
    - `high_pass_filter`: `True` for Clough-Penzien, `False` for plain Kanai-Tajimi
      (static; the `high_pass_*` fields are then ignored).

    The envelope defaults (2 s rise, 10 s strong phase, decay 0.3 1/s over a 25 s record)
    describe a moderate shallow event; they are illustrative, not values from the
    references.
    """

    peak_ground_acceleration: Float[Array, ""] = eqx.field(converter=_float)
    peak_factor: Float[Array, ""] = eqx.field(converter=_float, default=3.0)
    site_frequency: Float[Array, ""] = eqx.field(converter=_float, default=15.6)
    site_damping: Float[Array, ""] = eqx.field(converter=_float, default=0.6)
    high_pass_frequency: Float[Array, ""] = eqx.field(converter=_float, default=1.56)
    high_pass_damping: Float[Array, ""] = eqx.field(converter=_float, default=0.6)
    rise_time: Float[Array, ""] = eqx.field(converter=_float, default=2.0)
    strong_motion_duration: Float[Array, ""] = eqx.field(converter=_float, default=10.0)
    decay_rate: Float[Array, ""] = eqx.field(converter=_float, default=0.3)
    duration: float = eqx.field(static=True, default=25.0)
    time_step: float = eqx.field(static=True, default=0.01)
    high_pass_filter: bool = eqx.field(static=True, default=True)

    def __check_init__(self):
        for name in (
            "peak_ground_acceleration",
            "peak_factor",
            "site_frequency",
            "site_damping",
            "rise_time",
            "decay_rate",
        ):
            _check_value(name, getattr(self, name))
        _check_value("strong_motion_duration", self.strong_motion_duration, allow_zero=True)
        if self.high_pass_filter:
            _check_value("high_pass_frequency", self.high_pass_frequency)
            _check_value("high_pass_damping", self.high_pass_damping)
        for name in ("duration", "time_step"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(
                    f"StochasticGroundMotion: `{name}` must be a Python number in seconds "
                    f"(it fixes the array shape), got {type(value).__name__}."
                )
            if not (math.isfinite(value) and value > 0):
                raise ValueError(
                    f"StochasticGroundMotion: `{name}` must be positive and finite [s], "
                    f"got {value}."
                )
        if self.duration < self.time_step:
            raise ValueError(
                f"StochasticGroundMotion: `duration` ({self.duration} s) is shorter than "
                f"`time_step` ({self.time_step} s); lengthen the record or refine the step."
            )
        envelope_end = self.rise_time + self.strong_motion_duration
        if not isinstance(envelope_end, jax.core.Tracer) and bool(
            jnp.any(envelope_end > self.duration)
        ):
            raise ValueError(
                f"StochasticGroundMotion: `rise_time` + `strong_motion_duration` "
                f"({envelope_end} s) exceeds `duration` ({self.duration} s); lengthen "
                f"`duration` or shorten the envelope."
            )
        nyquist = math.pi / self.time_step
        if not isinstance(self.site_frequency, jax.core.Tracer) and bool(
            jnp.any(2.0 * self.site_frequency > nyquist)
        ):
            raise ValueError(
                f"StochasticGroundMotion: `time_step` ({self.time_step} s) is too coarse "
                f"for `site_frequency` ({self.site_frequency} rad/s): the Nyquist "
                f"frequency pi / time_step = {nyquist:.4g} rad/s must be at least twice "
                f"the site frequency; reduce `time_step`."
            )


def num_time_steps(model: StochasticGroundMotion) -> int:
    """Samples per record, `nt = floor(duration / time_step) + 1` (a Python int)."""
    return int(math.floor(model.duration / model.time_step + 1e-9)) + 1


def sample_times(model: StochasticGroundMotion) -> Float[Array, " nt"]:
    """Times `t_j = j * time_step`, `j = 0 .. nt - 1`, of the samples [s]."""
    return jnp.arange(num_time_steps(model), dtype=jnp.result_type(float)) * model.time_step


@jax.jit
def envelope(
    model: StochasticGroundMotion, t: Float[Array, "*shape"]
) -> Float[Array, "*shape"]:
    """Jennings-Housner-Tsai (1968) time-modulating envelope.

        e(t) = (t / t1)^2          for 0 <= t < t1,
               1                   for t1 <= t <= t2,
               exp(-c (t - t2))    for t > t2,

    with `t1 = rise_time`, `t2 = rise_time + strong_motion_duration`, `c = decay_rate`,
    and `e(t) = 0` for `t < 0`.

    **Arguments:**

    - `model`: the ground-motion model.
    - `t`: times [s], any shape.

    **Returns:** `e(t)` [-], the shape of `t`.
    """
    t = _float(t)
    t1 = model.rise_time
    t2 = model.rise_time + model.strong_motion_duration
    rise = (jnp.clip(t, 0.0, None) / t1) ** 2
    decay = jnp.exp(-model.decay_rate * jnp.clip(t - t2, 0.0, None))
    return jnp.where(t < 0.0, 0.0, jnp.where(t < t1, rise, decay))


def _kanai_tajimi_gain(model: StochasticGroundMotion, omega: Array) -> Array:
    """|H_KT(omega)|^2 = (wg^4 + 4 zg^2 wg^2 w^2) / ((wg^2 - w^2)^2 + 4 zg^2 wg^2 w^2)."""
    wg2 = model.site_frequency**2
    damping_term = 4.0 * model.site_damping**2 * wg2 * omega**2
    return (wg2**2 + damping_term) / ((wg2 - omega**2) ** 2 + damping_term)


def _high_pass_denominator(model: StochasticGroundMotion, omega: Array) -> Array:
    """(wf^2 - w^2)^2 + 4 zf^2 wf^2 w^2 of the Clough-Penzien filter."""
    wf2 = model.high_pass_frequency**2
    return (wf2 - omega**2) ** 2 + 4.0 * model.high_pass_damping**2 * wf2 * omega**2


def _state_space(model: StochasticGroundMotion) -> tuple[Array, Array, Array]:
    """Filters as `z' = A z + b w`, `a_g = c . z`, with `z = (x_g, v_g[, x_f, v_f])`.

    Kanai-Tajimi: `x_g'' + 2 zg wg x_g' + wg^2 x_g = -w`, whose absolute acceleration is
    `a_1 = -(wg^2 x_g + 2 zg wg x_g')`. Clough-Penzien: `x_f'' + 2 zf wf x_f' + wf^2 x_f =
    a_1`, and the ground acceleration is `a_g = x_f'' = a_1 - wf^2 x_f - 2 zf wf x_f'`.
    """
    wg, zg = model.site_frequency, model.site_damping
    zero = jnp.zeros_like(wg)
    one = jnp.ones_like(wg)
    kt_row = jnp.stack([-(wg**2), -2.0 * zg * wg])  # a_1 = kt_row . (x_g, v_g)
    if not model.high_pass_filter:
        a = jnp.stack([jnp.stack([zero, one]), kt_row])
        b = jnp.stack([zero, -one])
        return a, b, kt_row
    wf, zf = model.high_pass_frequency, model.high_pass_damping
    hp_row = jnp.stack([-(wf**2), -2.0 * zf * wf])
    a = jnp.stack(
        [
            jnp.stack([zero, one, zero, zero]),
            jnp.concatenate([kt_row, jnp.stack([zero, zero])]),
            jnp.stack([zero, zero, zero, one]),
            jnp.concatenate([kt_row, hp_row]),
        ]
    )
    b = jnp.stack([zero, -one, zero, zero])
    return a, b, jnp.concatenate([kt_row, hp_row])


def _variance_per_unit_intensity(model: StochasticGroundMotion) -> Array:
    """Stationary acceleration variance for `S0 = 1` [m^2/s^4 per m^2/s^3], exactly.

    Solves the Lyapunov equation `A P + P A^T + 2 pi b b^T = 0` for the state covariance
    (two-sided white noise of intensity `S0` has autocorrelation `2 pi S0 delta(tau)`)
    and returns `c P c^T`.
    """
    a, b, c = _state_space(model)
    n = a.shape[0]
    eye = jnp.eye(n, dtype=a.dtype)
    # Row-major vec: vec(A P) = (A kron I) vec(P), vec(P A^T) = (I kron A) vec(P).
    lyapunov = jnp.kron(a, eye) + jnp.kron(eye, a)
    rhs = -2.0 * math.pi * jnp.outer(b, b).reshape(-1)
    covariance = jnp.linalg.solve(lyapunov, rhs).reshape(n, n)
    return c @ covariance @ c


@jax.jit
def stationary_variance(model: StochasticGroundMotion) -> Float[Array, ""]:
    """Variance of the stationary ground acceleration [m^2/s^4].

        sigma^2 = integral_{-inf}^{inf} S(omega) d omega
                = (peak_ground_acceleration / peak_factor)^2.

    The sampled records miss the part of the spectrum above the Nyquist frequency
    `pi / time_step`; with the Kanai-Tajimi tail `S ~ 4 S0 zeta_g^2 omega_g^2 / omega^2`
    that is about `8 S0 zeta_g^2 omega_g^2 time_step / pi` (about 2 % of the variance
    for the defaults).
    """
    return (model.peak_ground_acceleration / model.peak_factor) ** 2


@jax.jit
def white_noise_intensity(model: StochasticGroundMotion) -> Float[Array, ""]:
    """Two-sided intensity `S0` of the bedrock white noise [m^2/s^3].

    Fixed by `sigma^2 = S0 * integral |H(omega)|^2 d omega`, the integral of the filters'
    squared gain taken exactly from the Lyapunov equation of their state-space form. For
    plain Kanai-Tajimi it equals the classical `pi omega_g (1 + 4 zeta_g^2) / (2 zeta_g)`.
    """
    return stationary_variance(model) / _variance_per_unit_intensity(model)


@functools.partial(jax.jit, static_argnames=("quantity",))
def power_spectral_density(
    model: StochasticGroundMotion,
    omega: Float[Array, "*shape"],
    *,
    quantity: str = "acceleration",
) -> Float[Array, "*shape"]:
    """Two-sided power spectral density of the stationary ground motion.

        S_a(omega) = S0 |H_KT(omega)|^2 omega^4 / ((omega_f^2 - omega^2)^2
                                                   + 4 zeta_f^2 omega_f^2 omega^2),
        S_v(omega) = S_a(omega) / omega^2,   S_d(omega) = S_a(omega) / omega^4,

    (the last factor of `S_a` is 1 for plain Kanai-Tajimi), normalised so that
    `integral_{-inf}^{inf} S_a d omega = stationary_variance(model)`; the one-sided
    spectrum over `omega >= 0` is `2 S`. With the Clough-Penzien filter the velocity
    and displacement spectra stay finite at `omega = 0` (the displacement one tends to
    `S0 / omega_f^4`); for plain Kanai-Tajimi they are infinite there.

    **Arguments:**

    - `model`: the ground-motion model.
    - `omega`: circular frequencies [rad/s], any shape (negative values allowed).
    - `quantity`: `"acceleration"` [m^2/s^3], `"velocity"` [m^2/s] or `"displacement"`
      [m^2 s].

    **Returns:** `S(omega)`, the shape of `omega`.
    """
    if quantity not in _QUANTITY_ORDER:
        raise ValueError(
            f"power_spectral_density: `quantity` must be one of "
            f"{', '.join(_QUANTITY_ORDER)}, got {quantity!r}."
        )
    order = _QUANTITY_ORDER[quantity]
    omega = _float(omega)
    s0 = white_noise_intensity(model)
    gain = _kanai_tajimi_gain(model, omega)
    if model.high_pass_filter:
        # omega^(4 - 2 order) written out so that omega = 0 gives the finite limit.
        return s0 * gain * omega ** (4 - 2 * order) / _high_pass_denominator(model, omega)
    if order == 0:
        return s0 * gain
    return s0 * gain / omega ** (2 * order)


def _is_prng_key(key) -> bool:
    """A new-style typed key of shape `()` or a legacy `uint32[2]` key."""
    if not isinstance(key, jax.Array):
        return False
    if jnp.issubdtype(key.dtype, jax.dtypes.prng_key):
        return key.shape == ()
    return key.dtype == jnp.uint32 and key.shape == (2,)


@eqx.filter_jit
def _sample(
    model: StochasticGroundMotion,
    key: PRNGKeyArray,
    n: int,
    stationary: bool,
    random_amplitudes: bool,
) -> Array:
    nt = num_time_steps(model)
    dtype = jnp.result_type(float)
    delta_omega = 2.0 * math.pi / (nt * model.time_step)
    n_components = (nt - 1) // 2  # k = 1 .. K; the mean (k = 0) and Nyquist bins stay 0
    omega = delta_omega * jnp.arange(1, n_components + 1, dtype=dtype)
    amplitude = jnp.sqrt(2.0 * power_spectral_density(model, omega) * delta_omega)[None, :]
    shape = (n, n_components)
    if random_amplitudes:
        real_key, imag_key = jax.random.split(key)
        real = amplitude * jax.random.normal(real_key, shape, dtype)
        imag = amplitude * jax.random.normal(imag_key, shape, dtype)
    else:
        phase = jax.random.uniform(key, shape, dtype, 0.0, 2.0 * math.pi)
        real = math.sqrt(2.0) * amplitude * jnp.cos(phase)
        imag = math.sqrt(2.0) * amplitude * jnp.sin(phase)
    coefficient = jax.lax.complex(real, imag)
    # irfft(X)_j = (1 / nt) [X_0 + 2 Re sum_k X_k exp(2 pi i k j / nt)], so X_k = nt c_k / 2
    # gives x_j = Re sum_k c_k exp(i omega_k t_j).
    spectrum = jnp.zeros((n, nt // 2 + 1), coefficient.dtype)
    spectrum = spectrum.at[:, 1 : n_components + 1].set(0.5 * nt * coefficient)
    record = jnp.fft.irfft(spectrum, n=nt, axis=-1)
    if stationary:
        return record
    return record * envelope(model, sample_times(model))[None, :]


def sample(
    model: StochasticGroundMotion,
    key: PRNGKeyArray,
    n: int,
    *,
    stationary: bool = False,
    random_amplitudes: bool = True,
) -> Float[Array, "n nt"]:
    """Draw `n` ground-acceleration records by the spectral representation method.

    Each stationary record is a finite sum of harmonics at `omega_k = k delta_omega`,
    `delta_omega = 2 pi / (nt time_step)`, `k = 1 .. (nt - 1) // 2`,

        x(t) = Re sum_k c_k exp(i omega_k t),   E|c_k|^2 = 2 A_k^2,
        A_k = sqrt(2 S(omega_k) delta_omega)

    (Shinozuka & Deodatis 1991), summed with one inverse FFT, and is then multiplied by
    `envelope(model, t)`. With `random_amplitudes=True` the `c_k` are complex Gaussian,
    so every record is exactly Gaussian; with `False` they have the fixed modulus
    `sqrt(2) A_k` and uniform random phases (the classic form, Gaussian only as the
    number of harmonics grows). The records are periodic with period `nt time_step`,
    have no zero-frequency content (each stationary record has zero time average), and
    contain no frequencies above the Nyquist frequency `pi / time_step`.

    Memory grows as `n * nt`; draw large ensembles in chunks with different keys
    (`jax.random.split`). The function is `jit`-compiled once per `n` and model
    structure and can be `vmap`-ed over keys or over the model's array fields.

    **Arguments:**

    - `model`: the ground-motion model.
    - `key`: a JAX PRNG key.
    - `n`: number of records (a positive Python int).
    - `stationary`: `True` to skip the envelope and return the stationary process.
    - `random_amplitudes`: see above.

    **Returns:** ground accelerations [m/s^2], shape `(n, nt)`, sampled at
    `sample_times(model)`; rows are ready for the batch simulator.
    """
    try:
        count = operator.index(n)
    except TypeError:
        count = None
    if isinstance(n, bool) or count is None or count <= 0:
        raise ValueError(
            f"sample: `n` (number of records) must be a positive int, got {n!r}."
        )
    if not _is_prng_key(key):
        raise ValueError(
            f"sample: `key` must be a JAX PRNG key such as `jax.random.key(seed)`, got "
            f"{type(key).__name__} {getattr(key, 'dtype', '')}{getattr(key, 'shape', '')}."
        )
    return _sample(model, key, count, bool(stationary), bool(random_amplitudes))
