"""Omniverse Replicator's ``BasicWriter`` (``omni.replicator.core``) for scripts that save camera data with it.

Isaac Lab's camera tutorials pack one camera's images into Replicator's layout and hand it to
``BasicWriter.write``::

    {"annotators": {"distance_to_image_plane": {"render_product": {"data": array, **info}}, ...},
     "trigger_outputs": {"on_time": frame}}

simlab's writer takes the same dict and writes each array as a file in ``output_dir``:
``normals`` as a PNG coloured ``(n + 1) / 2`` per channel, 8-bit images (``rgb``, ``rgba``, coloured
segmentation) as PNGs, anything else (depths, ids) as ``.npy``; with ``colorize_depth`` a depth also
as a grey PNG (near dark, far light, nothing hit black). Files are named
``<annotator>_<on_time>_<frame>`` (the frame counts this writer's writes, ``frame_padding`` digits),
under a folder per render product when there are several; the other entries of a render product
(labels) go into a ``.json`` beside them. Writers attached to Kit's render products have no
counterpart: :meth:`BasicWriter.attach` says so.
"""

from __future__ import annotations

import json
import os
from typing import Any

import numpy as np

from simlab.utils.optional import require

_DEPTH_TYPES = ("distance_to_camera", "distance_to_image_plane", "depth")
# Replicator's switches of what an attached writer asks its render products for, and how it colours them
_ANNOTATOR_SWITCHES = (
    "rgb",
    "bounding_box_2d_tight",
    "bounding_box_2d_loose",
    "semantic_segmentation",
    "instance_id_segmentation",
    "instance_segmentation",
    "distance_to_camera",
    "distance_to_image_plane",
    "bounding_box_3d",
    "occlusion",
    "normals",
    "motion_vectors",
    "camera_params",
    "pointcloud",
    "pointcloud_include_unlabelled",
    "skeleton_data",
    "semantic_types",
    "colorize_semantic_segmentation",
    "colorize_instance_id_segmentation",
    "colorize_instance_segmentation",
)


