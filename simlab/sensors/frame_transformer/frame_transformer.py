"""Frame transformer: poses of target frames (bodies plus fixed offsets) relative to a source frame.

Isaac Lab's ``FrameTransformer``. Frames are named by prim path: ``{ENV_REGEX_NS}/Robot/panda_hand``
is the body ``panda_hand`` of the entity ``Robot``; a path that names an entity alone
(``{ENV_REGEX_NS}/Object``) is its root body; the body part may be a regex
(``{ENV_REGEX_NS}/Robot/panda_.*finger``), giving one target frame per matched body.
The data are computed from the bodies' current poses when read, so they are always current.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.markers import VisualizationMarkers

from ..sensor_base import SensorBase
from .frame_transformer_data import FrameTransformerData

if TYPE_CHECKING:
    from .frame_transformer_cfg import FrameTransformerCfg, OffsetCfg

_ENV_PREFIX = re.compile(r"^(\{ENV_REGEX_NS\}|/World/envs/env_(\.\*|\d+))/")


class _Frames:
    """Model body ids and fixed offsets of a set of frames."""

    def __init__(self, body_ids: list[int], offsets: list[OffsetCfg], device):
        self.body_index = torch.tensor(body_ids, dtype=torch.long, device=device)
        self.offset_pos = torch.tensor([o.pos for o in offsets], dtype=torch.float32, device=device)
        self.offset_quat = torch.tensor([o.rot for o in offsets], dtype=torch.float32, device=device)
        self.has_offset = bool(
            self.offset_pos.any() or (self.offset_quat != self.offset_quat.new_tensor([1, 0, 0, 0])).any()
        )


class FrameTransformer(SensorBase):
    cfg: FrameTransformerCfg

    def __init__(self, cfg: FrameTransformerCfg, scene=None):
        super().__init__(cfg, scene)
        self._target_names: list[str] = []

    def __str__(self) -> str:
        return f"FrameTransformer @ '{self.cfg.prim_path}': target frames {self._target_names}"

    @property
    def data(self) -> FrameTransformerData:
        return self._data

    # -- debug visualization: a frame marker at every target frame ---------------------------------

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        if debug_vis and not hasattr(self, "frame_visualizer"):
            self.frame_visualizer = VisualizationMarkers(self.cfg.visualizer_cfg)
        if hasattr(self, "frame_visualizer"):
            self.frame_visualizer.set_visibility(debug_vis)

    def _debug_vis_callback(self, event) -> None:
        data = self.data
        self.frame_visualizer.visualize(data.target_pos_w.reshape(-1, 3), data.target_quat_w.reshape(-1, 4))

    def _initialize(self, sim) -> None:
        super()._initialize(sim)
        model = sim.model
        self._physics = sim.physics
        self._xpos, self._xquat = sim.physics.data("xpos"), sim.physics.data("xquat")
        self._origins = sim.env_origins
        body_names = [model.body(b).name for b in range(model.nbody)]
        source_ids, _ = _bodies_of(self.cfg.prim_path, body_names, "prim_path")
        if len(source_ids) != 1:
            raise ValueError(
                f"FrameTransformerCfg.prim_path '{self.cfg.prim_path}' names {len(source_ids)} bodies; the source"
                " frame must be one body"
            )
        self._source = _Frames(source_ids, [self.cfg.source_frame_offset], self.device)
        target_ids, offsets, names = [], [], []
        for frame in self.cfg.target_frames:
            ids, matched = _bodies_of(frame.prim_path, body_names, "target_frames[].prim_path")
            if frame.name is not None and len(ids) > 1:
                raise ValueError(
                    f"target frame '{frame.name}' ({frame.prim_path}) matches {len(ids)} bodies {matched}; give each"
                    " frame its own FrameCfg to name it, or leave name=None to name the frames after the bodies"
                )
            target_ids += ids
            offsets += [frame.offset] * len(ids)
            names += [frame.name] if frame.name is not None else matched
        if not target_ids:
            raise ValueError("FrameTransformerCfg.target_frames is empty: add at least one FrameCfg")
        self._targets = _Frames(target_ids, offsets, self.device)
        self._target_names = names
        self._data = FrameTransformerData(self)

    def _frames_w(self, frames: _Frames) -> tuple[torch.Tensor, torch.Tensor]:
        """(N, M, 3) positions (env origins included) and (N, M, 4) orientations of ``frames``."""
        self._physics.ensure_forward()
        pos = self._xpos[:, frames.body_index] + self._origins[:, None]
        quat = self._xquat[:, frames.body_index]
        if frames.has_offset:
            n, m = pos.shape[:2]
            pos, quat = math_utils.combine_frame_transforms(
                pos, quat, frames.offset_pos.expand(n, m, 3), frames.offset_quat.expand(n, m, 4)
            )
        return pos, quat


def _bodies_of(prim_path: str, body_names: Sequence[str], what: str) -> tuple[list[int], list[str]]:
    """Model bodies a prim path names, ``<env>/<Entity>`` (its root body, named after the entity, as the
    prim is in Isaac Lab) or ``<env>/<Entity>/<body regex>``, and their names."""
    rest = _ENV_PREFIX.sub("", prim_path)
    if rest == prim_path and prim_path.startswith("/World/"):
        rest = prim_path[len("/World/") :]
    entity, _, body = rest.partition("/")
    owned = [(i, n) for i, n in enumerate(body_names) if n.startswith(entity + "/")]
    if not owned:
        entities = sorted({n.split("/")[0] for n in body_names if "/" in n})
        raise ValueError(f"{what} '{prim_path}': the scene has no entity '{entity}'; entities: {entities}")
    if not body:
        return [owned[0][0]], [entity]
    pattern = re.compile(body)
    matched = [(i, n) for i, n in owned if pattern.fullmatch(n[len(entity) + 1 :])]
    if not matched:
        raise ValueError(
            f"{what} '{prim_path}': no body of '{entity}' matches '{body}'; its bodies:"
            f" {[n[len(entity) + 1 :] for _, n in owned]}"
        )
    return [i for i, _ in matched], [n[len(entity) + 1 :] for _, n in matched]
