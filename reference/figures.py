"""One figure style for every builder: mathtext labels, readable fonts, PNG and SVG.

Builders draw with matplotlib (Agg), label axes with :data:`LABELS` (mathtext with units),
mark the values the thesis prints for a figure with :func:`mark_thesis` (one marker style
everywhere, from the catalogue by :func:`printed_values`), and write with :func:`save`,
which always writes ``<path>.png`` and ``<path>.svg`` with a tight bounding box (no clipped
titles or legends).
"""

from __future__ import annotations

import contextlib
import re
from contextvars import ContextVar
from pathlib import Path
from typing import Any

from debench.reference import catalogue

_WRITE = ContextVar("debench_write_figures", default=True)

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


@contextlib.contextmanager
def not_written():
    """Inside this block :func:`save` closes figures without rendering or writing them (for
    commands that rebuild datasets only to compare them, e.g. ``debench verify``)."""
    token = _WRITE.set(False)
    try:
        yield
    finally:
        _WRITE.reset(token)


def written() -> bool:
    """Whether :func:`save` writes figures here (false inside :func:`not_written`): builders
    skip drawing figures nobody will see."""
    return _WRITE.get()


def save(fig, path: Path | str) -> list[Path]:
    """Write ``fig`` as ``<path>.png`` and ``<path>.svg`` (tight box), close it.

    ``path`` is given without suffix (a ``.png``/``.svg`` suffix is replaced). Returns the
    two paths, PNG first; inside :func:`not_written` nothing is written and the list is
    empty.
    """
    import matplotlib.pyplot as plt

    if not _WRITE.get():
        plt.close(fig)
        return []
    path = Path(path)
    if path.suffix in (".png", ".svg"):
        path = path.with_suffix("")
    path.parent.mkdir(parents=True, exist_ok=True)
    bbox = tight_bbox(fig)
    out = []
    for suffix in (".png", ".svg"):
        p = path.with_name(path.name + suffix)
        fig.savefig(p, dpi=DPI, bbox_inches=bbox)
        out.append(p)
    plt.close(fig)
    return out


def footnote(fig, text: str | None) -> None:
    """Write ``text`` (e.g. where the data of the figure come from) in small grey type below
    the axes of ``fig``; nothing when ``text`` is None."""
    if text:
        fig.text(0.01, -0.01, text, fontsize=8, color="0.35", ha="left", va="top",
                 wrap=True)


def tight_bbox(fig):
    """The box (inches) that ``savefig(..., bbox_inches="tight")`` crops ``fig`` to at
    :data:`DPI`: the tight bounding box of every artist after one layout pass without
    rendering, padded by ``savefig.pad_inches``.

    :func:`save` computes it once and writes both formats with it, instead of one layout
    pass per format (the layout pass costs about as much as drawing the figure).
    """
    import matplotlib.pyplot as plt

    fig.set_dpi(DPI)
    fig.draw_without_rendering()
    return fig.get_tightbbox().padded(plt.rcParams["savefig.pad_inches"])


def printed_values(figure: str) -> list[Any]:
    """Catalogue entries (claims) with a numeric printed value whose source names
    ``figure`` (e.g. ``"3.5"``; ``"4.2"`` matches ``"4.2(a)-(c), 4.4"``)."""

    out = []
    for e in catalogue.load():
        figs = str(e.source.get("figure", ""))
        if e.kind != "claim" or not isinstance(e.value, int | float) \
                or isinstance(e.value, bool):
            continue
        if figure in re.findall(r"\d+\.\d+", figs) and "-" not in figs.split("(")[0]:
            out.append(e)
    return out


#: Prefix of the SVG group id of every drawn thesis value, followed by the catalogue entry
#: ids joined by ``+`` (so a test can find each drawn entry in the saved SVG).
THESIS_GID = "thesis:"


def thesis_gid(entries) -> str:
    """The SVG group id under which the printed values of catalogue ``entries`` are drawn."""
    return THESIS_GID + "+".join(entries)


def drawn_entries(svg_text: str) -> set[str]:
    """Catalogue entry ids drawn with :func:`mark_thesis` / :func:`mark_thesis_x` in an SVG."""
    out: set[str] = set()
    for gid in re.findall(r'id="' + re.escape(THESIS_GID) + r'([^"]+)"', svg_text):
        out.update(gid.split("+"))
    return out


def _note(ax, x, y, note, arrow=False, **kw) -> None:
    if arrow:
        kw["arrowprops"] = {"arrowstyle": "-", "color": THESIS_STYLE["mec"], "lw": 0.6,
                            "shrinkA": 1, "shrinkB": 6}
    ax.annotate(note, (x, y), xytext=kw.pop("xytext", (6, 5)), textcoords="offset points",
                fontsize=8, color=THESIS_STYLE["mec"], **kw)


def mark_thesis(ax, x, y, label: str | None = "thesis (printed value)", *,
                entries=(), note: str | None = None, note_offset=(6, 5),
                arrow: bool = False) -> None:
    """Draw the thesis' printed value(s) at ``(x, y)`` in the one thesis style.

    ``entries``: the catalogue ids whose printed values the marker shows (written as the
    SVG group id, see :func:`thesis_gid`); ``label=None`` keeps it out of the legend;
    ``note``: a short text (e.g. the printed percentage) ``note_offset`` points from a
    single marker, joined to it by a thin line when ``arrow``.
    """
    (line,) = ax.plot(x, y, label=label if label is not None else "_nolegend_",
                      **THESIS_STYLE)
    if entries:
        line.set_gid(thesis_gid(entries))
    if note:
        _note(ax, x, y, note, arrow, xytext=note_offset, ha="center" if arrow else "left")


def mark_thesis_x(ax, x: float, label: str | None = "thesis (printed value)", *,
                  entries=(), note: str | None = None, note_y: float = 0.03) -> None:
    """A printed value of the quantity on the x axis (e.g. a threshold): a vertical line
    in the thesis colour, with the same ``entries``/``note`` conventions as
    :func:`mark_thesis` (the note at height ``note_y``, in axes fraction)."""
    line = ax.axvline(x, color=THESIS_STYLE["mec"], ls="--", lw=1.2,
                      label=label if label is not None else "_nolegend_", zorder=4)
    if entries:
        line.set_gid(thesis_gid(entries))
    if note:
        _note(ax, x, note_y, note, xycoords=ax.get_xaxis_transform(), xytext=(4, 0))


def percent_note(entry_id: str, sign: str = "+") -> str:
    """``"+15.6 %"``: the printed percentage of ``entry_id`` as a marker note."""
    return f"{sign}{printed_value(entry_id):g} %"


def printed_value(entry_id: str) -> float:
    """The value the thesis prints for catalogue entry ``entry_id``."""
    entry = catalogue.by_id(catalogue.load())[entry_id]
    return float(entry.value)
