"""Small pictures of each specimen's signed map, off-screen, through one pyvista plotter.

One plotter draws every specimen in turn (its mesh replaced, the camera
reframed), which is several times faster than a plotter per picture.  Colours
are the project's diverging scale (:mod:`dentopo.figures`) with one set of
limits for the whole collection, so that thumbnails compare.  Pictures are
WebP (lossless would be larger than needed: quality 85) where Pillow writes it,
else PNG.
"""

from __future__ import annotations

import base64
import io

import numpy as np

from .._optional import PICTURES, require
from ..figures import ColorScale, camera_for
from ..figures._colors import lookup_table
from ..figures._render import _quiet_vtk_warnings
from ._payload import pack_mesh

#: Width and height of a thumbnail, pixels.
THUMBNAIL_SIZE = 192


def report_camera(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(3, 3) rows: the picture's right, up and towards-the-viewer axes, in mesh coordinates.

    The one place the report's camera is chosen: the occlusal view of every
    picture (:func:`dentopo.figures.camera_for`).  Thumbnails look along the
    third row; the 3D view's mesh is stored turned into these axes, so that the
    page's camera, looking down its z axis with y up, starts from the same view.
    """
    return camera_for(vertices, faces).rotation()


def _image_module():
    return require("PIL.Image", extra=PICTURES.extra, purpose=PICTURES.purpose)


def image_format() -> tuple[str, str]:
    """(Pillow's format name, MIME type) of the thumbnails: WebP where Pillow writes it."""
    features = require("PIL.features", extra=PICTURES.extra, purpose=PICTURES.purpose)
    if features.check("webp"):
        return "WEBP", "image/webp"
    return "PNG", "image/png"


class Thumbnailer:
    """Draws specimens one after another through one off-screen plotter; a context manager.

    Parameters
    ----------
    scale : ColorScale
        The collection's colour limits.
    size : int
        Width and height in pixels.
    """

    def __init__(self, scale: ColorScale, size: int = THUMBNAIL_SIZE):
        self.pv = PICTURES.require()
        self.image = _image_module()
        self.format, self.mime = image_format()
        self.scale = scale
        self.plotter = self.pv.Plotter(
            off_screen=True, window_size=(size, size), lighting="none", border=False
        )
        self.plotter.set_background("white")
        self.plotter.add_light(self.pv.Light(light_type="headlight"))
        self.plotter.enable_parallel_projection()  # every specimen framed alike
        self.plotter.show(auto_close=False)  # the first render, which resets the camera, now
        self.table = self.pv.LookupTable()
        self.table.values = lookup_table()
        self.table.scalar_range = scale.limits

    def __enter__(self) -> Thumbnailer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Release the plotter."""
        self.plotter.close()

    def render(self, vertices: np.ndarray, faces: np.ndarray, values: np.ndarray) -> bytes:
        """The picture of one specimen, encoded (:attr:`format`)."""
        poly = self.pv.PolyData.from_regular_faces(vertices, faces)
        poly.point_data["value"] = values
        self.plotter.add_mesh(
            poly,
            scalars="value",
            cmap=self.table,
            clim=self.scale.limits,
            smooth_shading=True,
            show_scalar_bar=False,
            specular=0.0,
            ambient=0.3,
            diffuse=0.7,
            name="specimen",
            reset_camera=False,
        )
        rotation = report_camera(vertices, faces)
        direction, up = rotation[2], rotation[1]
        low, high = vertices.min(axis=0), vertices.max(axis=0)
        centre = 0.5 * (low + high)
        distance = 3.0 * max(float(np.linalg.norm(high - low)), 1e-12)
        self.plotter.camera_position = [
            tuple(centre + distance * direction),
            tuple(centre),
            tuple(up),
        ]
        self.plotter.reset_camera()
        self.plotter.camera.zoom(1.35)
        pixels = self.plotter.screenshot(return_img=True)
        buffer = io.BytesIO()
        options = {"quality": 85, "method": 4} if self.format == "WEBP" else {}
        self.image.fromarray(np.ascontiguousarray(pixels)).save(buffer, self.format, **options)
        return buffer.getvalue()


def draw(fields: list, scale: ColorScale, size: int = THUMBNAIL_SIZE) -> list[tuple[str, dict]]:
    """Each field's thumbnail (a ``data:`` URL) and 3D payload, through one plotter.

    Parameters
    ----------
    fields : list of Field
        Meshes with their values (see ``_fields``).
    scale : ColorScale
        The collection's colour limits.
    size : int
        Thumbnail width and height, pixels.
    """
    drawn = []
    with _quiet_vtk_warnings(), Thumbnailer(scale, size) as thumbnailer:
        for field in fields:
            picture = thumbnailer.render(field.vertices, field.faces, field.values)
            encoded = base64.b64encode(picture).decode("ascii")
            turned = field.vertices @ report_camera(field.vertices, field.faces).T
            payload = pack_mesh(turned, field.faces, field.values, scale)
            drawn.append((f"data:{thumbnailer.mime};base64,{encoded}", payload))
    return drawn
