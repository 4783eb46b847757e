"""What a live viewer reads from the simulation: the shown envs' state, copied at the viewer's pace.

A viewer shows one followed env and its nearest neighbours, in the followed env's MuJoCo frame
(each env is its own world; neighbours are drawn at their origins relative to it). Only those
envs' ``qpos`` / ``qvel`` / mocap rows are copied from the backend's tensors (CPU or GPU), and the
body poses are computed on the host from them (``mj_kinematics``), so the physics step is never
touched: a CUDA-graphed GPU step stays graphed.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import mujoco
import numpy as np
import torch

from simlab.envs.utils.viewer import camera_pose, view_frame
from simlab.sim.renderer import DecorGeom, SceneDecor, gather_env_states

__all__ = ["EnvSnapshot", "SimSource"]


@dataclass
class EnvSnapshot:
    """The shown envs at one instant (row 0: the followed env)."""

    env_ids: list[int]
    offsets: np.ndarray  # (n, 3) env origins relative to the followed env's
    states: dict[str, np.ndarray]  # qpos, qvel, mocap rows, one per shown env
    episode_return: float | None = None  # of the followed env's running episode
    episode_length: int | None = None
    decor: list[DecorGeom] = field(default_factory=list)  # the followed env's debug markers
    anchor: np.ndarray | None = None  # the point of the followed env the camera moves with (SimSource.anchor)


class SimSource:
    """The batched simulation a viewer shows: its model, state tensors and env origins."""

    def __init__(
        self,
        model: mujoco.MjModel,
        physics,
        env_origins: torch.Tensor,
        step_dt: float,
        env=None,
    ):
        self.model = model
        self._env = env  # the env whose ``cfg.viewer`` places the camera; None for a bare simulation
        self.physics = physics
        self.env_origins = env_origins
        self.num_envs = int(env_origins.shape[0])
        self._decor = SceneDecor(model)
        self.step_dt = step_dt

    @classmethod
    def of_env(cls, env) -> SimSource:
        return cls(env.sim.model, env.sim.physics, env.sim.env_origins, float(env.step_dt), env)

    @classmethod
    def of_sim(cls, sim) -> SimSource:
        return cls(sim.model, sim.physics, sim.env_origins, float(sim.get_physics_dt()))

    def camera(self, follow: int) -> tuple[np.ndarray, np.ndarray] | None:
        """The eye and look-at point of the env's viewer camera (``cfg.viewer``) showing env ``follow``,
        in its MuJoCo frame: where ``env.render()``'s video camera looks from and at (``view_frame``)."""
        if self._env is None:
            return None
        env = self._env
        aim = getattr(env, "_view_aim", None)  # the video camera's remembered aim: left as it was
        try:
            frame = view_frame(env, _viewer_of(env, follow))
        finally:
            env._view_aim = aim
        return frame.eye, frame.lookat

    def anchor(self, follow: int) -> np.ndarray | None:
        """The point of env ``follow`` (its MuJoCo frame) the camera moves with: the origin of the frame
        ``cfg.viewer.origin_type`` names (an asset's root or body, as it moves), or the env's origin for
        a world-frame camera (the viewer follows an env)."""
        if self._env is None:
            return None
        viewer = _viewer_of(self._env, follow)
        if viewer.origin_type == "world":
            viewer.origin_type = "env"
        return camera_pose(self._env, viewer)[1]

    def shown_envs(self, follow: int, max_envs: int) -> tuple[list[int], np.ndarray]:
        """Env ``follow`` and the ``max_envs - 1`` envs whose origins are nearest it, with their
        origins relative to ``follow``'s."""
        if not 0 <= follow < self.num_envs:
            raise ValueError(f"env {follow} does not exist: there are {self.num_envs} envs (0..{self.num_envs - 1})")
        origins = self.env_origins.detach().cpu().numpy().astype(np.float64)
        offsets = origins - origins[follow]
        distance = np.linalg.norm(offsets[:, :2], axis=1)
        distance[follow] = -1.0
        ids = np.argsort(distance, kind="stable")[: max(1, max_envs)].tolist()
        return ids, offsets[ids]

    def snapshot(self, env_ids: list[int], offsets: np.ndarray) -> EnvSnapshot:
        """The shown envs' state and the followed env's debug markers (debug_vis of commands, sensors, ...)."""
        decor = self._decor.capture(int(env_ids[0]), self.env_origins)
        states = gather_env_states(self.physics, env_ids)
        return EnvSnapshot(list(env_ids), offsets, states, decor=decor, anchor=self.anchor(int(env_ids[0])))


def _viewer_of(env, follow: int):
    """A copy of ``env.cfg.viewer`` about env ``follow``."""
    viewer = copy.copy(env.cfg.viewer)
    viewer.env_index = follow
    return viewer


class HostKinematics:
    """Body poses of snapshot rows, computed on the host from their joint state."""

    def __init__(self, model: mujoco.MjModel):
        self.model = model
        self.data = mujoco.MjData(model)

    def load(self, snapshot: EnvSnapshot, row: int, full: bool = False) -> mujoco.MjData:
        """Row ``row`` in the host ``MjData``: kinematics only, or a full forward (``full``)."""
        for name, values in snapshot.states.items():
            getattr(self.data, name)[:] = values[row]
        (mujoco.mj_forward if full else mujoco.mj_kinematics)(self.model, self.data)
        return self.data

    def body_poses(self, snapshot: EnvSnapshot) -> tuple[np.ndarray, np.ndarray]:
        """``(xpos (n, nbody, 3), xmat (n, nbody, 3, 3))`` of the shown envs, neighbours moved
        to their offsets."""
        n = len(snapshot.env_ids)
        xpos = np.empty((n, self.model.nbody, 3))
        xmat = np.empty((n, self.model.nbody, 3, 3))
        for row in range(n):
            data = self.load(snapshot, row)
            xpos[row] = data.xpos + snapshot.offsets[row]
            xmat[row] = data.xmat.reshape(-1, 3, 3)
        return xpos, xmat
