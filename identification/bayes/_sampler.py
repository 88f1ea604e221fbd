"""The NUTS runs of the Bayesian fit: a compiled sampler kept for records of one shape.

`NutsSampler` drives numpyro's functional NUTS (`numpyro.infer.hmc.hmc`, Hoffman & Gelman
2014, with numpyro's dual-averaging step size and windowed dense mass-matrix adaptation)
through two compiled programs: the chains' initial states, and `length` transitions of all
chains (warm-up and draws alike, in blocks). Everything that changes from one fit to the next
-- the record arrays, the prior ranges, the constants held, the starts, the initial mass
matrix, the random key -- is an argument of those programs, not a constant compiled into
them, so `compiled_sampler` hands out the same programs for every fit of records with the
same sample counts, free set, interfaces, chains and warm-up: a process that runs many fits
compiles once, and its memory stays flat.

`sample_uncached` is the earlier driver, numpyro's `MCMC` made anew for each fit (its
programs hold the record as constants and are compiled for every fit); it is kept for
comparison (`fit_bayes(..., reuse_compiled=False)`, `benchmarks/bayes_many_fits.py`).
"""

import collections
import sys

import jax
import numpy as np
from numpyro.infer import MCMC, NUTS
from numpyro.infer.hmc import hmc
from numpyro.infer.hmc_util import euclidean_kinetic_energy
from numpyro.infer.util import potential_energy

from ._model import make_model

MAX_SAMPLERS = 4
"""Compiled samplers kept at once (the least recently used is dropped beyond)."""

_SAMPLERS: collections.OrderedDict = collections.OrderedDict()

BLOCKS = 10
"""The draws are taken in at most this many blocks (after the warm-up, which runs in blocks of
the same length) of at least `MIN_BLOCK` draws, so that an interrupted run keeps the blocks it
finished."""

MIN_BLOCK = 10
"""Fewest draws per chain in a block (all of them when fewer are asked for)."""


class SamplingInterrupted(KeyboardInterrupt):
    """Ctrl-C (`KeyboardInterrupt`) during `fit_bayes` or `fit_series_bayes`; `result` is the `BayesResult` of the
    blocks of draws finished before it (`converged=False`, `interrupted` set), or None when
    no block had finished (interrupted in the warm-up)."""

    def __init__(self, result):
        super().__init__("sampling interrupted")
        self.result = result


