"""What a frame transformer reports: source and target frame poses, computed when read."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils

if TYPE_CHECKING:
    from .frame_transformer import FrameTransformer


class FrameTransformerData:
    """Poses of the source frame (world) and of the target frames (world, and in the source frame).

    Shapes use N envs and M target frames; quaternions are ``(w, x, y, z)``.
    """

    def __init__(self, sensor: FrameTransformer):
        self._sensor = sensor
        self.target_frame_names: list[str] = sensor._target_names

    @property
    def source_pos_w(self) -> torch.Tensor:
        """(N, 3)"""
        return self._sensor._frames_w(self._sensor._source)[0][:, 0]

    @property
    def source_quat_w(self) -> torch.Tensor:
        """(N, 4)"""
        return self._sensor._frames_w(self._sensor._source)[1][:, 0]

    @property
    def target_pos_w(self) -> torch.Tensor:
        """(N, M, 3)"""
        return self._sensor._frames_w(self._sensor._targets)[0]

    @property
    def target_quat_w(self) -> torch.Tensor:
        """(N, M, 4)"""
        return self._sensor._frames_w(self._sensor._targets)[1]

    @property
    def target_pos_source(self) -> torch.Tensor:
        """(N, M, 3) target positions in the source frame."""
        return self._in_source()[0]

    @property
    def target_quat_source(self) -> torch.Tensor:
        """(N, M, 4) target orientations relative to the source frame."""
        return self._in_source()[1]

    def _in_source(self) -> tuple[torch.Tensor, torch.Tensor]:
        src_pos, src_quat = self._sensor._frames_w(self._sensor._source)
        tgt_pos, tgt_quat = self._sensor._frames_w(self._sensor._targets)
        m = tgt_pos.shape[1]
        return math_utils.subtract_frame_transforms(
            src_pos.expand(-1, m, -1), src_quat.expand(-1, m, -1), tgt_pos, tgt_quat
        )
