"""The figures' Agg canvas: the pixels of matplotlib's own canvas with each text at its origin
rounded to a whole pixel, each font's line metrics read once per figure and each text's image
kept (issue 28: the demo's figures laid text out ~380 times and drew ~1,400 glyphs)."""

from __future__ import annotations

import sys

import matplotlib
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg
from matplotlib.figure import Figure

from fretbem.output import canvas, figures
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run


class _SnappedRenderer(RendererAgg):
    """matplotlib's own Agg renderer drawing each plain text at its origin rounded to a whole
    pixel (where matplotlib before 3.11 put a text's image)."""

    def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        if not ismath:
            x, y = round(x), round(y)
        return super().draw_text(gc, x, y, s, prop, angle, ismath, mtext)


class SnappedCanvas(FigureCanvasAgg):
    """The plain Agg canvas with :class:`_SnappedRenderer`."""

    def get_renderer(self):
        width, height = self.get_width_height(physical=True)
        key = width, height, self.figure.dpi
        if self._lastKey != key:
            self.renderer = _SnappedRenderer(width, height, self.figure.dpi)
            self._lastKey = key
        return self.renderer


#: the canvas whose pixels the figures' canvas draws: with the text images (3.11), the plain
#: canvas with whole-pixel text origins; otherwise the plain canvas
PLAIN = SnappedCanvas if canvas.GLYPH_LAYOUTS else FigureCanvasAgg


#: where two glyphs' edges share a pixel the figures' canvas blends their combined coverage
#: once, Agg each glyph in turn: the colour differs by rounding, measured at most 4 levels on
#: 0.13 % of a figure's pixels (unhinted bold text rotated by 30 degrees); none elsewhere
SHARED_EDGE_LEVELS, SHARED_EDGE_SHARE = 6, 0.002


def assert_same_drawing(ours: np.ndarray, plain: np.ndarray) -> None:
    """The pixels equal but for glyph edges shared by two glyphs of one text (at most
    SHARED_EDGE_LEVELS apart, on at most SHARED_EDGE_SHARE of the pixels)."""
    assert ours.shape == plain.shape
    apart = np.abs(ours.astype(int) - plain).max(axis=2)
    assert apart.max() <= SHARED_EDGE_LEVELS
    assert np.count_nonzero(apart) <= SHARED_EDGE_SHARE * apart.size


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
    plain = _pixels(fig, PLAIN)
    assert_same_drawing(ours, plain)


@pytest.mark.parametrize(
    "make", [figures.traction_figure, figures.displacement_figure, figures.stick_slip_figure]
)
def test_the_demo_figures_draw_the_plain_canvas_pixels(results, make):
    fig = make(results)
    ours = _pixels(fig, canvas.FigureCanvas)
    plain = _pixels(fig, PLAIN)
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
        ours, plain = drawn(canvas.FigureCanvas, fresh), drawn(PLAIN, fresh)
        assert_same_drawing(ours, plain)


#: the tests of the kept text images need the matplotlib (3.11+) whose text drawing they replay
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
def test_texts_kept_across_draws_draw_the_plain_canvas_pixels(hinting):
    """The text images kept from earlier draws (another hinting, the same texts) give the
    plain canvas's pixels: the hinting, the features, the language, the angle and the
    antialiasing are in the key."""
    for drawn in ("no_hinting", hinting):  # the images of the first draw are kept
        with matplotlib.rc_context({"text.hinting": drawn}):
            fig = _hinted_texts()
            ours = _pixels(fig, canvas.FigureCanvas)
            plain = _pixels(fig, SnappedCanvas)
        assert_same_drawing(ours, plain)


def _ink_box(pixels: np.ndarray) -> np.ndarray:
    rows, cols = np.nonzero(pixels[..., :3].min(axis=2) < 128)
    return np.array([rows.min(), rows.max(), cols.min(), cols.max()])


