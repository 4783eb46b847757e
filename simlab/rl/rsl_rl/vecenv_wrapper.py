"""``RslRlVecEnvWrapper``: a simlab env as an rsl_rl ``VecEnv`` (rsl-rl-lib 5.x).

rsl_rl reads observations as a ``TensorDict`` of groups, gets ``dones`` as one tensor, and reads
``extras["time_outs"]`` to bootstrap the value of time-limited episodes and ``extras["log"]`` for
logging. It never calls ``reset()``: the wrapper resets once at construction. It never reads
``extras["final_obs"]`` either; ``simlab train`` turns them off for it (``READS_FINAL_OBS`` in
:mod:`simlab.cli.libraries.rsl_rl`), while play keeps them for the success criteria that read them.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch

from simlab.rl.utils import check_single_agent, require, stack_image_history

require("rsl_rl")
TensorDict = require("tensordict").TensorDict
from rsl_rl.env import VecEnv  # noqa: E402

__all__ = ["RslRlVecEnvWrapper", "stack_image_history"]


class RslRlVecEnvWrapper(VecEnv):
    """Wrap a (single-agent) simlab env made with ``gym.make`` for rsl_rl's runners.

    Args:
        env: the environment (``ManagerBasedRLEnv`` or ``DirectRLEnv``, possibly inside Gymnasium
            wrappers such as ``RecordVideo``).
        clip_actions: clip actions to ``[-clip_actions, clip_actions]`` before stepping; None: no clipping.
    """

    def __init__(self, env: gym.Env, clip_actions: float | None = None):
        base = check_single_agent(env, "RslRlVecEnvWrapper")
        if clip_actions is not None and not clip_actions > 0:
            raise ValueError(f"clip_actions must be a positive number or None, got {clip_actions!r}.")
        self.env = env
        self.clip_actions = clip_actions
        self.num_envs: int = base.num_envs
        self.device = base.device
        self.max_episode_length = base.max_episode_length
        self.num_actions: int = gym.spaces.flatdim(base.single_action_space)
        if clip_actions is not None:
            self._set_action_bounds(base, clip_actions)
        obs, _ = self.env.reset()
        self._obs = self._to_tensordict(obs)

    # -- properties ------------------------------------------------------------------------------

    @property
    def cfg(self) -> Any:
        return self.unwrapped.cfg

    @property
    def unwrapped(self) -> Any:
        return self.env.unwrapped

    @property
    def render_mode(self) -> str | None:
        return self.env.render_mode

    @property
    def observation_space(self) -> gym.Space:
        return self.env.observation_space

    @property
    def action_space(self) -> gym.Space:
        return self.env.action_space

    @classmethod
    def class_name(cls) -> str:
        return cls.__name__

    @property
    def episode_length_buf(self) -> torch.Tensor:
        """Steps taken in the current episode of each env (rsl_rl randomizes it at start)."""
        return self.unwrapped.episode_length_buf

    @episode_length_buf.setter
    def episode_length_buf(self, value: torch.Tensor) -> None:
        # in place: the env (or a multi-agent view of one) keeps its own buffer
        self.unwrapped.episode_length_buf[:] = value

    # -- VecEnv ----------------------------------------------------------------------------------

    def seed(self, seed: int = -1) -> int:
        return self.unwrapped.seed(seed)

    def reset(self) -> tuple[TensorDict, dict]:
        obs, extras = self.env.reset()
        self._obs = self._to_tensordict(obs)
        return self._obs, extras

    def get_observations(self) -> TensorDict:
        """The observations of the last reset or step."""
        return self._obs

    def step(self, actions: torch.Tensor) -> tuple[TensorDict, torch.Tensor, torch.Tensor, dict]:
        if self.clip_actions is not None:
            actions = torch.clamp(actions, -self.clip_actions, self.clip_actions)
        obs, rew, terminated, truncated, extras = self.env.step(actions)
        dones = (terminated | truncated).to(dtype=torch.long)
        # time-outs are not failures: rsl_rl bootstraps their value, unless the task is finite-horizon
        if not getattr(self.cfg, "is_finite_horizon", False):
            extras["time_outs"] = truncated
        self._obs = self._to_tensordict(obs)
        return self._obs, rew, dones, extras

    def close(self) -> None:
        self.env.close()

    # -- helpers ---------------------------------------------------------------------------------

    def _to_tensordict(self, obs: dict[str, torch.Tensor] | torch.Tensor) -> TensorDict:
        if isinstance(obs, torch.Tensor):
            obs = {"policy": obs}
        groups = {name: _channels_first(value) for name, value in obs.items()}
        return TensorDict(groups, batch_size=[self.num_envs])

    def _set_action_bounds(self, base: Any, clip: float) -> None:
        # tell the env (and the video/metadata wrappers reading it) the actions it can now receive
        shape = (self.num_actions,)
        base.single_action_space = gym.spaces.Box(low=-clip, high=clip, shape=shape)
        base.action_space = gym.vector.utils.batch_space(base.single_action_space, self.num_envs)


def _channels_first(value: torch.Tensor) -> torch.Tensor:
    """Image groups come as (N, H, W, C) (Isaac Lab's layout), or as an image term's history
    (:func:`stack_image_history`); rsl_rl's CNNs take (N, C, H, W)."""
    value = stack_image_history(value)
    return value.permute(0, 3, 1, 2) if value.ndim == 4 else value
