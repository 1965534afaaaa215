"""An Agg canvas whose renderer looks each font up once per draw.

matplotlib (3.11) lays a text out with its font's ascent, descent and line gap, read from
the font file's OS/2 or hhea table on every layout: a font search and two table reads per
text, each time a text is measured or drawn (a tick label three times per figure); and
each text measured or drawn searches its font again. The demo's three figures lay text out
~380 times and measure or draw it ~200 times with ~10 distinct fonts and sizes. This
renderer keeps, for the length of one draw, each font's line metrics (the answer to
matplotlib's ``_get_font_height_metrics`` question, which its PDF and PostScript renderers
answer too, computed as matplotlib computes it) and each font object (its
``_prepare_font``, the same lookup). Drawing a text, Agg has FreeType and libraqm lay its
glyphs out (~0.3 ms for a title) and forms the glyph transform's matrix for every glyph
(~1,400 in the demo); this renderer keeps each layout for the process (tick labels and
axis labels repeat: 57 distinct of the demo's 128 drawn texts) and forms the matrix once
per text. The pixels are the same (``tests/framework/output/test_canvas.py`` compares
them with the plain canvas's). A matplotlib that does not ask the question lays text out
as before. matplotlib is imported by the caller (:func:`fretbem.output.figures._figure`).
"""

from __future__ import annotations

import math

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


#: each text's glyphs as FreeType and libraqm lay them out, by (font, size, resolution, text,
#: hinting, features, language): the same input gives the same glyphs, and tick labels and
#: axis labels repeat within and across figures
_LAYOUTS: dict = {}
#: the layouts kept at most (the table starts again when full)
LAYOUTS_KEPT = 4096
#: whether this matplotlib draws text as :meth:`_Renderer.draw_text` replays it (3.11's
#: glyph layout and loop); otherwise Agg's own ``draw_text`` runs
GLYPH_LAYOUTS = (
    RenderMode is not None
    and hasattr(FT2Font, "_layout")
    and hasattr(RendererAgg, "_draw_text_glyphs_and_boxes")
)


def _layout(font, size: float, dpi: float, text: str, flags, features, language):
    """``font._layout`` of ``text`` (``font`` set to ``size`` at ``dpi``), remembered."""
    key = (font, size, dpi, text, flags, features, language)
    try:
        items = _LAYOUTS.get(key)
    except TypeError:  # features or language of a kind that cannot be a key
        return font._layout(text, flags=flags, features=features, language=language)
    if items is None:
        items = font._layout(text, flags=flags, features=features, language=language)
        if len(_LAYOUTS) >= LAYOUTS_KEPT:
            _LAYOUTS.clear()
        _LAYOUTS[key] = items
    return items


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
        """Agg's ``draw_text`` with each text's glyph layout remembered (:func:`_layout`)."""
        if ismath or not GLYPH_LAYOUTS:
            return super().draw_text(gc, x, y, s, prop, angle, ismath, mtext)
        font = self._prepare_font(prop)
        size = prop.get_size_in_points()
        items = _layout(
            font, size, self.dpi, s, get_hinting_flag(),
            mtext.get_fontfeatures() if mtext is not None else None,
            mtext.get_language() if mtext is not None else None,
        )  # fmt: skip
        glyphs = ((item.ft_object, size, item.glyph_index, 0, 1, item.x, item.y) for item in items)
        self._draw_text_glyphs_and_boxes(gc, x, y, angle, glyphs, [])

    def _draw_text_glyphs_and_boxes(self, gc, x, y, angle, glyphs, boxes):
        """Agg's glyph loop with the transform's matrix formed once per text, not per glyph
        (the same matrix and pen positions: plain text is neither slanted nor stretched);
        mathtext's rules and any slanted or stretched glyph go to Agg's own loop."""
        glyphs = list(glyphs)
        if boxes or any(slant != 0 or extend != 1 for _, _, _, slant, extend, _, _ in glyphs):
            return super()._draw_text_glyphs_and_boxes(gc, x, y, angle, glyphs, boxes)
        cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
        matrix = (0x10000 * np.array([[cos, -sin], [sin, cos]])).round().astype(int)
        flags = get_hinting_flag()
        antialiased = gc.get_antialiased()
        mode = RenderMode.NORMAL if antialiased else RenderMode.MONO
        height = self.height
        for font, size, glyph_index, _, _, dx, dy in glyphs:  # dy is upwards
            font.set_size(size, self.dpi)
            pen = [round(0x40 * (x + dx * cos - dy * sin)),
                   round(0x40 * (height - y + dx * sin + dy * cos))]  # fmt: skip
            font._set_transform(matrix, pen)
            bitmap = font._render_glyph(glyph_index, flags, mode)
            buffer = bitmap.buffer
            if not antialiased:
                buffer *= 0xFF
            self._renderer.draw_text_image(
                buffer, bitmap.left, int(height) - bitmap.top + buffer.shape[0], 0, gc
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
