"""The PNG writer: the pixels, size, DPI and text a reader gets back, against Pillow's."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image
from PIL.PngImagePlugin import PngInfo

from fretbem.output import figures
from fretbem.output.png import png_bytes, write_png


@pytest.mark.parametrize("shape", [(1, 1), (3, 7), (37, 5)])
def test_pixels_round_trip_as_pillows_own_file(tmp_path, shape):
    """Random RGBA pixels (every byte value, transparent ones included) read back equal, with
    the size, DPI and text of the file Pillow writes for them."""
    rgba = np.random.default_rng(1).integers(0, 256, (*shape, 4), dtype=np.uint8)
    path = write_png(tmp_path / "x.png", rgba, 72.0, {"Software": "fretbem test"})
    text = PngInfo()
    text.add_text("Software", "fretbem test")
    Image.fromarray(rgba).save(tmp_path / "pillow.png", dpi=(72.0, 72.0), pnginfo=text)
    with Image.open(path) as image, Image.open(tmp_path / "pillow.png") as pillow:
        assert image.mode == pillow.mode == "RGBA"
        assert image.size == (shape[1], shape[0])
        assert image.info == pillow.info
        assert image.info["Software"] == "fretbem test"
        np.testing.assert_array_equal(np.asarray(image), rgba)


@pytest.mark.parametrize("bad", [np.zeros((2, 2, 3), np.uint8), np.zeros((2, 2, 4), float)])
def test_anything_but_rgba_bytes_is_refused(bad):
    with pytest.raises(ValueError, match=r"\(rows, columns, 4\) uint8"):
        png_bytes(bad, 100.0)


def test_a_figure_reads_back_as_matplotlibs_own_png(tmp_path):
    """save_figures' writer gives the pixels, size, DPI and Software text of savefig's PNG."""
    fig = figures._figure((3.3, 2.17))  # 2.17 in x 100 dpi: 216.99999999999997 pixels
    ax = fig.add_subplot()
    ax.plot([0, 1, 2], [1, 0, 2], "o-", label="a line")
    ax.set_title("title, $\\sigma_B$")
    fig.legend()
    figures._save_png(fig, tmp_path / "ours.png")
    fig.savefig(tmp_path / "theirs.png", dpi=figures.DPI)
    assert (tmp_path / "ours.png").read_bytes().count(b"IDAT") == 1  # ours, not Pillow's
    with Image.open(tmp_path / "ours.png") as ours, Image.open(tmp_path / "theirs.png") as theirs:
        assert ours.size == theirs.size
        assert ours.info == theirs.info
        np.testing.assert_array_equal(np.asarray(ours), np.asarray(theirs))
