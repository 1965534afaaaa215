"""The figures' Agg canvas: matplotlib's own canvas's drawing, with each font's line metrics
read once per figure and each plain text laid out and drawn once per process, its image placed
at a whole pixel as matplotlib placed text before 3.11 (issue 28: the demo's figures laid
text out ~380 times and drew ~1,400 glyphs one by one)."""

from __future__ import annotations

import sys

import matplotlib
import matplotlib.text
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg
from matplotlib.figure import Figure

from fretbem.output import canvas, figures
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

#: a plain text's ink sits within this many pixels of Agg 3.11's (its centre of ink; the
#: origin rounded to a whole pixel and the glyphs drawn into one image, as before 3.11:
#: measured 1.25 unhinted and with the default hinting, 1.8 autohinted)
PLACED_WITHIN = 2.0
#: and carries the same ink, up to this share (measured 1.5 % antialiased, 7.4 % for
#: monochrome glyphs, which FreeType renders apart at whole and sub-pixel pens)
INK_SHARE = 0.1


def _text_boxes(fig, margin: int) -> list[tuple[slice, slice]]:
    """The pixel rows and columns of every text ``fig`` lays out, ``margin`` pixels wider
    each side (after a draw)."""
    renderer = fig.canvas.get_renderer()
    height = renderer.height
    boxes = []
    for text in fig.findobj(matplotlib.text.Text):
        if not text.get_visible() or not text.get_text():
            continue
        box = text.get_window_extent(renderer)
        rows = slice(max(int(height - box.y1) - margin, 0), max(int(height - box.y0) + margin, 0))
        cols = slice(max(int(box.x0) - margin, 0), max(int(box.x1) + margin, 0))
        boxes.append((rows, cols))
    return boxes


def _ink(pixels: np.ndarray) -> np.ndarray:
    return 255 - pixels[..., :3].min(axis=2).astype(int)


def assert_drawn_alike(fig, ours: np.ndarray, plain: np.ndarray, margin: int = 6) -> None:
    """``ours`` and ``plain`` (``fig`` drawn on two canvases) differ only where ``fig`` lays
    text out (``margin`` pixels around: autohinted glyphs reach 4.2 pixels beyond the box
    matplotlib measures); there, each text carries the same ink (INK_SHARE) and its centre
    of ink lies within PLACED_WITHIN pixels."""
    assert ours.shape == plain.shape
    apart = np.abs(ours.astype(int) - plain).max(axis=2) > 0
    boxes = _text_boxes(fig, margin)
    for rows, cols in boxes:
        apart[rows, cols] = False
    assert not apart.any(), f"{np.count_nonzero(apart)} pixels differ outside the texts"
    for rows, cols in boxes:
        mine, theirs = _ink(ours[rows, cols]), _ink(plain[rows, cols])
        # a neighbour's overrunning glyph may bring a pixel or two of ink into the box
        assert abs(mine.sum() - theirs.sum()) <= INK_SHARE * theirs.sum() + 2 * 255
        if mine.sum() < 4 * 255 or theirs.sum() < 4 * 255:
            continue
        for axis in (0, 1):  # the centre of ink along the rows, then the columns
            at = [np.average(np.arange(ink.shape[1 - axis]), weights=ink.sum(axis=axis))
                  for ink in (mine, theirs)]  # fmt: skip
            assert abs(at[0] - at[1]) <= PLACED_WITHIN


def _pixels(fig, canvas_class) -> np.ndarray:
    canvas_class(fig)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba()).copy()


def _texts() -> Figure:
    """Text of every kind a figure lays out: several sizes and weights, multi-line,
    rotated, mathtext, a legend, tick labels, a suptitle."""
    fig = Figure(figsize=(5.0, 3.2), dpi=100)
    ax = fig.add_subplot()
    fig.subplots_adjust(bottom=0.2, left=0.15)  # no text cut by the figure's edge
    ax.plot([0, 1, 2], [3, -1, 2], "o-", label="line, p=2")
    ax.set_title("two\nlines, $\\sigma_B$ = 20 MPa", fontsize=9)
    ax.set_xlabel("x / a")
    ax.set_ylabel("traction (MPa)", rotation=70)
    ax.text(0.5, 0.5, "bold, large", fontsize=15, fontweight="bold", rotation=30)
    ax.text(1.5, 0.0, "serif\nthree\nlines", family="serif", linespacing=1.6)
    fig.suptitle("Suptitle µm −g")
    fig.legend(loc="upper right", fontsize=8)  # clear of the texts: they are compared
    return fig