def block_length(num_samples: int) -> int:
    """Draws per chain in a block: `num_samples` in at most `BLOCKS` blocks of at least
    `MIN_BLOCK` (all of them when fewer are asked for)."""
    return max(-(-num_samples // BLOCKS), min(num_samples, MIN_BLOCK))


class NutsSampler:
    """NUTS over all chains at once (vectorised), compiled once for one model shape.

    **Arguments:** `shapes`, `fixed_names`, `n_interfaces`: as `make_model`; `num_warmup`,
    `num_chains`, `target_accept`: NUTS settings (dense mass matrix over all sites, maximum
    tree depth 10, as `numpyro.infer.NUTS(dense_mass=True)`). `runs` counts the fits run.
    """

    def __init__(self, shapes, fixed_names, n_interfaces, *, num_warmup, num_chains,
                 target_accept):
        model = make_model(dict(shapes), tuple(fixed_names), tuple(n_interfaces))
        self.num_warmup, self.num_chains = int(num_warmup), int(num_chains)
        self.runs = 0

        def potential_gen(*args):
            return lambda z: potential_energy(model, args, {}, z)

        init_kernel, sample_kernel = hmc(potential_fn_gen=potential_gen,
                                         kinetic_fn=euclidean_kinetic_energy, algo="NUTS")

        def init(starts, keys, inverse_mass, args):
            dense = [tuple(sorted(starts))]

            def one(z, key):
                return init_kernel(z, self.num_warmup, step_size=1.0, inverse_mass_matrix=inverse_mass,
                                   adapt_step_size=True, adapt_mass_matrix=True, dense_mass=dense,
                                   target_accept_prob=target_accept, trajectory_length=None,
                                   max_tree_depth=10, model_args=args, rng_key=key)

            return jax.vmap(one)(starts, keys)

        def advance(state, args, length):
            def step(s, _):
                s = jax.vmap(sample_kernel, in_axes=(0, None))(s, args)
                return s, (s.z, s.diverging)

            return jax.lax.scan(step, state, None, length=length)

        self._init = jax.jit(init)
        self._advance = jax.jit(advance, static_argnums=2)

    def compilations(self) -> int:
        """Programs compiled so far (initial state, and one per block length)."""
        return self._init._cache_size() + self._advance._cache_size()

    def run(self, key, starts, inverse_mass, args, *, num_samples, block, on_block=None,
            progress_bar=False):
        """Warm-up, then `num_samples` draws per chain, both in blocks of `block` transitions.

        **Returns:** (site -> (chains, draws, ...) unconstrained draws, or None; (chains,
        draws) divergence flags, or None; None, or why the run stopped early: a
        `KeyboardInterrupt` ends it and keeps the blocks of draws finished).
        """
        self.runs += 1
        bar = _bar(self.num_warmup + num_samples, progress_bar)
        parts, flags, done = [], [], 0
        try:
            init_key, key = jax.random.split(key)
            state = self._init(starts, jax.random.split(init_key, self.num_chains),
                               inverse_mass, args)
            for length in _lengths(self.num_warmup, block):
                state, _ = self._advance(state, args, length)
                bar.update(length)
            if on_block is not None:
                on_block(0, num_samples)
            for length in _lengths(num_samples, block):
                state, (z, diverging) = self._advance(state, args, length)
                parts.append({k: np.swapaxes(np.asarray(v), 0, 1) for k, v in z.items()})
                flags.append(np.swapaxes(np.asarray(diverging), 0, 1))
                done += length
                bar.update(length)
                if on_block is not None:
                    on_block(done, num_samples)
        except KeyboardInterrupt:
            where = f"after {done} of {num_samples} draws per chain" if done else "in the warm-up"
            interrupted = f"interrupted {where}"
        else:
            interrupted = None
        finally:
            bar.close()
        return _joined(parts, flags, interrupted)


def _lengths(total, block):
    return [block] * (total // block) + ([total % block] if total % block else [])


def _joined(parts, flags, interrupted):
    if not parts:
        return None, None, interrupted
    base = {k: np.concatenate([p[k] for p in parts], axis=1) for k in parts[0]}
    return base, np.concatenate(flags, axis=1), interrupted


class _NoBar:
    def update(self, n):
        pass

    def close(self):
        pass


def _bar(total, shown):
    if not shown:
        return _NoBar()
    from tqdm import tqdm

    return tqdm(total=total, file=sys.stderr, desc="NUTS (warm-up, then draws)", unit="step")


def compiled_sampler(shapes, fixed_names, n_interfaces, lengths, *, num_warmup, num_chains,
                     target_accept) -> NutsSampler:
    """The `NutsSampler` of this shape of problem, made on first use and kept (at most
    `MAX_SAMPLERS`): `shapes` name -> `PriorShape`, `lengths` the records' sample counts."""
    key = (tuple(shapes.items()), tuple(fixed_names), tuple(n_interfaces), tuple(lengths),
           int(num_warmup), int(num_chains), float(target_accept),
           bool(jax.config.jax_enable_x64))
    if key in _SAMPLERS:
        _SAMPLERS.move_to_end(key)
        return _SAMPLERS[key]
    sampler = NutsSampler(shapes, fixed_names, n_interfaces, num_warmup=num_warmup,
                          num_chains=num_chains, target_accept=target_accept)
    _SAMPLERS[key] = sampler
    while len(_SAMPLERS) > MAX_SAMPLERS:
        _SAMPLERS.popitem(last=False)
    return sampler


def sample_uncached(shapes, fixed_names, n_interfaces, key, starts, inverse_mass, args, *,
                    num_warmup, num_samples, num_chains, target_accept, block, postprocess,
                    on_block=None, progress_bar=False):
    """The same run with a numpyro `MCMC` made for this fit (compiled for this fit alone);
    returns as `NutsSampler.run`, the draws on the base scale (`postprocess`)."""
    model = make_model(dict(shapes), tuple(fixed_names), tuple(n_interfaces))
    kernel = NUTS(model, dense_mass=True, target_accept_prob=target_accept,
                  inverse_mass_matrix=inverse_mass)
    return run_in_blocks(kernel, key, starts, args, num_warmup=num_warmup, num_samples=num_samples,
                         num_chains=num_chains, block=block, postprocess=postprocess,
                         on_block=on_block, progress_bar=progress_bar)


def run_in_blocks(kernel, key, init_params, args=(), *, num_warmup, num_samples, num_chains, block,
                  postprocess=None, on_block=None, progress_bar=False):
    """NUTS `kernel` (a numpyro `NUTS` of a model, or of a `potential_fn` with `args` empty)
    through a numpyro `MCMC`: warm-up from `init_params` (one per chain), then `num_samples`
    draws per chain in blocks of `block`, the chains vectorised; `on_block(done, total)` after
    the warm-up (`done = 0`) and each block. A `KeyboardInterrupt` (Ctrl-C) ends the run and
    keeps the blocks finished. **Returns:** as `NutsSampler.run` (the draws through
    `postprocess`, the model's base scale, where given)."""
    mcmc = MCMC(kernel, num_warmup=num_warmup, num_samples=block, num_chains=num_chains,
                chain_method="vectorized", progress_bar=progress_bar,
                **({} if postprocess is None else {"postprocess_fn": postprocess}))
    parts, flags, done = [], [], 0
    try:
        key, warm_key = jax.random.split(key)
        mcmc.warmup(warm_key, *args, init_params=init_params)
        if on_block is not None:
            on_block(0, num_samples)
        while done < num_samples:
            mcmc.num_samples = min(mcmc.num_samples, num_samples - done)
            key, run_key = jax.random.split(key)
            mcmc.run(run_key, *args, extra_fields=("diverging",))
            parts.append({k: np.asarray(v) for k, v in
                          mcmc.get_samples(group_by_chain=True).items()})
            flags.append(np.asarray(mcmc.get_extra_fields(group_by_chain=True)["diverging"]))
            mcmc.post_warmup_state = mcmc.last_state
            done += mcmc.num_samples
            if on_block is not None:
                on_block(done, num_samples)
    except KeyboardInterrupt:
        where = f"after {done} of {num_samples} draws per chain" if done else "in the warm-up"
        interrupted = f"interrupted {where}"
    else:
        interrupted = None
    return _joined(parts, flags, interrupted)