@glyph_layouts
@pytest.mark.parametrize("angle", [0.0, 90.0, 33.3, -40.0])
@pytest.mark.parametrize("where", [(0.3, 0.4), (0.5137, 0.4629), (0.28712, 0.60033)])
def test_a_text_sits_within_half_a_pixel_of_the_plain_canvas_text(angle, where):
    """A text's image lands where the plain canvas draws the text, give or take the rounding
    of its origin: its ink box within one pixel, the same ink within 2 %."""
    fig = Figure(figsize=(3.0, 2.0), dpi=100)
    fig.text(*where, "traction (MPa) −1 µm", rotation=angle)
    ours, plain = _pixels(fig, canvas.FigureCanvas), _pixels(fig, FigureCanvasAgg)
    assert np.abs(_ink_box(ours) - _ink_box(plain)).max() <= 1
    ink = [float((255 - p[..., :3].astype(int)).sum()) for p in (ours, plain)]
    assert ink[0] == pytest.approx(ink[1], rel=0.02)


@glyph_layouts
def test_a_text_drawn_again_is_rendered_once(monkeypatch):
    """A second figure with the same texts renders none of them again."""
    kept = []
    monkeypatch.setattr(canvas, "_TEXTS", {})
    fig = _hinted_texts()
    canvas.FigureCanvas(fig)
    fig.canvas.draw()
    kept.append(len(canvas._TEXTS))
    again = _hinted_texts()
    canvas.FigureCanvas(again)
    again.canvas.draw()
    kept.append(len(canvas._TEXTS))
    assert kept[0] > 10 and kept[1] == kept[0]


@glyph_layouts
def test_the_text_table_starts_again_when_full(monkeypatch):
    """The table holds at most TEXTS_KEPT images; the pixels do not change."""
    monkeypatch.setattr(canvas, "_TEXTS", {})
    monkeypatch.setattr(canvas, "TEXTS_KEPT", 3)
    fig = _hinted_texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    assert 1 <= len(canvas._TEXTS) <= 3
    assert_same_drawing(ours, _pixels(fig, SnappedCanvas))


@glyph_layouts
def test_glyphs_kept_by_their_pen_fraction_draw_the_plain_canvas_pixels(monkeypatch):
    """Glyphs rendered once and placed again at the same fraction of a pixel (the table
    emptied when full too) draw what rendering each on its own draws."""
    for kept in (3, canvas.GLYPHS_KEPT):
        monkeypatch.setattr(canvas, "_TEXTS", {})
        monkeypatch.setattr(canvas, "_GLYPHS", {})
        monkeypatch.setattr(canvas, "GLYPHS_KEPT", kept)
        fig = _hinted_texts()
        ours = _pixels(fig, canvas.FigureCanvas)
        assert 1 <= len(canvas._GLYPHS) <= kept
        assert_same_drawing(ours, _pixels(fig, SnappedCanvas))


@glyph_layouts
def test_a_blank_text_draws_nothing():
    """A text of blanks has no ink: no image is made and the pixels are the plain canvas's."""
    fig = Figure(figsize=(2.0, 1.0), dpi=100)
    fig.text(0.5, 0.5, "   ")
    fig.text(0.2, 0.2, "a")
    np.testing.assert_array_equal(_pixels(fig, canvas.FigureCanvas), _pixels(fig, SnappedCanvas))


def test_a_matplotlib_without_the_glyph_layout_draws_its_text_itself(monkeypatch):
    """Where matplotlib lays text out otherwise (before 3.11), Agg's own ``draw_text`` runs:
    nothing is kept, the pixels are the plain canvas's."""
    monkeypatch.setattr(canvas, "GLYPH_LAYOUTS", False)
    monkeypatch.setattr(canvas, "_TEXTS", {})
    fig = _texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    assert canvas._TEXTS == {}
    np.testing.assert_array_equal(ours, _pixels(fig, FigureCanvasAgg))
