"""``MotionLoader``: a motion clip on the device, sampled at any times (Isaac Lab's interface).

Positions and velocities are interpolated linearly between the two frames around a time,
rotations by slerp. Times are torch tensors (numpy arrays are accepted) and stay on the device, so
an env can sample reference states for every env inside its step.
"""

from __future__ import annotations

import numpy as np
import torch

from simlab.utils.math import quat_slerp

from .motion_file import HUMANOID_XML, read_motion_file

__all__ = ["MotionLoader"]


class MotionLoader:
    """A clip read from an Isaac Lab motion file (see :mod:`.motion_file`); ``mjcf`` is the model whose
    forward kinematics fills the body states of a file that stores its root instead."""

    def __init__(self, motion_file: str, device: torch.device | str, mjcf: str = HUMANOID_XML) -> None:
        clip = read_motion_file(motion_file, mjcf)
        self.motion_file = motion_file
        self.device = device
        self._dof_names = [str(name) for name in clip["dof_names"].tolist()]
        self._body_names = [str(name) for name in clip["body_names"].tolist()]

        def tensor(key: str) -> torch.Tensor:
            return torch.tensor(clip[key], dtype=torch.float32, device=device)

        self.dof_positions = tensor("dof_positions")
        self.dof_velocities = tensor("dof_velocities")
        self.body_positions = tensor("body_positions")
        self.body_rotations = tensor("body_rotations")
        self.body_linear_velocities = tensor("body_linear_velocities")
        self.body_angular_velocities = tensor("body_angular_velocities")

        self.fps = float(clip["fps"])
        self.dt = 1.0 / self.fps
        self.num_frames = self.dof_positions.shape[0]
        self.duration = self.dt * (self.num_frames - 1)

    @property
    def dof_names(self) -> list[str]:
        return self._dof_names

    @property
    def body_names(self) -> list[str]:
        return self._body_names

    @property
    def num_dofs(self) -> int:
        return len(self._dof_names)

    @property
    def num_bodies(self) -> int:
        return len(self._body_names)

    def sample_times(self, num_samples: int, duration: float | None = None) -> torch.Tensor:
        """``num_samples`` times drawn uniformly in ``[0, duration]`` (default: the whole clip)."""
        duration = self.duration if duration is None else duration
        if not 0.0 <= duration <= self.duration:
            raise ValueError(f"duration {duration} s is outside the clip's [0, {self.duration}] s.")
        return duration * torch.rand(num_samples, device=self.device)

    def sample(
        self, num_samples: int, times: torch.Tensor | np.ndarray | None = None, duration: float | None = None
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
        """The clip at ``times`` (drawn uniformly when None; clamped to the clip), as Isaac Lab returns it.

        Returns dof positions (N, D), dof velocities (N, D), body positions (N, B, 3), body rotations
        (N, B, 4, w x y z), body linear velocities (N, B, 3) and body angular velocities (N, B, 3).
        """
        if times is None:
            times = self.sample_times(num_samples, duration)
        times = torch.as_tensor(times, dtype=torch.float32, device=self.device).reshape(-1)
        frame = (times / self.dt).clamp(0.0, self.num_frames - 1)
        index_0 = frame.floor().long().clamp(max=self.num_frames - 2)
        index_1 = index_0 + 1
        blend = frame - index_0

        def lerp(values: torch.Tensor) -> torch.Tensor:
            w = blend.view(-1, *([1] * (values.dim() - 1)))
            return (1.0 - w) * values[index_0] + w * values[index_1]

        rotations = quat_slerp(
            self.body_rotations[index_0], self.body_rotations[index_1], blend.unsqueeze(-1).expand(-1, self.num_bodies)
        )
        return (
            lerp(self.dof_positions),
            lerp(self.dof_velocities),
            lerp(self.body_positions),
            rotations,
            lerp(self.body_linear_velocities),
            lerp(self.body_angular_velocities),
        )

    def get_dof_index(self, dof_names: list[str]) -> list[int]:
        """Indices of ``dof_names`` in the clip."""
        return _indices(dof_names, self._dof_names, "joint", self.motion_file)

    def get_body_index(self, body_names: list[str]) -> list[int]:
        """Indices of ``body_names`` in the clip."""
        return _indices(body_names, self._body_names, "body", self.motion_file)


def _indices(names: list[str], available: list[str], kind: str, where: str) -> list[int]:
    missing = [name for name in names if name not in available]
    if missing:
        raise ValueError(f"The motion file {where} has no {kind} named {missing}; its {kind} names: {available}.")
    return [available.index(name) for name in names]
