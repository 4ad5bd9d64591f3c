"""The thesis' printed values are drawn on the figures they belong to.

Every catalogue claim with a numeric printed value whose source names a figure
(:func:`debench.reference.figures.printed_values`) must be drawn with
:func:`~debench.reference.figures.mark_thesis` / :func:`~debench.reference.figures.mark_thesis_x`,
which tag the marker with the entry id (the SVG group id). Checked here on the figure
functions of the Chapter 3 and Chapter 4 builders, called on the curated datasets:

* every printed value of figure F is drawn on some figure of the chapter (a value about a
  quantity that F has no axis for, e.g. a threshold in ``c`` for the voltage-stretch curves
  of Fig. 3.5, is drawn where that quantity is an axis, Fig. 3.9);
* the file of F shows at least one of F's own printed values;
* every drawn marker names a catalogue entry with a numeric printed value.

The default run collects the markers from the figure objects (no rendering); ``--full``
renders the PNG/SVG files and reads the markers back from the SVG text.
"""

from __future__ import annotations

import pytest
from debench.reference import catalogue
from debench.reference import figures as F
from debench.reference.datasets import read_dataset

#: Thesis figure -> file stem written by the builders (reference/builders/ch3.py, ch4.py).
FIGURE_FILES = {
    "3.2": "fig3_2_annulus_stretches", "3.3": "fig3_3_thickness_stretch",
    "3.4": "fig3_4_voltage_stretch_c0", "3.5": "fig3_5_voltage_stretch_lamP_1p25",
    "3.6": "fig3_6_sigma1_lamP_3", "3.7": "fig3_7_failure_modes",
    "3.8": "fig3_8_voltage_stretch_c", "3.9": "fig3_9_c_sweep",
    "4.2": "fig4_2_curves_printed", "4.3": "fig4_3_areas", "4.4": "fig4_4_thin_limit",
    "4.5": "fig4_5_anisotropy", "4.6": "fig4_6_critical_D",
}
CH3_DATASETS = ("ch3_annulus_profiles", "ch3_voltage_stretch", "ch3_failure_points",
                "ch3_c_sweep")


_CATALOGUE: dict = {}


@pytest.fixture(autouse=True)
def _catalogue_read_once(monkeypatch):
    """The catalogue parsed once for the module (the figure code looks entries up often)."""
    entries = _CATALOGUE.setdefault("entries", catalogue.load())
    monkeypatch.setattr(catalogue, "load", lambda *a, **k: entries)


def marker_problems(drawn: dict[str, set[str]], chapter: str) -> list[str]:
    """What is wrong with the thesis markers of one chapter's figures.

    ``drawn``: file stem -> catalogue ids drawn on it. Returns readable problems (empty
    when every rule of the module docstring holds).
    """
    numeric = {e.id for fig in FIGURE_FILES for e in F.printed_values(fig)}
    everywhere = set().union(*drawn.values()) if drawn else set()
    problems = []
    for fig, stem in FIGURE_FILES.items():
        if not fig.startswith(chapter + "."):
            continue
        own = {e.id for e in F.printed_values(fig)}
        if not own:
            continue
        if stem not in drawn:
            problems.append(f"Fig. {fig}: file {stem} not written")
            continue
        for eid in sorted(own - everywhere):
            problems.append(f"Fig. {fig}: printed value {eid} drawn on no figure")
        if not own & drawn[stem]:
            problems.append(f"Fig. {fig}: {stem} shows none of its printed values "
                            f"{sorted(own)}")
    for stem, ids in drawn.items():
        for eid in sorted(ids - numeric):
            problems.append(f"{stem}: marker {eid!r} is not a numeric printed value of a "
                            "figure in the catalogue")
    return problems


