"""One figure style for every builder: mathtext labels, readable fonts, PNG and SVG.

Builders draw with matplotlib (Agg), label axes with :data:`LABELS` (mathtext with units),
mark the values the thesis prints for a figure with :func:`mark_thesis` (one marker style
everywhere, from the catalogue by :func:`printed_values`), and write with :func:`save`,
which always writes ``<path>.png`` and ``<path>.svg`` with a tight bounding box (no clipped
titles or legends).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

#: Resolution of the PNG: at 100 % zoom a 6.4 in wide figure is ~770 px, labels ~13 px.
DPI = 120
#: Font sizes (points) readable at 100 % in the report.
RC = {
    "font.size": 11, "axes.titlesize": 11, "axes.labelsize": 11, "legend.fontsize": 9,
    "xtick.labelsize": 10, "ytick.labelsize": 10, "figure.titlesize": 12,
    "axes.grid": True, "grid.alpha": 0.3, "svg.fonttype": "none", "savefig.dpi": DPI,
    "lines.linewidth": 1.3,
}
#: Axis labels (mathtext, units in brackets; dimensionless quantities have none).
LABELS = {
    "lambda_A": r"stretch of circle A $\lambda_A$",
    "lambda_P": r"pre-stretch $\lambda_P$",
    "phibar": r"normalised voltage $\bar\Phi$",
    "r_over_ra": r"radius $R/R_A$",
    "lambda_12": r"stretch $\lambda_1$, $\lambda_2$",
    "lambda_3": r"thickness stretch $\lambda_3$",
    "sigma1_mu": r"radial stress of circle A $\sigma_1^{(A)}/\mu$",
    "c": r"permittivity coefficient $c$",
    "lambda_max": r"maximum stretch $\lambda_{\max}$",
    "phibar_at_max": r"$\bar\Phi$ at $\lambda_{\max}$",
    "kH": r"$kH$",
    "lam_cr": r"critical stretch $\lambda_{cr}$",
    "Dhat": r"normalised displacement $\hat D$",
    "xi": r"anisotropy $\xi$",
    "lambda_uniaxial": r"uniaxial stretch $\lambda$",
    "stress_difference_kPa": r"$\sigma_{11}-\sigma_{22}$ [kPa]",
    "phibar_ch5": r"normalised voltage $\Phi/t_0\,\sqrt{\varepsilon/\mu}$",
    "deflection_mm": r"centre deflection $w$ [mm]",
    "h_over_t0": r"in-plane mesh size $h/t_0$",
    "phibar_cr": r"critical normalised voltage $\bar\Phi_{cr}$",
}
#: How the thesis' printed values are drawn (one style for every figure).
THESIS_STYLE = {"marker": "*", "ms": 11, "mfc": "none", "mec": "crimson", "mew": 1.4,
                "ls": "none", "zorder": 5}


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend with the debench style applied."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update(RC)
    return plt


def save(fig, path: Path | str) -> list[Path]:
    """Write ``fig`` as ``<path>.png`` and ``<path>.svg`` (tight box), close it.

    ``path`` is given without suffix (a ``.png``/``.svg`` suffix is replaced). Returns the
    two paths, PNG first.
    """
    import matplotlib.pyplot as plt

    path = Path(path)
    if path.suffix in (".png", ".svg"):
        path = path.with_suffix("")
    path.parent.mkdir(parents=True, exist_ok=True)
    out = []
    for suffix in (".png", ".svg"):
        p = path.with_name(path.name + suffix)
        fig.savefig(p, dpi=DPI, bbox_inches="tight")
        out.append(p)
    plt.close(fig)
    return out


def printed_values(figure: str) -> list[Any]:
    """Catalogue entries (claims) with a numeric printed value whose source names
    ``figure`` (e.g. ``"3.5"``; ``"4.2"`` matches ``"4.2(a)-(c), 4.4"``)."""
    import re

    from debench.reference import catalogue

    out = []
    for e in catalogue.load():
        figs = str(e.source.get("figure", ""))
        if e.kind != "claim" or not isinstance(e.value, int | float) \
                or isinstance(e.value, bool):
            continue
        if figure in re.findall(r"\d+\.\d+", figs) and "-" not in figs.split("(")[0]:
            out.append(e)
    return out


def mark_thesis(ax, x, y, label: str = "thesis (printed value)") -> None:
    """Draw the thesis' printed value(s) at ``(x, y)`` in the one thesis style."""
    ax.plot(x, y, label=label, **THESIS_STYLE)


def printed_value(entry_id: str) -> float:
    """The value the thesis prints for catalogue entry ``entry_id``."""
    from debench.reference import catalogue

    entry = catalogue.by_id(catalogue.load())[entry_id]
    return float(entry.value)
