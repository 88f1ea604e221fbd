"""Statistics of a nested Monte Carlo, K bearings (posterior draws) x M motions.

The variance of a peak X over the runs splits by the law of total variance into the part the
motions cause and the part the bearing's uncertainty causes,

    Var[X] = E_k[ Var_m(X | k) ] + Var_k[ E_m(X | k) ],

with population moments over the runs that converged (bearing k weighted by its share
n_k / n of them, 1 / K when every run converged), so the two parts add up to the total to
rounding. The bearing share is Var_k[E_m(X | k)] / Var[X]. All bearings run on the same M
motions, so the bearing part compares the bearings on one set of motions; it still holds
the part of the motions' spread that changes from bearing to bearing.

The qth percentile of a peak (e.g. the 95th of the base displacement) gets a band from the
bearing uncertainty: the spread over the K draws of the per-bearing qth percentile over the
motions, as the percentiles `band` (e.g. 5 and 95) of those K values.
"""

import numpy as np


def _nested(peaks, converged):
    x = np.asarray(peaks, dtype=float)
    if x.ndim != 2:
        raise ValueError(f"peaks: expected a (bearing, motion) array, got shape {x.shape}.")
    ok = np.ones(x.shape, bool) if converged is None else np.asarray(converged, bool)
    if ok.shape != x.shape:
        raise ValueError(f"converged: shape {ok.shape} differs from the peaks' {x.shape}.")
    return x, ok


def variance_split(peaks, converged=None) -> dict:
    """The law-of-total-variance split of the peaks of a nested run (module docstring).

    **Arguments:** `peaks` (K, M): bearing k's peak under motion m; `converged` (K, M) bool,
    the runs to use (default all).

    **Returns:** dict `total` Var[X] (over all used runs, computed directly), `motion`
    E_k[Var_m], `bearing` Var_k[E_m] (in the peak's units squared), `bearing_share`
    `bearing / total` (`None` when the total is 0), `n` runs and `n_bearings` bearings used
    (a bearing whose every run failed is left out).
    """
    x, ok = _nested(peaks, converged)
    counts = ok.sum(axis=1)
    keep = counts > 0
    x, ok, counts = x[keep], ok[keep], counts[keep]
    n = int(counts.sum())
    if n == 0:
        return {"total": None, "motion": None, "bearing": None, "bearing_share": None, "n": 0,
                "n_bearings": 0}
    weights = counts / n
    means = np.where(ok, x, 0.0).sum(axis=1) / counts
    within = np.where(ok, (x - means[:, None]) ** 2, 0.0).sum(axis=1) / counts
    mean = float(np.sum(weights * means))
    motion = float(np.sum(weights * within))
    bearing = float(np.sum(weights * (means - mean) ** 2))
    total = float(np.var(x[ok]))
    return {"total": total, "motion": motion, "bearing": bearing,
            "bearing_share": bearing / total if total > 0 else None, "n": n,
            "n_bearings": int(keep.sum())}


def percentile_band(peaks, converged=None, *, q: float = 95.0, band=(5.0, 95.0)) -> dict:
    """The qth percentile of a nested run's peaks with its band from the bearing uncertainty.

    **Arguments:** `peaks`, `converged` as `variance_split`; `q` [%] the percentile; `band`
    [%] (low, high) percentiles of the per-bearing values.

    **Returns:** dict `pooled` (qth percentile over all used runs), `per_bearing` (K,) list of
    each bearing's qth percentile over its motions (`None` for a bearing without a converged
    run), `median` of those, `band` [low, high] of them, `q`, `band_percentiles`.
    """
    low, high = (float(b) for b in band)
    if not 0 <= low < high <= 100 or not 0 <= q <= 100:
        raise ValueError(f"band: percentiles 0 <= low < high <= 100 and 0 <= q <= 100, got "
                         f"q = {q}, band = {band}.")
    x, ok = _nested(peaks, converged)
    per_bearing = [float(np.percentile(row[good], q)) if good.any() else None for row, good in zip(x, ok)]
    values = np.array([v for v in per_bearing if v is not None])
    empty = values.size == 0
    return {"pooled": None if empty else float(np.percentile(x[ok], q)),
            "per_bearing": per_bearing,
            "median": None if empty else float(np.median(values)),
            "band": None if empty else [float(np.percentile(values, low)), float(np.percentile(values, high))],
            "q": float(q), "band_percentiles": [low, high]}
