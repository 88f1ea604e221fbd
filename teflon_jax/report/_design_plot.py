"""Plot of a design sweep and the optimum found by gradients."""

from collections.abc import Mapping

from ..studies import DesignResult


def plot_design(sweep: Mapping, result: DesignResult, path, *, units: Mapping | None = None) -> None:
    """Sweep of the objective (1-D curve or 2-D contours) with the optimum marked, beside the
    trade-off of mean base shear against mean base displacement (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = units or {}
    names = list(sweep["grid"])
    scale = {n: units.get(n, (1.0, ""))[0] for n in names}
    label = {n: f"{n} [{units.get(n, (1.0, ''))[1]}]" for n in names}
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    if len(names) == 1:
        n = names[0]
        left.plot(sweep["grid"][n] / scale[n], sweep["objective"], "o-", label="grid sweep")
        left.plot(result.optimum[n] / scale[n], result.objective, "r*", ms=14, label="BFGS optimum")
        left.set_xlabel(label[n])
        left.set_ylabel("objective J")
        left.legend()
    else:
        a, b = names[:2]
        contour = left.contourf(sweep["grid"][a] / scale[a], sweep["grid"][b] / scale[b], sweep["objective"], 20)
        fig.colorbar(contour, ax=left, label="objective J")
        left.plot(result.optimum[a] / scale[a], result.optimum[b] / scale[b], "r*", ms=14)
        left.set_xlabel(label[a])
        left.set_ylabel(label[b])
    feasible = sweep["disp"] <= result.disp_limit
    right.scatter(sweep["disp"][~feasible] * 1e3, sweep["shear"][~feasible], c="0.6", s=12, label="grid, over limit")
    right.scatter(sweep["disp"][feasible] * 1e3, sweep["shear"][feasible], c="C0", s=12, label="grid, within limit")
    right.axvline(result.disp_limit * 1e3, color="k", ls="--", lw=0.8, label="displacement limit")
    right.plot(result.mean_disp * 1e3, result.mean_shear, "r*", ms=14, label="optimum")
    right.set_xlabel("mean smooth peak base displacement [mm]")
    right.set_ylabel("mean smooth peak base shear ratio [-]")
    right.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
