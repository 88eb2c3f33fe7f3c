"""The read-out's glyphs in a video: each rendered by FreeType once, then reused.

matplotlib's Agg renderer (3.10 and later) renders every glyph of every string anew:
it sets the font's size and transform and rasterises the glyph at its position, then
composites the bitmap. A video's read-out draws the same few characters at the same
sizes in every frame. FreeType works in 1/64 pixel: a glyph moved by whole pixels
rasterises to the same bitmap, moved. :func:`reuse_glyphs` makes one renderer keep each
glyph's bitmap by its font, size, transform and position within its pixel, and
composite the kept bitmap at the glyph's whole-pixel position: the frames are the same
to the bit (``tests/visual``), at less CPU per frame.

It replaces the drawing of glyphs on that one renderer only, and only where this
matplotlib draws glyphs as described (its private ``_draw_text_glyphs_and_boxes``, with
the FreeType calls it makes); elsewhere the renderer is left as it is.
"""

from __future__ import annotations

import inspect
import math
import types
from typing import Any

import numpy as np

__all__ = ["reuse_glyphs"]

_PARAMETERS = ["gc", "x", "y", "angle", "glyphs", "boxes"]


def _supported(renderer: Any) -> bool:
    """Whether ``renderer`` draws glyphs one by one as :func:`reuse_glyphs` expects."""
    from matplotlib import ft2font

    method = getattr(type(renderer), "_draw_text_glyphs_and_boxes", None)
    if method is None or not hasattr(renderer, "_renderer"):
        return False
    if not all(hasattr(ft2font.FT2Font, name) for name in ("_set_transform", "_render_glyph")):
        return False
    return list(inspect.signature(method).parameters)[1:] == _PARAMETERS


def reuse_glyphs(renderer: Any) -> bool:
    """Let ``renderer`` (a matplotlib Agg renderer) keep and reuse its glyph bitmaps for
    as long as it lives; True if it does (False: this matplotlib draws otherwise, and
    the renderer is unchanged)."""
    if not _supported(renderer):
        return False
    from matplotlib.backends.backend_agg import get_hinting_flag
    from matplotlib.ft2font import RenderMode

    draw_boxes = type(renderer)._draw_text_glyphs_and_boxes
    kept: dict[tuple[Any, ...], tuple[np.ndarray, int, int]] = {}

    def draw(self: Any, gc: Any, x: float, y: float, angle: float, glyphs: Any, boxes: Any) -> None:
        # the arithmetic of matplotlib's own method, the glyph's position split into whole
        # pixels (>> 6) and 1/64 pixels (& 63); y is downwards, FreeType's y upwards
        cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
        flags = get_hinting_flag()
        smooth = gc.get_antialiased()
        height = self.height
        for font, size, index, slant, extend, dx, dy in glyphs:
            px = round(0x40 * (x + dx * cos - dy * sin))
            py = round(0x40 * (height - y + dx * sin + dy * cos))
            key = (
                font,
                size,
                self.dpi,
                index,
                slant,
                extend,
                angle,
                flags,
                smooth,
                px & 63,
                py & 63,
            )
            glyph = kept.get(key)
            if glyph is None:
                font.set_size(size, self.dpi)
                matrix = 0x10000 * np.array([[cos, -sin], [sin, cos]])
                font._set_transform(
                    (matrix @ [[extend, extend * slant], [0, 1]]).round().astype(int),
                    [px & 63, py & 63],
                )
                bitmap = font._render_glyph(
                    index, flags, RenderMode.NORMAL if smooth else RenderMode.MONO
                )
                buffer = np.array(bitmap.buffer)  # FreeType's own is reused by the next glyph
                if not smooth:
                    buffer *= 0xFF
                glyph = kept[key] = (buffer, bitmap.left, bitmap.top)
            buffer, left, top = glyph
            self._renderer.draw_text_image(
                buffer, left + (px >> 6), int(height) - (top + (py >> 6)) + buffer.shape[0], 0, gc
            )
        draw_boxes(self, gc, x, y, angle, (), boxes)

    renderer._draw_text_glyphs_and_boxes = types.MethodType(draw, renderer)
    return True
