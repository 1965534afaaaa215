"""An Agg canvas whose renderer looks each font up once per draw and draws each text once.

matplotlib (3.11) lays a text out with its font's ascent, descent and line gap, read from
the font file's OS/2 or hhea table on every layout: a font search and two table reads per
text, each time a text is measured or drawn (a tick label three times per figure); and
each text measured or drawn searches its font again. The demo's three figures lay text out
~380 times and measure or draw it ~200 times with ~10 distinct fonts and sizes. This
renderer keeps, for the length of one draw, each font's line metrics (the answer to
matplotlib's ``_get_font_height_metrics`` question, which its PDF and PostScript renderers
answer too, computed as matplotlib computes it) and each font object (its
``_prepare_font``, the same lookup). Drawing a text, matplotlib 3.11's Agg has FreeType and
libraqm lay its glyphs out (~0.3 ms for a title), then renders and blends every glyph on
its own (~1,400 in the demo, ~40 us each); this renderer composes each text's glyphs into
one coverage image kept for the process (tick labels and axis labels repeat: 57 distinct of
the demo's 128 drawn texts) and blends it once, at the text's origin rounded to a whole
pixel, as matplotlib placed text before 3.11. The pixels are the plain canvas's for text so
placed, but for glyph edges two glyphs share (``tests/framework/output/test_canvas.py``).
A matplotlib that does not lay text out so (before 3.11) draws it as before. matplotlib is
imported by the caller (:func:`fretbem.output.figures._figure`).
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg, get_hinting_flag
from matplotlib.font_manager import FontProperties, fontManager, get_font

try:  # matplotlib 3.11: glyphs laid out by libraqm (FT2Font._layout), rendered one by one
    from matplotlib.ft2font import FT2Font, RenderMode
except ImportError:  # an older matplotlib: Agg draws its text itself
    FT2Font = RenderMode = None

__all__ = ["FigureCanvas", "font_height_metrics"]

#: the font tables matplotlib reads a line's metrics from, in its order: (table, line gap,
#: ascent, descent keys)
HEIGHT_TABLES = (
    ("OS/2", "sTypoLineGap", "sTypoAscender", "sTypoDescender"),
    ("hhea", "lineGap", "ascent", "descent"),
)


def font_height_metrics(prop: FontProperties, dpi: float) -> tuple:
    """(ascent, descent, line gap) in pixels of the font ``prop`` finds at ``dpi``, from the
    first table the font has (``matplotlib.text.Text._get_layout``'s reading); (None, None,
    None) if it has neither, and matplotlib then measures the text "lp" instead."""
    font = get_font(fontManager._find_fonts_by_props(prop))
    for name, gap, ascent, descent in HEIGHT_TABLES:
        table = font.get_sfnt_table(name)
        if table is None:
            continue
        scale = 1 / font.get_sfnt_table("head")["unitsPerEm"] * prop.get_size_in_points()
        scale = scale * dpi / 72
        return table[ascent] * scale, -table[descent] * scale, table[gap] * scale
    return None, None, None


#: each text's glyphs as FreeType and libraqm lay them out and render them, composed into one
#: coverage image, by (font, size, resolution, text, hinting, features, language, angle,
#: antialiasing): the same input gives the same image, and tick labels and axis labels repeat
#: within and across figures
_TEXTS: dict = {}
#: the text images kept at most (the table starts again when full; the demo keeps ~60)
TEXTS_KEPT = 4096
#: each glyph's coverage as FreeType renders it, by font, size, resolution, glyph, hinting,
#: rendering mode, rotation and the pen's position within its pixel (1/64 pixel): texts
#: repeat glyphs at the same fraction (a third of the demo's ~1,100 glyphs)
_GLYPHS: dict = {}
#: the glyphs kept at most (the table starts again when full)
GLYPHS_KEPT = 16384
#: whether this matplotlib draws text as :meth:`_Renderer.draw_text` replays it (3.11's
#: glyph layout and loop); otherwise Agg's own ``draw_text`` runs
GLYPH_LAYOUTS = (
    RenderMode is not None
    and hasattr(FT2Font, "_layout")
    and hasattr(RendererAgg, "_draw_text_glyphs_and_boxes")
)


@attrs.frozen(eq=False)
class TextImage:
    """A text's glyphs composed as Agg would draw them one by one at a whole-pixel origin:
    the coverage (0-255) of each pixel, and where its top-left pixel sits from the origin
    (columns right, rows down)."""

    coverage: np.ndarray
    left: int
    top: int


def text_image(font, size: float, dpi: float, text: str, flags, features, language,
               angle: float, antialiased: bool) -> TextImage | None:  # fmt: skip
    """The :class:`TextImage` of ``text`` in ``font`` at ``size`` points and ``dpi``, rotated
    by ``angle`` degrees, remembered; None for a text without ink (blanks only).

    Every glyph is rendered as matplotlib 3.11's Agg renders it for a text whose origin is
    a whole pixel: its pen at the same 1/64 pixel, the same transform, hinting and
    rendering mode. Where two glyphs' pixels meet, the coverages combine as Agg's blending
    of two draws does (a + b - ab)."""
    key = (font, size, dpi, text, flags, features, language, angle, antialiased)
    try:
        found = _TEXTS.get(key, False)
    except TypeError:  # features or language of a kind that cannot be a key
        key, found = None, False
    if found is not False:
        return found
    items = font._layout(text, flags=flags, features=features, language=language)
    cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    matrix = (0x10000 * np.array([[cos, -sin], [sin, cos]])).round().astype(int)
    mode = RenderMode.NORMAL if antialiased else RenderMode.MONO
    turn = tuple(matrix.ravel().tolist())
    pieces = []
    for item in items:  # item.y is upwards, as FreeType's
        pen = (round(0x40 * (item.x * cos - item.y * sin)),
               round(0x40 * (item.x * sin + item.y * cos)))  # fmt: skip
        glyph = _glyph(item.ft_object, size, dpi, item.glyph_index, flags, mode, matrix, turn, pen)
        if glyph is not None:
            left, top, buffer = glyph
            pieces.append((left + (pen[0] >> 6), -top - (pen[1] >> 6), buffer))
    image = None
    if pieces:
        left = min(col for col, _, _ in pieces)
        top = min(row for _, row, _ in pieces)
        right = max(col + b.shape[1] for col, _, b in pieces)
        bottom = max(row + b.shape[0] for _, row, b in pieces)
        coverage = np.zeros((bottom - top, right - left), np.uint16)
        for col, row, buffer in pieces:
            view = coverage[row - top : row - top + buffer.shape[0],
                            col - left : col - left + buffer.shape[1]]  # fmt: skip
            if not antialiased:  # monochrome glyphs cover 0 or 1
                buffer = buffer * 0xFF
            view += buffer - (view * buffer + 127) // 255
        image = TextImage(coverage.astype(np.uint8), left, top)
    if key is not None:
        if len(_TEXTS) >= TEXTS_KEPT:
            _TEXTS.clear()
        _TEXTS[key] = image
    return image


def _glyph(font, size, dpi, index, flags, mode, matrix, turn, pen):
    """(left, top, coverage) of glyph ``index`` of ``font`` rendered with its pen at ``pen``
    (1/64 pixels, y upwards) turned by ``matrix`` (``turn`` its key), its bitmap's corner
    counted from the pen's whole pixel; None if it has no ink. Remembered by the pen's
    fraction: a whole-pixel shift of the pen moves the bitmap by whole pixels and changes
    nothing else (FreeType translates the hinted outline)."""
    key = (font, size, dpi, index, flags, mode, turn, pen[0] & 63, pen[1] & 63)
    found = _GLYPHS.get(key, False)
    if found is False:
        font.set_size(size, dpi)
        font._set_transform(matrix, [pen[0] & 63, pen[1] & 63])
        bitmap = font._render_glyph(index, flags, mode)
        buffer = bitmap.buffer
        found = (bitmap.left, bitmap.top, np.array(buffer, np.uint16)) if buffer.size else None
        if len(_GLYPHS) >= GLYPHS_KEPT:
            _GLYPHS.clear()
        _GLYPHS[key] = found
    return found


class _Renderer(RendererAgg):
    """Agg's renderer with each font and its line metrics remembered from the start of a
    draw (keyed by the font's properties, as matplotlib's own text-metrics cache is)."""

    def __init__(self, width: float, height: float, dpi: float):
        super().__init__(width, height, dpi)
        self._font_heights: dict = {}
        self._fonts: dict = {}

    def clear(self) -> None:
        """Clear the pixels and the tables: every draw starts with it (a font family in the
        rcParams may have changed between two draws of one figure)."""
        super().clear()
        self._font_heights.clear()
        self._fonts.clear()

    def _prepare_font(self, font_prop: FontProperties):
        """The FT2Font of ``font_prop`` cleared and set to its size, as Agg's own method, the
        font searched once per draw."""
        font = self._fonts.get(font_prop)
        if font is None:
            font = get_font(fontManager._find_fonts_by_props(font_prop))
            self._fonts[font_prop.copy()] = font
        font.clear()
        font.set_size(font_prop.get_size_in_points(), self.dpi)
        return font

    def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        """Agg's ``draw_text`` as one image per text (:func:`text_image`), kept for the
        process, its origin rounded to a whole pixel (as matplotlib before 3.11 placed each
        text): one blend instead of one per glyph, no glyph rendered twice."""
        if ismath or not GLYPH_LAYOUTS:
            return super().draw_text(gc, x, y, s, prop, angle, ismath, mtext)
        image = text_image(
            self._prepare_font(prop), prop.get_size_in_points(), self.dpi, s,
            get_hinting_flag(), mtext.get_fontfeatures() if mtext is not None else None,
            mtext.get_language() if mtext is not None else None, angle, gc.get_antialiased(),
        )  # fmt: skip
        if image is not None:  # draw_text_image's y is downwards, at the image's bottom row
            col, row = round(x) + image.left, round(y) + image.top
            self._renderer.draw_text_image(
                image.coverage, col, row + image.coverage.shape[0], 0, gc
            )

    def _get_font_height_metrics(self, prop: FontProperties) -> tuple:
        found = self._font_heights.get(prop)
        if found is None:
            found = font_height_metrics(prop, self.dpi)
            self._font_heights[prop.copy()] = found  # a snapshot: the text's may change
        return found


class FigureCanvas(FigureCanvasAgg):
    """A FigureCanvasAgg drawing with :class:`_Renderer` (the same pixels, fewer font-file
    reads); everything else, saving included, is Agg's."""

    def get_renderer(self) -> RendererAgg:
        """The renderer of the figure's current size and DPI (a new one when they change),
        as :meth:`FigureCanvasAgg.get_renderer`."""
        width, height = self.get_width_height(physical=True)
        key = width, height, self.figure.dpi
        if self._lastKey != key:
            self.renderer = _Renderer(width, height, self.figure.dpi)
            self._lastKey = key
        return self.renderer
