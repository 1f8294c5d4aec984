"""The gallery's picture scraper: the PNG files an example's code wrote.

The gallery's examples draw with dentopo's own ``render_*`` functions, which
write picture files (``screenshot="signed.png"``) rather than matplotlib
figures.  After each code block, sphinx-gallery calls :func:`png_files`, which
moves every PNG that block wrote beside the example into the gallery's images
(so the examples folder stays clean) and returns the reST that shows them.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from sphinx_gallery.scrapers import figure_rst


def png_files(block, block_vars, gallery_conf) -> str:
    folder = Path(block_vars["src_file"]).parent
    written = sorted(folder.glob("*.png"), key=lambda p: p.stat().st_mtime)
    images = []
    for picture, target in zip(written, block_vars["image_path_iterator"], strict=False):
        shutil.move(picture, target)
        images.append(target)
    return figure_rst(images, gallery_conf["src_dir"])
