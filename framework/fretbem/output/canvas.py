"""An Agg canvas whose renderer looks each font up once per draw and lays each text out once.

matplotlib (3.11) lays a text out with its font's ascent, descent and line gap, read from
the font file's OS/2 or hhea table on every layout: a font search and two table reads per
text, each time a text is measured or drawn (a tick label three times per figure); and
each text measured or drawn searches its font again. The demo's three figures lay text out
~380 times and measure or draw it ~200 times with ~10 distinct fonts and sizes. This
renderer keeps, for the length of one draw, each font's line metrics (the answer to
matplotlib's ``_get_font_height_metrics`` question, which its PDF and PostScript renderers
answer too, computed as matplotlib computes it) and each font object (its
``_prepare_font``, the same lookup). matplotlib 3.11's Agg measures a text with one
libraqm shaping (``FT2Font.set_text``, ~0.3 ms), shapes it again to draw it
(``FT2Font._layout``) and renders and blends every glyph on its own (~1,400 glyphs in the
demo, ~40 us each). This renderer keeps each plain text for the process (tick labels and
axis labels repeat: 57 distinct of the demo's 128 drawn texts) from one shaping: its measure,
the same numbers, and its glyphs drawn into one image by FreeType
(``draw_glyphs_to_bitmap``), blended once at the text's origin rounded to a whole pixel, as
matplotlib drew every text before 3.11. Layouts are the plain canvas's; each glyph sits
within a pixel or two of where Agg 3.11 puts it, with the same ink
(``tests/framework/output/test_canvas.py``). Turned text and mathtext are Agg's own; a
matplotlib that lays text out otherwise (before 3.11) draws it as before. matplotlib is
imported by the caller (:func:`fretbem.output.figures._figure`).
"""

from __future__ import annotations

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


#: each text as FreeType and libraqm lay it out and draw it (:func:`text_image`), by (font,
#: size, resolution, text, hinting, features, language, antialiasing): the same input gives
#: the same glyphs, and tick labels and axis labels repeat within and across figures
_TEXTS: dict = {}
#: the texts kept at most (the table starts again when full; the demo keeps ~70)
TEXTS_KEPT = 4096
#: whether this matplotlib lays text out as :class:`_Renderer` expects (3.11: libraqm's
#: shaping behind ``FT2Font.set_text`` and ``_layout``, glyphs rendered one by one by
#: ``_draw_text_glyphs_and_boxes``); otherwise Agg's own text drawing runs
GLYPH_LAYOUTS = (
    RenderMode is not None
    and hasattr(FT2Font, "_layout")
    and hasattr(FT2Font, "draw_glyphs_to_bitmap")
    and hasattr(RendererAgg, "_draw_text_glyphs_and_boxes")
)


@attrs.frozen(eq=False)
class TextImage:
    """A text laid out once: matplotlib's measure of it (advance width, height and descent,
    1/64 pixels; the ink's overhang to the left of the origin) and its glyphs drawn at their
    sub-pixel pens into one coverage image (0-255, FreeType's padding included)."""

    width: int
    height: int
    descent: int
    left: int
    coverage: np.ndarray


def text_image(font, size: float, dpi: float, text: str, flags, features=None, language=None,
               antialiased: bool = True) -> TextImage:  # fmt: skip
    """The :class:`TextImage` of ``text`` in ``font`` (which the caller set to ``size``
    points at ``dpi``), remembered: one ``set_text`` (libraqm's shaping, ~0.3 ms) answers
    matplotlib's measure of the text and draws it (``draw_glyphs_to_bitmap``: the glyphs of
    a title in ~0.05 ms), where Agg 3.11 shapes it again to draw it and renders its glyphs
    one by one."""
    key = (font, size, dpi, text, flags, features, language, antialiased)
    try:
        found = _TEXTS.get(key)
    except TypeError:  # features or language of a kind that cannot be a key
        key, found = None, None
    if found is None:
        font.set_text(text, 0.0, flags=flags, features=features, language=language)
        width, height = font.get_width_height()
        left, _ = font.get_bitmap_offset()
        descent = font.get_descent()
        font.draw_glyphs_to_bitmap(antialiased=antialiased)
        coverage = np.array(font.get_image())  # a copy: the font draws the next text there
        found = TextImage(width, height, descent, left, coverage)
        if key is not None:
            if len(_TEXTS) >= TEXTS_KEPT:
                _TEXTS.clear()
            _TEXTS[key] = found
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

    def get_text_width_height_descent(self, s, prop, ismath):
        """Agg's measure of a plain text, from its kept :class:`TextImage`."""
        if ismath or not GLYPH_LAYOUTS:
            return super().get_text_width_height_descent(s, prop, ismath)
        font = self._prepare_font(prop)
        text = text_image(font, prop.get_size_in_points(), self.dpi, s, get_hinting_flag())
        return text.width / 64, text.height / 64, text.descent / 64

    def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        """A plain text's kept image blended once, at its origin rounded to a whole pixel and
        turned about it by Agg, as matplotlib drew every text before 3.11 (where 3.11 shapes
        the text again and renders and blends each glyph on its own)."""
        if ismath or angle % 360 or not GLYPH_LAYOUTS:  # turned text: Agg turns each glyph
            return super().draw_text(gc, x, y, s, prop, angle, ismath, mtext)
        text = text_image(
            self._prepare_font(prop), prop.get_size_in_points(), self.dpi, s, get_hinting_flag(),
            mtext.get_fontfeatures() if mtext is not None else None,
            mtext.get_language() if mtext is not None else None, gc.get_antialiased(),
        )  # fmt: skip
        x, y = round(x + text.left / 64), round(y + text.descent / 64)
        self._renderer.draw_text_image(text.coverage, x, y + 1, 0, gc)

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