@pytest.fixture(scope="module")
def results():
    return [run(cattaneo_mindlin(basis=b, pairs=21)) for b in ("nurbs", "lagrange2")]


def test_text_of_every_kind_draws_as_the_plain_canvas():
    fig = _texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    plain = _pixels(fig, FigureCanvasAgg)
    assert_drawn_alike(fig, ours, plain)


@pytest.mark.parametrize(
    "make", [figures.traction_figure, figures.displacement_figure, figures.stick_slip_figure]
)
def test_the_demo_figures_draw_as_the_plain_canvas(results, make):
    fig = make(results)
    ours = _pixels(fig, canvas.FigureCanvas)
    plain = _pixels(fig, FigureCanvasAgg)
    assert_drawn_alike(fig, ours, plain)


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
    sans-serif font draws as the plain canvas for the same two draws (whose own text-metrics
    cache keeps the first font's sizes: the wider font's texts overrun their boxes, by up to
    a glyph), and a fresh figure as the fresh plain canvas."""

    def drawn(canvas_class, fresh: bool):
        fig = _texts()
        canvas_class(fig)
        if not fresh:
            fig.canvas.draw()
        with matplotlib.rc_context({"font.sans-serif": ["DejaVu Sans Mono", "DejaVu Sans"]}):
            fig.canvas.draw()
            return fig, np.asarray(fig.canvas.buffer_rgba()).copy()

    for fresh in (False, True):
        fig, ours = drawn(canvas.FigureCanvas, fresh)
        _, plain = drawn(FigureCanvasAgg, fresh)
        with matplotlib.rc_context({"font.sans-serif": ["DejaVu Sans Mono", "DejaVu Sans"]}):
            assert_drawn_alike(fig, ours, plain, margin=6 if fresh else 12)


#: the tests of the kept texts need the matplotlib (3.11+) whose text layout they replay
glyph_layouts = pytest.mark.skipif(
    not canvas.GLYPH_LAYOUTS, reason="this matplotlib draws its text itself (before 3.11)"
)


def _hinted_texts() -> Figure:
    """Texts the canvas keeps apart: not antialiased (monochrome glyphs), with and without
    font features (libraqm's ligatures and kerning), with a language; the same texts turned
    by odd angles (drawn glyph by glyph by Agg)."""
    fig = _texts()
    ax = fig.axes[0]
    for angle, row in ((0.0, 0.0), (12.5, 1.0), (-40.0, 2.0)):
        mono = ax.text(0.1, row, "mono 0.5 −1", fontsize=11, rotation=angle)
        mono.set_antialiased(False)
        mono.set_language("en")
        ax.text(1.0, row - 0.5, "ffi fl AV", rotation=angle)  # ligatures and kerning
        featured = ax.text(1.5, row - 0.5, "ffi fl AV", rotation=angle)  # neither
        featured.set_fontfeatures(["-liga", "-kern"])
    return fig


@glyph_layouts
@pytest.mark.parametrize("hinting", ["no_hinting", "default", "force_autohint"])
def test_texts_kept_across_draws_draw_as_the_plain_canvas(hinting):
    """The texts kept from earlier draws (another hinting, the same texts) draw as the plain
    canvas: the hinting, the features, the language and the antialiasing are in the key."""
    for drawn in ("no_hinting", hinting):  # the texts of the first draw are kept
        with matplotlib.rc_context({"text.hinting": drawn}):
            fig = _hinted_texts()
            ours = _pixels(fig, canvas.FigureCanvas)
            plain = _pixels(fig, FigureCanvasAgg)
            assert_drawn_alike(fig, ours, plain)


@glyph_layouts
@pytest.mark.parametrize("hinting", ["no_hinting", "default"])
def test_a_kept_text_measures_as_the_plain_renderer(hinting):
    """The kept measure of a text (width, height, descent) is Agg's, exactly: the layout of
    every figure is the plain canvas's."""
    ours, plain = canvas._Renderer(200, 100, 100), RendererAgg(200, 100, 100)
    props = [matplotlib.font_manager.FontProperties(size=size, weight=weight, family=family)
             for size, weight, family in ((10, "normal", "sans-serif"), (15, "bold", "serif"),
                                          (7.3, "normal", "monospace"))]  # fmt: skip
    with matplotlib.rc_context({"text.hinting": hinting}):
        for prop in props:
            for text in ("x / a", "step B: P = 100, Q = 18 N/mm", "µm −g ffi", " ", "lp"):
                for _ in range(2):  # laid out, then kept
                    assert ours.get_text_width_height_descent(text, prop, False) == (
                        plain.get_text_width_height_descent(text, prop, False)
                    )


@glyph_layouts
@pytest.mark.parametrize("angle", [0.0, 90.0, 33.3])
@pytest.mark.parametrize("where", [(0.3, 0.4), (0.5137, 0.4629), (0.28712, 0.60033)])
def test_a_text_sits_within_a_pixel_of_the_plain_canvas_text(angle, where):
    """A text lands where the plain canvas draws it, give or take the rounding of its
    origin: its ink's extent within PLACED_WITHIN pixels, the same ink within INK_SHARE."""
    fig = Figure(figsize=(3.0, 2.0), dpi=100)
    fig.text(*where, "traction (MPa) −1 µm", rotation=angle)
    ours, plain = _pixels(fig, canvas.FigureCanvas), _pixels(fig, FigureCanvasAgg)
    assert_drawn_alike(fig, ours, plain)


@glyph_layouts
def test_a_text_drawn_again_is_laid_out_once(monkeypatch):
    """A second figure with the same texts lays none of them out again."""
    laid_out = []
    monkeypatch.setattr(canvas, "_TEXTS", {})
    fig = _hinted_texts()
    canvas.FigureCanvas(fig)
    fig.canvas.draw()
    laid_out.append(len(canvas._TEXTS))
    again = _hinted_texts()
    canvas.FigureCanvas(again)
    again.canvas.draw()
    laid_out.append(len(canvas._TEXTS))
    assert laid_out[0] > 10 and laid_out[1] == laid_out[0]


@glyph_layouts
def test_the_text_table_starts_again_when_full(monkeypatch):
    """The table holds at most TEXTS_KEPT texts; the drawing does not change."""
    monkeypatch.setattr(canvas, "_TEXTS", {})
    monkeypatch.setattr(canvas, "TEXTS_KEPT", 3)
    fig = _hinted_texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    assert 1 <= len(canvas._TEXTS) <= 3
    monkeypatch.setattr(canvas, "TEXTS_KEPT", 4096)
    np.testing.assert_array_equal(ours, _pixels(fig, canvas.FigureCanvas))


@glyph_layouts
def test_a_blank_text_draws_nothing():
    """A text of blanks has no ink: the pixels are those of the figure without it."""
    fig = Figure(figsize=(2.0, 1.0), dpi=100)
    fig.text(0.2, 0.2, "a")
    without = _pixels(fig, canvas.FigureCanvas)
    fig.text(0.5, 0.5, "   ")
    np.testing.assert_array_equal(_pixels(fig, canvas.FigureCanvas), without)


def test_a_matplotlib_without_the_glyph_layout_draws_its_text_itself(monkeypatch):
    """Where matplotlib lays text out otherwise (before 3.11), Agg's own text drawing runs:
    nothing is kept, the pixels are the plain canvas's."""
    monkeypatch.setattr(canvas, "GLYPH_LAYOUTS", False)
    monkeypatch.setattr(canvas, "_TEXTS", {})
    fig = _texts()
    ours = _pixels(fig, canvas.FigureCanvas)
    assert canvas._TEXTS == {}
    np.testing.assert_array_equal(ours, _pixels(fig, FigureCanvasAgg))
