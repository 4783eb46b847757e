"""The manager-based RL environment: a ``gymnasium.Env`` over ``num_envs`` parallel worlds.

``step(action)`` returns ``(obs, reward, terminated, truncated, extras)``, tensors with the env
dimension first. Envs that finish are reset inside the same step (Gymnasium's SAME_STEP autoreset),
so the returned observation of such an env is the first one of its next episode; the observation
before the reset is kept in ``extras["final_obs"]`` (every group, every env; present only in steps
where some env reset) for bootstrapping, and ``extras["time_outs"]`` marks the truncations
(the key rsl_rl reads). ``extras["log"]`` carries ``Episode_Reward/<term>`` and
``Episode_Termination/<term>`` of the envs that reset in the step.

Order inside ``step`` (Isaac Lab's): actions, ``decimation`` physics steps, episode counters,
terminations, rewards, resets, commands, ``interval`` events, observations. Body poses and other
derived quantities are recomputed only if a term reads them (``PhysicsBackend.ensure_forward``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
import torch

from simlab.managers import CommandManager, CurriculumManager, RewardManager, TerminationManager

from .common import VecEnvObs, VecEnvStepReturn
from .manager_based_env import ManagerBasedEnv
from .manager_based_rl_env_cfg import ManagerBasedRLEnvCfg
from .utils.cuda_graph import CudaGraphStep
from .utils.viewer import show_in_viewer


class ManagerBasedRLEnv(ManagerBasedEnv, gym.Env):
    is_vector_env: ClassVar[bool] = True
    metadata: ClassVar[dict[str, Any]] = {
        "render_modes": [None, "human", "rgb_array"],
        "autoreset_mode": gym.vector.AutoresetMode.SAME_STEP,
    }
    cfg: ManagerBasedRLEnvCfg

    def __init__(self, cfg: ManagerBasedRLEnvCfg, render_mode: str | None = None, **kwargs):
        if render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}")
        self.render_mode = render_mode
        self.common_step_counter = 0
        self.episode_length_buf = torch.zeros(cfg.scene.num_envs, dtype=torch.long)
        super().__init__(cfg)
        self.episode_length_buf = torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
        self.metadata = dict(self.metadata, render_fps=1.0 / self.step_dt)
        self._all_env_ids = torch.arange(self.num_envs, dtype=torch.long, device=self.device)
        # The GPU fast path (simlab.envs.utils.cuda_graph); interval events and curricula run on the host.
        self._cuda_graph = None
        host_driven = "interval" in self.event_manager.available_modes or self.curriculum_manager.active_terms
        if "cuda" in self.device and cfg.sim.use_cuda_graph and not host_driven:
            self._cuda_graph = CudaGraphStep(self, self._graph_step)
        print("[INFO]: Completed setting up the environment...")

    # -- properties --------------------------------------------------------------------------------

    # -- building ----------------------------------------------------------------------------------

    def load_managers(self) -> None:
        self.command_manager = CommandManager(self.cfg.commands, self)
        print("[INFO]: Command Manager:", self.command_manager)
        super().load_managers()
        self.termination_manager = TerminationManager(self.cfg.terminations, self)
        print("[INFO]: Termination Manager:", self.termination_manager)
        self.reward_manager = RewardManager(self.cfg.rewards, self)
        print("[INFO]: Reward Manager:", self.reward_manager)
        self.curriculum_manager = CurriculumManager(self.cfg.curriculum, self)
        print("[INFO]: Curriculum Manager:", self.curriculum_manager)
        self._configure_gym_env_spaces()
        self.event_manager.apply(mode="startup")

    def _configure_gym_env_spaces(self) -> None:
        om = self.observation_manager
        self.single_observation_space = gym.spaces.Dict()
        for group, names in om.active_terms.items():
            if om.group_obs_concatenate[group]:
                self.single_observation_space[group] = gym.spaces.Box(-np.inf, np.inf, shape=om.group_obs_dim[group])
            else:
                self.single_observation_space[group] = gym.spaces.Dict(
                    {
                        name: gym.spaces.Box(-np.inf, np.inf, shape=dim)
                        for name, dim in zip(names, om.group_obs_term_dim[group])
                    }
                )
        self.single_action_space = gym.spaces.Box(-np.inf, np.inf, shape=(self.action_manager.total_action_dim,))
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, self.num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)

    # -- operations --------------------------------------------------------------------------------

    def step(self, action: torch.Tensor) -> VecEnvStepReturn:
        if self._cuda_graph is not None:
            return self._step_graphed(action)
        self.action_manager.process_action(action)
        self._physics_steps(self.action_manager.apply_action)
        self._sim_step_counter += self.cfg.decimation

        self.episode_length_buf += 1
        self.common_step_counter += 1
        self.reset_buf = self.termination_manager.compute()
        self.reset_terminated = self.termination_manager.terminated
        self.reset_time_outs = self.termination_manager.time_outs
        self.reward_buf = self.reward_manager.compute(dt=self.step_dt)

        self.extras.pop("final_obs", None)
        reset_env_ids = self.reset_buf.nonzero().flatten()
        if len(reset_env_ids) > 0:
            # The observation the finished episodes ended in, before their reset (for bootstrapping).
            self.extras["final_obs"] = self.observation_manager.compute(update_history=False)
            self._reset_idx(reset_env_ids)
            self.scene.write_data_to_sim()
            self.sim.physics.mark_stale(reset_env_ids)
        self.extras["time_outs"] = self.reset_time_outs

        self.command_manager.compute(dt=self.step_dt)
        if "interval" in self.event_manager.available_modes:
            self.event_manager.apply(mode="interval", dt=self.step_dt)
        self.obs_buf = self.observation_manager.compute(update_history=True)
        return self.obs_buf, self.reward_buf, self.reset_terminated, self.reset_time_outs, self.extras

    def reset(
        self, seed: int | None = None, env_ids: Sequence[int] | torch.Tensor | None = None, options: dict | None = None
    ) -> tuple[VecEnvObs, dict]:
        self.extras.pop("final_obs", None)
        if self._cuda_graph is not None and env_ids is None:
            # A full reset that also notes what a reset writes (for the masked resets of the graph).
            self._learn_footprint = True
        try:
            return super().reset(seed=seed, env_ids=env_ids, options=options)
        finally:
            self._learn_footprint = False

    def _step_graphed(self, action: torch.Tensor) -> VecEnvStepReturn:
        """``step`` on the GPU fast path: the same order of work, replayed as one CUDA graph.

        Episode logs are masked means over the envs that finished; like the eager step, they are
        refreshed only in steps where some env finished (one host read of a flag per step).
        """
        action = action.to(device=self.device, dtype=torch.float32)
        if action.shape != (self.num_envs, self.action_manager.total_action_dim):
            self.action_manager.process_action(action)  # raises with the expected shape
        if self._cuda_graph._touched is None:
            self.reset()
        obs, reward, terminated, truncated, final_obs, log = self._cuda_graph(action)
        self._sim_step_counter += self.cfg.decimation
        self.common_step_counter += 1
        self.obs_buf, self.reward_buf = obs, reward
        self.reset_terminated, self.reset_time_outs = terminated, truncated
        self.extras["time_outs"] = truncated
        if bool(self.reset_buf.any()):
            self.extras["final_obs"] = final_obs
            self.extras["log"] = log
        else:
            self.extras.pop("final_obs", None)
        return obs, reward, terminated, truncated, self.extras

    def _graph_step(self, action: torch.Tensor):
        """The body of a graphed step: fixed shapes, resets by mask (see ``CudaGraphStep``)."""
        self.action_manager.process_action(action)
        self._physics_steps(self.action_manager.apply_action)
        self.episode_length_buf += 1
        self.reset_buf = self.termination_manager.compute()
        terminated, truncated = self.termination_manager.terminated, self.termination_manager.time_outs
        reward = self.reward_manager.compute(dt=self.step_dt)
        log = {
            **self.reward_manager.episode_log(self.reset_buf),
            **self.termination_manager.episode_log(self.reset_buf),
        }
        final_obs = self.observation_manager.compute(update_history=False)
        self._cuda_graph.masked_reset(self.reset_buf)
        self.sim.physics.mark_stale()
        self.command_manager.compute(dt=self.step_dt)
        obs = self.observation_manager.compute(update_history=True)
        return obs, reward, terminated, truncated, final_obs, log

    def render(self, recompute: bool = False) -> np.ndarray | None:
        """``rgb_array``: an (H, W, 3) uint8 image of env ``cfg.viewer.env_index``; ``human``: show it
        in MuJoCo's viewer window (needs a display); None: nothing to render."""
        if self.render_mode == "rgb_array":
            return self._render_rgb()
        if self.render_mode == "human":
            self._render_human()
            return None
        raise RuntimeError(
            "render() needs a render mode: build the env with render_mode='rgb_array' (images) or 'human' (a window),"
            " e.g. gym.make(task, cfg=cfg, render_mode='rgb_array')"
        )

    def close(self) -> None:
        if not self._is_closed:
            super().close()

    # -- helpers -------------------------------------------------------------------------------------

    def _reset_idx(self, env_ids: torch.Tensor) -> None:
        if getattr(self, "_learn_footprint", False):
            self._learn_footprint = False
            self._cuda_graph.learn_reset_footprint()  # runs _reset_idx on every env
            return
        self.curriculum_manager.compute(env_ids=env_ids)
        self.scene.reset(env_ids)
        if "reset" in self.event_manager.available_modes:
            env_step_count = self._sim_step_counter // self.cfg.decimation
            self.event_manager.apply(mode="reset", env_ids=env_ids, global_env_step_count=env_step_count)
        log: dict[str, Any] = {}
        log.update(self.observation_manager.reset(env_ids))
        log.update(self.action_manager.reset(env_ids))
        log.update(self.reward_manager.reset(env_ids))
        log.update(self.curriculum_manager.reset(env_ids))
        log.update(self.command_manager.reset(env_ids))
        log.update(self.event_manager.reset(env_ids))
        log.update(self.termination_manager.reset(env_ids))
        self.extras["log"] = log
        self.episode_length_buf[env_ids] = 0

    def _render_human(self) -> None:
        show_in_viewer(self)
