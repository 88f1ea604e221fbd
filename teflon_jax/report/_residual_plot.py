"""Residual maps: a residual against several regressors, on axes that one outlier does not set."""

import numpy as np

ROBUST_PERCENTILES = (1.0, 99.0)
"""The residual axis spans these percentiles of the residual (padded), not its extremes."""


def robust_limits(values, percentiles=ROBUST_PERCENTILES, pad: float = 0.05) -> tuple:
    """Axis limits from the `percentiles` of the finite `values`, widened by `pad` of their
    span on each side (a span of zero becomes +-1e-12 about the value).

    **Returns:** (low, high).
    """
    finite = np.asarray(values, dtype=float)
    finite = finite[np.isfinite(finite)]
    if finite.size == 0:
        return (-1.0, 1.0)
    low, high = np.percentile(finite, percentiles)
    span = max(high - low, 1e-12)
    return (float(low - pad * span), float(high + pad * span))


def in_length_unit(label: str, values, length) -> tuple:
    """(label, values) of a regressor in the length unit `length` = (name, size in m): a
    label ending in "[m]" or "[m/s]" (SI) is rewritten with `length`'s name and its values
    divided by its size; other labels are returned as they are (`length` None: SI kept)."""
    if length is None:
        return label, values
    for si, unit in (("[m]", f"[{length[0]}]"), ("[m/s]", f"[{length[0]}/s]")):
        if label.endswith(si):
            return label[:-len(si)] + unit, np.asarray(values, dtype=float) / length[1]
    return label, values


def residual_maps(columns, residual, groups, *, ylabel: str, title: str, ncols: int = 3, length=None):
    """A panel per regressor of `residual` against it, its axis at `robust_limits` of the
    residual of all `groups`; points beyond are drawn at the edge as triangles and counted in
    the axis label.

    **Arguments:**

    - `columns`: list of (axis label, regressor values), one panel each.
    - `residual`: the residual at each sample.
    - `groups`: list of (boolean mask, colour, legend label) of the samples to draw.
    - `ylabel`, `title`: the residual's axis label and the figure's title.
    - `length`: (name, size in m) of the length unit of the output (`--units`): regressors
      labelled in m or m/s are drawn in it (`in_length_unit`); None keeps SI.

    **Returns:** the `matplotlib.figure.Figure` (not saved).
    """
    from matplotlib.figure import Figure

    residual = np.asarray(residual, dtype=float)
    shown = np.zeros(residual.shape, dtype=bool)
    for mask, _, _ in groups:
        shown |= np.asarray(mask, dtype=bool)
    low, high = robust_limits(residual[shown])
    beyond = int(np.count_nonzero(shown & ((residual < low) | (residual > high))))
    rows = -(-len(columns) // ncols)
    figure = Figure(figsize=(4.0 * ncols, 3.25 * rows), layout="constrained")
    axes = np.atleast_1d(figure.subplots(rows, ncols, squeeze=False)).ravel()
    for ax, (label, x) in zip(axes, columns):
        label, x = in_length_unit(label, x, length)
        x = np.asarray(x)
        for mask, colour, name in groups:
            mask = np.asarray(mask, dtype=bool)
            ax.plot(x[mask], np.clip(residual[mask], low, high), ".", ms=2, color=colour,
                    label=name)
            for edge, marker in ((high, "^"), (low, "v")):
                out = mask & ((residual > high) if edge == high else (residual < low))
                ax.plot(x[out], np.full(int(out.sum()), edge), marker, ms=4, color=colour)
        ax.axhline(0, color="k", lw=0.6)
        ax.set_ylim(low, high)
        ax.set_xlabel(label, fontsize=8)
        ax.grid(alpha=0.3)
    for ax in axes[len(columns):]:
        ax.axis("off")
    for ax in axes[::ncols]:
        ax.set_ylabel(f"{ylabel}\naxis: {ROBUST_PERCENTILES[0]:g}st-{ROBUST_PERCENTILES[1]:g}th "
                      f"percentile; {beyond} beyond (triangles)", fontsize=8)
    axes[0].legend(fontsize=8, markerscale=4)
    figure.suptitle(title, fontsize=9)
    return figure
