"""The figures' Agg canvas: the pixels of matplotlib's own canvas, with each font's line
metrics read once per figure (issue 28: the demo's figures laid text out ~380 times)."""

from __future__ import annotations

import sys

import matplotlib
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from fretbem.output import canvas, figures
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run


def _pixels(fig, canvas_class) -> np.ndarray:
    canvas_class(fig)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba()).copy()


def _texts() -> Figure:
    """Text of every kind a figure lays out: several sizes and weights, multi-line,
    rotated, mathtext, a legend, tick labels, a suptitle."""
    fig = Figure(figsize=(5.0, 3.2), dpi=100)
    ax = fig.add_subplot()
    ax.plot([0, 1, 2], [3, -1, 2], "o-", label="line, p=2")
    ax.set_title("two\nlines, $\\sigma_B$ = 20 MPa", fontsize=9)
    ax.set_xlabel("x / a")
    ax.set_ylabel("traction (MPa)", rotation=70)
    ax.text(0.5, 0.5, "bold, large", fontsize=15, fontweight="bold", rotation=30)
    ax.text(1.5, 0.0, "serif\nthree\nlines", family="serif", linespacing=1.6)
    fig.suptitle("Suptitle µm −g")
    fig.legend(loc="lower center", fontsize=8)
    return fig


@pytest.fixture(scope="module")
def results():
    return [run(cattaneo_mindlin(basis=b, pairs=21)) for b in ("nurbs", "lagrange2")]


def test_text_of_every_kind_draws_the_plain_canvas_pixels():
    fig = _texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    plain = _pixels(fig, FigureCanvasAgg)
    np.testing.assert_array_equal(ours, plain)


@pytest.mark.parametrize(
    "make", [figures.traction_figure, figures.displacement_figure, figures.stick_slip_figure]
)
def test_the_demo_figures_draw_the_plain_canvas_pixels(results, make):
    fig = make(results)
    ours = _pixels(fig, canvas.FigureCanvas)
    plain = _pixels(fig, FigureCanvasAgg)
    np.testing.assert_array_equal(ours, plain)


def test_figures_are_made_on_this_canvas_without_pyplot(monkeypatch):
    """The command line's figures (no pyplot loaded) are drawn on this canvas; with pyplot in
    use, pyplot's own figures are kept (notebooks, galleries)."""
    monkeypatch.delitem(sys.modules, "matplotlib.pyplot", raising=False)
    assert isinstance(figures._figure((2.0, 1.0)).canvas, canvas.FigureCanvas)


def test_each_font_is_read_once_per_draw(monkeypatch):
    """Where matplotlib asks the renderer for a font's line metrics (3.11 on), the canvas
    reads each font and size once per draw, not once per text laid out."""
    reads = []
    read = canvas.font_height_metrics

    def counted(prop, dpi):
        reads.append((prop.get_size_in_points(), prop.get_family()[0], prop.get_weight()))
        return read(prop, dpi)

    monkeypatch.setattr(canvas, "font_height_metrics", counted)
    fig = _texts()
    canvas.FigureCanvas(fig)
    fig.canvas.draw()
    asked = len(getattr(fig.canvas.get_renderer(), "_font_heights", {}))
    if not reads:
        pytest.skip("this matplotlib does not ask the renderer for a font's line metrics")
    assert len(reads) == len(set(reads)) == asked
    first = list(reads)
    fig.canvas.draw()  # a new draw reads them again, once each
    assert sorted(reads[len(first) :]) == sorted(first)