class BasicWriter:
    """Writes the arrays ``write(data)`` is given (Replicator's layout) as files in ``output_dir``."""

    def __init__(
        self,
        output_dir: str,
        frame_padding: int = 4,
        colorize_depth: bool = False,
        image_output_format: str = "png",
        **annotators: bool,
    ):
        if image_output_format != "png":
            raise ValueError(f"BasicWriter(image_output_format={image_output_format!r}): simlab writes 'png' only")
        if isinstance(frame_padding, bool) or not isinstance(frame_padding, int) or frame_padding < 0:
            raise ValueError(f"BasicWriter(frame_padding={frame_padding!r}) must be a whole number of digits >= 0")
        # Replicator's rgb=True, normals=True, ... choose what attached render products give; write()
        # writes every annotator it is handed (coloured or not already), so they change nothing here
        unknown = sorted(set(annotators) - set(_ANNOTATOR_SWITCHES))
        if unknown:
            raise TypeError(
                f"BasicWriter got unknown arguments {unknown}; it takes output_dir, frame_padding, colorize_depth,"
                f" image_output_format and Replicator's switches {list(_ANNOTATOR_SWITCHES)}"
            )
        self.output_dir = str(output_dir)
        self.frame_padding = frame_padding
        self.colorize_depth = colorize_depth
        self.annotators = annotators
        self._frame_id = 0
        os.makedirs(self.output_dir, exist_ok=True)

    def attach(self, render_products: Any = None, **kwargs: Any) -> None:
        raise NotImplementedError(
            "BasicWriter.attach: simlab has no Kit render products to attach to; read the camera's data.output"
            " each step and pass it to writer.write({'annotators': {name: {'render_product': {'data': array}}}})"
        )

    def write(self, data: dict) -> list[str]:
        """Write every annotator's arrays of ``data``; returns the paths written."""
        if not isinstance(data, dict) or not isinstance(data.get("annotators"), dict):
            raise ValueError(
                "BasicWriter.write takes Replicator's layout {'annotators': {name: {render_product: {'data': array}}}},"
                f" got {type(data).__name__} with keys {list(data) if isinstance(data, dict) else []}"
            )
        triggers = data.get("trigger_outputs", {})
        sequence = "".join(f"{int(count)}_" for name, count in triggers.items() if "on_time" in name)
        frame = f"{sequence}{self._frame_id:0{self.frame_padding}d}"
        written: list[str] = []
        for annotator, products in data["annotators"].items():  # all checked before any file is written
            entries = products.values() if isinstance(products, dict) else [products]
            if not all(isinstance(entry, dict) and "data" in entry for entry in entries):
                raise ValueError(
                    f"BasicWriter.write: annotator {annotator!r} must map render products to {{'data': array, **info}},"
                    " e.g. {'render_product': {'data': array}}"
                )
            for name in [annotator, *(products if isinstance(products, dict) else [])]:
                _check_plain_name(name)
        for annotator, products in data["annotators"].items():
            for product, entry in products.items():
                folder = os.path.join(self.output_dir, product) if len(products) > 1 else self.output_dir
                os.makedirs(folder, exist_ok=True)
                stem = os.path.join(folder, f"{annotator}_{frame}")
                written += self._write_entry(annotator, stem, dict(entry))
        self._frame_id += 1
        return written

    def _write_entry(self, annotator: str, stem: str, entry: dict) -> list[str]:
        array = np.asarray(entry.pop("data"))
        if annotator.startswith("normals"):
            paths = [_write_png(f"{stem}.png", _colorize_normals(array))]
        elif array.dtype == np.uint8 and array.ndim in (2, 3) and (array.ndim == 2 or array.shape[-1] in (1, 3, 4)):
            paths = [_write_png(f"{stem}.png", array)]
        else:
            np.save(f"{stem}.npy", array)
            paths = [f"{stem}.npy"]
            if self.colorize_depth and annotator.startswith(_DEPTH_TYPES):
                paths.append(_write_png(f"{stem}.png", colorize_depth(array)))
        if entry:  # labels and other info of the render product
            with open(f"{stem}.json", "w") as f:
                json.dump(entry, f, default=_jsonable)
            paths.append(f"{stem}.json")
        return paths


def colorize_depth(depth: np.ndarray) -> np.ndarray:
    """A depth image (H, W) or (H, W, 1) as 8-bit grey: depth over the largest finite depth, non-finite black."""
    depth = np.asarray(depth, dtype=np.float64).reshape(depth.shape[0], depth.shape[1])
    finite = np.isfinite(depth) & (depth > 0)
    top = depth[finite].max() if finite.any() else 1.0
    return np.where(finite, np.round(255.0 * depth / top), 0.0).astype(np.uint8)


def _colorize_normals(normals: np.ndarray) -> np.ndarray:
    """Unit normals (H, W, 3) as 8-bit RGB, each axis from -1..1 to 0..255; no normal (inf): black."""
    normals = np.asarray(normals, dtype=np.float64)[..., :3]
    finite = np.isfinite(normals).all(axis=-1, keepdims=True)
    return np.where(finite, np.round((np.clip(normals, -1.0, 1.0) * 0.5 + 0.5) * 255.0), 0.0).astype(np.uint8)


def _check_plain_name(name: Any) -> None:
    """Annotator and render-product names become file and folder names: one plain name each, so a
    ``'../x'`` cannot write outside ``output_dir``."""
    if not isinstance(name, str) or name in ("", ".", "..") or "/" in name or "\\" in name or "\0" in name:
        raise ValueError(
            f"BasicWriter.write: annotator and render product names must be plain file names (no '/', '\\',"
            f" '.' or '..'), got {name!r}"
        )


def _write_png(path: str, image: np.ndarray) -> str:
    iio = require("imageio.v3")  # the "render" extra; a clear install hint when missing
    iio.imwrite(path, image[..., 0] if image.ndim == 3 and image.shape[-1] == 1 else image)
    return path


def _jsonable(value: Any) -> Any:
    return value.tolist() if hasattr(value, "tolist") else str(value)