def _collect_without_rendering(monkeypatch):
    """Replace :func:`figures.save` by one that records the thesis markers of each
    figure (from the artists' gids) and closes it without drawing."""
    drawn: dict[str, set[str]] = {}

    def record(fig, path):
        import matplotlib.pyplot as plt

        ids = set()
        for artist in fig.findobj():
            gid = artist.get_gid()
            if gid and gid.startswith(F.THESIS_GID):
                ids.update(gid[len(F.THESIS_GID):].split("+"))
        stem = str(path).rsplit("/", 1)[-1].removesuffix(".png").removesuffix(".svg")
        drawn[stem] = ids
        plt.close(fig)
        return []

    monkeypatch.setattr(F, "save", record)
    return drawn


def _ch3_figures(out):
    from debench.reference.builders import ch3

    return ch3.figures({n: read_dataset(n) for n in CH3_DATASETS}, out)


def _ch4_figures(out):
    from debench.reference.builders import ch4

    r = read_dataset
    return ch4.figures(out, r("ch4_fig4_2_curves"), r("ch4_fig4_5_curves"), r("ch4_limits"),
                       r("ch4_areas"), r("ch4_critical_dhat"))


def test_chapter3_figures_draw_every_printed_value(monkeypatch, tmp_path):
    drawn = _collect_without_rendering(monkeypatch)
    _ch3_figures(tmp_path)
    assert set(drawn) >= {s for f, s in FIGURE_FILES.items() if f.startswith("3.")}
    assert marker_problems(drawn, "3") == []
    # the figures the thesis prints numbers for, each with its own marker
    for fig in ("3.2", "3.3", "3.4", "3.5", "3.6", "3.7"):
        assert drawn[FIGURE_FILES[fig]], fig


def test_marker_check_fails_when_a_value_is_not_drawn():
    drawn = {stem: set() for stem in FIGURE_FILES.values()}
    problems = marker_problems(drawn, "3")
    assert any("ch3.annulus.lam1_interface_increase" in p for p in problems)
    assert any(p.startswith("Fig. 3.7:") for p in problems)
    drawn[FIGURE_FILES["3.8"]] = {"ch3.not_an_entry"}
    assert any("ch3.not_an_entry" in p for p in marker_problems(drawn, "3"))


def test_chapter4_figures_have_no_printed_numbers_in_the_catalogue():
    """The Chapter 4 figures carry no thesis marker because the thesis prints their values
    only in the figure images: the catalogue's entries for them have no numeric value (if
    one is added, the slow rendering test below requires it drawn)."""
    entries = catalogue.load()
    for fig in ("4.3", "4.4", "4.6"):
        assert F.printed_values(fig) == []
        image_only = [e for e in entries if fig in str(e.source.get("figure", ""))
                      and e.printed == "(figure image only)"]
        assert image_only, fig
        assert all(e.value is None for e in image_only), fig


def test_mark_thesis_tags_the_svg(tmp_path):
    plt = F.pyplot()
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    F.mark_thesis(ax, 0.5, 0.5, entries=["a.b", "c.d"], note="+1 %", arrow=True)
    F.mark_thesis_x(ax, 0.2, None, entries=["e.f"], note="x")
    F.mark_thesis(ax, 0.7, 0.7, None)    # no entry: not reported
    svg = F.save(fig, tmp_path / "t")[1].read_text()
    assert F.drawn_entries(svg) == {"a.b", "c.d", "e.f"}


@pytest.mark.slow
@pytest.mark.parametrize("chapter", ["3", "4"])
def test_rendered_svgs_show_every_printed_value(chapter, tmp_path):
    paths = (_ch3_figures if chapter == "3" else _ch4_figures)(tmp_path)
    drawn = {p.stem: F.drawn_entries(p.read_text()) for p in paths if p.suffix == ".svg"}
    assert all(p.with_suffix(".png").exists() for p in paths if p.suffix == ".svg")
    assert marker_problems(drawn, chapter) == []