def test_a_font_family_changed_between_two_draws_draws_as_the_plain_canvas():
    """The tables live for one draw: a figure drawn again after the rcParams name another
    sans-serif font gives the plain canvas's pixels for the same two draws (whose own
    text-metrics cache keeps the first font's sizes), and a fresh figure the fresh plain
    canvas's."""

    def drawn(canvas_class, fresh: bool) -> np.ndarray:
        fig = _texts()
        canvas_class(fig)
        if not fresh:
            fig.canvas.draw()
        with matplotlib.rc_context({"font.sans-serif": ["DejaVu Sans Mono", "DejaVu Sans"]}):
            fig.canvas.draw()
        return np.asarray(fig.canvas.buffer_rgba()).copy()

    for fresh in (False, True):
        ours, plain = drawn(canvas.FigureCanvas, fresh), drawn(FigureCanvasAgg, fresh)
        np.testing.assert_array_equal(ours, plain)


#: the tests of the kept glyph layouts need the matplotlib (3.11+) whose text drawing they replay
glyph_layouts = pytest.mark.skipif(
    not canvas.GLYPH_LAYOUTS, reason="this matplotlib draws its text itself (before 3.11)"
)


def _hinted_texts() -> Figure:
    """Texts the glyph loop draws apart: not antialiased (monochrome glyphs), rotated by
    odd angles, one text twice: with and without font features, and a language (libraqm's
    inputs)."""
    fig = _texts()
    ax = fig.axes[0]
    plain = ax.text(0.2, 2.0, "mono 0.5 −1", fontsize=11, rotation=12.5)
    plain.set_antialiased(False)
    plain.set_language("en")
    ax.text(1.0, -0.5, "ffi fl AV", rotation=-40)  # ligatures and kerning: libraqm's
    featured = ax.text(1.0, 1.0, "ffi fl AV", rotation=-40)  # the same text without them
    featured.set_fontfeatures(["-liga", "-kern"])
    return fig


@glyph_layouts
@pytest.mark.parametrize("hinting", ["no_hinting", "default", "force_autohint"])
def test_layouts_kept_across_draws_draw_the_plain_canvas_pixels(hinting):
    """The glyph layouts kept from earlier draws (another hinting, the same texts) give the
    plain canvas's pixels: the hinting, the features and the language are in the key."""
    for drawn in ("no_hinting", hinting):  # the layouts of the first draw are kept
        with matplotlib.rc_context({"text.hinting": drawn}):
            fig = _hinted_texts()
            ours = _pixels(fig, canvas.FigureCanvas)
            plain = _pixels(fig, FigureCanvasAgg)
        np.testing.assert_array_equal(ours, plain)


@glyph_layouts
def test_a_text_drawn_again_is_laid_out_once(monkeypatch):
    """A second figure with the same texts lays none of them out again."""
    laid_out = []
    monkeypatch.setattr(canvas, "_LAYOUTS", {})
    fig = _hinted_texts()
    canvas.FigureCanvas(fig)
    fig.canvas.draw()
    laid_out.append(len(canvas._LAYOUTS))
    again = _hinted_texts()
    canvas.FigureCanvas(again)
    again.canvas.draw()
    laid_out.append(len(canvas._LAYOUTS))
    assert laid_out[0] > 10 and laid_out[1] == laid_out[0]


@glyph_layouts
def test_the_layout_table_starts_again_when_full(monkeypatch):
    """The table holds at most LAYOUTS_KEPT layouts; the pixels do not change."""
    monkeypatch.setattr(canvas, "_LAYOUTS", {})
    monkeypatch.setattr(canvas, "LAYOUTS_KEPT", 3)
    fig = _hinted_texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    assert 1 <= len(canvas._LAYOUTS) <= 3
    np.testing.assert_array_equal(ours, _pixels(fig, FigureCanvasAgg))


def test_a_matplotlib_without_the_glyph_layout_draws_its_text_itself(monkeypatch):
    """Where matplotlib lays text out otherwise (before 3.11), Agg's own ``draw_text`` runs:
    nothing is kept, the pixels are the plain canvas's."""
    monkeypatch.setattr(canvas, "GLYPH_LAYOUTS", False)
    monkeypatch.setattr(canvas, "_LAYOUTS", {})
    fig = _texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    assert canvas._LAYOUTS == {}
    np.testing.assert_array_equal(ours, _pixels(fig, FigureCanvasAgg))
