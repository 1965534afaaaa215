"""The demo's figures with three families: titles that fit, few ticks, unhinted glyphs only
while saving (the figures' cost is per tick and per glyph; issue 28)."""

from __future__ import annotations

import matplotlib
import pytest

from fretbem.output import figures
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

PAIRS = 31  # 3 k + 1: every family (the cubic lagrange3 too)
FAMILIES = ("nurbs", "lagrange2", "lagrange3")


@pytest.fixture(scope="module")
def results(cubic_plugin):
    """The reference cycle in the three families the demo draws (the third from the example
    plugin package, installed for the session if it is not installed)."""
    return [run(cattaneo_mindlin(basis=b, pairs=PAIRS)) for b in FAMILIES]


def _drawn(fig):
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def test_traction_titles_of_three_families_fit_their_panels(results):
    """Each step panel's two-line title (loads, every family's max e_q) stays inside the
    figure and clear of its neighbours' titles (they ran into each other before)."""
    fig = figures.traction_figure(results)
    renderer = _drawn(fig)
    boxes = [ax.title.get_window_extent(renderer) for ax in fig.axes]
    width = fig.bbox.width
    for ax, box in zip(fig.axes, boxes, strict=True):
        assert all(name in ax.get_title() for name in FAMILIES)
        assert box.x0 >= 0 and box.x1 <= width, ax.get_title()
    for k, a in enumerate(boxes):
        for b in boxes[k + 1 :]:
            assert not a.overlaps(b)


@pytest.mark.parametrize(
    "make", [figures.traction_figure, figures.displacement_figure, figures.stick_slip_figure]
)
def test_panels_carry_at_most_tick_bins_intervals(results, make):
    """Every axis has at most TICK_BINS + 1 major ticks in view (matplotlib's default puts
    9-11 on a panel; each tick is five artists and a label to draw)."""
    fig = make(results)
    _drawn(fig)
    for ax in fig.axes:
        for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
            lo, hi = min(lo, hi), max(lo, hi)
            shown = [t for t in axis.get_majorticklocs() if lo <= t <= hi]
            assert 2 <= len(shown) <= figures.TICK_BINS + 1, (make.__name__, shown)


def test_glyphs_are_unhinted_only_while_the_files_are_written(results, tmp_path, monkeypatch):
    """save_figures draws without hinting and leaves the user's rcParams as they were; a
    hinting the user chose is kept."""
    seen = []
    draw = matplotlib.backends.backend_agg.FigureCanvasAgg.draw

    def spy(canvas):
        seen.append(matplotlib.rcParams["text.hinting"])
        return draw(canvas)

    monkeypatch.setattr(matplotlib.backends.backend_agg.FigureCanvasAgg, "draw", spy)
    before = matplotlib.rcParams["text.hinting"]
    figures.save_figures(results, tmp_path / "a")
    assert seen and set(seen) == {"no_hinting"}
    assert matplotlib.rcParams["text.hinting"] == before
    seen.clear()
    with matplotlib.rc_context({"text.hinting": "native"}):
        figures.save_figures(results, tmp_path / "b")
    assert seen and set(seen) == {"native"}


def _ticks(fig):
    """Each axis's drawn ticks: (location, label) in view, after a draw."""
    _drawn(fig)
    return [
        [(t.get_loc(), t.label1.get_text()) for t in axis._update_ticks()]
        for ax in fig.axes
        for axis in (ax.xaxis, ax.yaxis)
    ]


@pytest.mark.parametrize(
    "make", [figures.traction_figure, figures.displacement_figure, figures.stick_slip_figure]
)
def test_ticks_in_view_draw_the_same_ticks_with_fewer_made(results, make):
    """Before a file is drawn every automatic axis keeps only the ticks in its view: the
    same locations and labels are drawn, and no tick beyond the view is made."""
    fig = make(results)
    before = _ticks(fig)
    made = sum(len(axis.get_majorticklocs()) for ax in fig.axes for axis in (ax.xaxis, ax.yaxis))
    figures._ticks_in_view(fig)
    assert _ticks(fig) == before
    kept = sum(len(axis.get_majorticklocs()) for ax in fig.axes for axis in (ax.xaxis, ax.yaxis))
    assert kept == sum(len(axis) for axis in before) < made


def test_ticks_in_view_keep_an_offset_formatter():
    """An axis whose labels need an offset or a scale ("1e-5", "+1e3") keeps its formatter:
    fixed labels would lose the offset text; the others get their labels fixed once."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import ScalarFormatter

    fig = Figure()
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(2, 2, 1)
    ax.plot([1000.001, 1000.002, 1000.004], [1e-5, 3e-5, 2e-5])
    ax.locator_params(nbins=figures.TICK_BINS)
    plain = fig.add_subplot(2, 2, 4)
    plain.plot([0, 1], [0, 2])
    plain.locator_params(nbins=figures.TICK_BINS)
    fig.canvas.draw()
    offsets = (ax.xaxis.get_major_formatter().get_offset(),
               ax.yaxis.get_major_formatter().get_offset())  # fmt: skip
    assert all(offsets)
    before = _ticks(fig)
    figures._ticks_in_view(fig)
    assert _ticks(fig) == before
    assert isinstance(ax.xaxis.get_major_formatter(), ScalarFormatter)
    assert isinstance(ax.yaxis.get_major_formatter(), ScalarFormatter)
    assert [ax.xaxis.get_major_formatter().get_offset(),
            ax.yaxis.get_major_formatter().get_offset()] == list(offsets)  # fmt: skip
    # the labels fixed (matplotlib keeps them in a FixedFormatter or, 3.11, a FuncFormatter)
    assert not isinstance(plain.xaxis.get_major_formatter(), ScalarFormatter)
    assert not isinstance(plain.yaxis.get_major_formatter(), ScalarFormatter)