def test_figures_are_not_written_inside_not_written(tmp_path):
    """`debench verify` rebuilds datasets only to compare them: inside
    ``figures.not_written()`` a builder's figure is closed without being rendered or
    written; outside it, both files are written."""
    from debench.reference.figures import not_written, pyplot, save

    plt = pyplot()
    with not_written():
        fig, _ = plt.subplots()
        assert save(fig, tmp_path / "a") == []
        assert not plt.fignum_exists(fig.number)
    assert not list(tmp_path.iterdir())
    fig, _ = plt.subplots()
    assert [p.name for p in save(fig, tmp_path / "a")] == ["a.png", "a.svg"]


def test_save_crops_both_formats_as_savefig_tight(tmp_path):
    """:func:`figures.save` lays the figure out once (:func:`figures.tight_bbox`) and writes
    both formats with that box: the PNG has the size ``savefig(bbox_inches="tight")`` gives
    (a legend outside the axes and a two-line title included), and the SVG the same box."""
    import re

    import matplotlib.image as mpimg

    plt = F.pyplot()

    def draw():
        fig, ax = plt.subplots(figsize=(5, 3))
        ax.semilogx([1e-2, 1, 10], [1, 2, 3], label="a long legend label")
        ax.set_title("a title\nover two lines")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2))
        return fig

    fig = draw()
    fig.savefig(tmp_path / "ref.png", dpi=F.DPI, bbox_inches="tight")
    fig.savefig(tmp_path / "ref.svg", dpi=F.DPI, bbox_inches="tight")
    plt.close(fig)
    png, svg = F.save(draw(), tmp_path / "new")
    assert mpimg.imread(png).shape == mpimg.imread(tmp_path / "ref.png").shape

    def size(p):
        head = p.read_text()[:2000]
        return [float(re.search(rf'{k}="([\d.]+)pt"', head).group(1)) for k in ("width", "height")]

    # the SVG's box from the PNG's layout: equal to a point (text metrics at 72 vs 120 dpi)
    assert size(svg) == pytest.approx(size(tmp_path / "ref.svg"), abs=1.0)


@pytest.mark.parametrize("chapter, stem", [
    ("ch5_wrinkling", "fig5_5_nonaxisymmetric_modes_r20"),
    ("ch5_imperfection", "fig5_4_imperfection_sensitivity_r20"),
])
def test_default_build_of_a_converged_only_study_draws_its_figure_from_curated_data(
        chapter, stem, tmp_path, capsys):
    """The radius/thickness 20 studies cost CPU hours, so the default `debench reproduce`
    does not recompute them; it still draws their figures, from the curated datasets
    (checksum verified), says so on stderr and on the figure, and writes no dataset; the
    line `debench reproduce` reports for the dataset names the command that recomputes it."""
    from debench.reference import builds

    paths = builds.builder(chapter).build(tmp_path, full=False)
    assert sorted(p.name for p in paths) == [f"{stem}.png", f"{stem}.svg"]
    assert not list(tmp_path.glob("*.nc"))
    err = capsys.readouterr().err
    assert f"{chapter}.nc: not recomputed by the default run" in err
    assert f"debench reproduce {chapter} --full" in err
    svg = (tmp_path / "figures" / f"{stem}.svg").read_text()
    assert f"Drawn from the curated dataset {chapter}.nc" in svg
    assert builds.not_recomputed([chapter, "ch3"], False) == [
        line for line in err.splitlines() if line.startswith(f"{chapter}.nc:")]
    assert builds.not_recomputed([chapter], True) == []


def test_converged_only_default_build_without_curated_data_says_so(tmp_path, monkeypatch,
                                                                   capsys):
    """Without the curated dataset (another data directory) the default build still
    succeeds: no figure, and stderr says why."""
    from debench.reference import builds, datasets

    monkeypatch.setenv(datasets.DATA_DIR_ENV, str(tmp_path / "empty"))
    assert builds.builder("ch5_wrinkling").build(tmp_path, full=False) == []
    assert "figure not drawn: no curated dataset" in capsys.readouterr().err
