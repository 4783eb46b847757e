"""The manager-based RL environment: a ``gymnasium.Env`` over ``num_envs`` parallel worlds.

``step(action)`` returns ``(obs, reward, terminated, truncated, extras)``, tensors with the env
dimension first. Envs that finish are reset inside the same step (Gymnasium's SAME_STEP autoreset);
``docs/env_step.md`` states what the returned values and ``extras`` mean, the same for every
workflow. ``extras["log"]`` carries ``Episode_Reward/<term>`` and ``Episode_Termination/<term>`` of
the envs that reset in the step.

Order inside the step (Isaac Lab's): actions, ``decimation`` physics steps, episode counters,
terminations, rewards, resets, commands, ``interval`` events, observations. The envs that finished
are reset by mask: every manager and term resets its own per-env state where the mask is set, so
the step has fixed shapes and, on the GPU, replays as one CUDA graph (``simlab.envs.utils.cuda_graph``).
Body poses and other derived quantities are recomputed only if a term reads them
(``PhysicsBackend.ensure_forward``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import MISSING
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
import torch

from simlab.managers import CommandManager, CurriculumManager, RewardManager, TerminationManager
from simlab.utils.env_mask import env_mask, masked_copy_

from .common import VecEnvObs, VecEnvStepReturn
from .manager_based_env import ManagerBasedEnv
from .manager_based_rl_env_cfg import ManagerBasedRLEnvCfg
from .utils.cuda_graph import EnvStepper
from .utils.viewer import show_in_viewer


class ManagerBasedRLEnv(ManagerBasedEnv, gym.Env):
    is_vector_env: ClassVar[bool] = True
    metadata: ClassVar[dict[str, Any]] = {
        "render_modes": [None, "human", "rgb_array"],
        "autoreset_mode": gym.vector.AutoresetMode.SAME_STEP,
    }
    cfg: ManagerBasedRLEnvCfg
    log_refresh_on_device: bool = False
    """False: ``extras["log"]`` is replaced only in steps where some env finished (Isaac Lab's way;
    deciding that reads a flag back from the device every step). True: every step puts its logs in
    ``extras["log"]`` and whether they are fresh in ``extras["log_refreshed"]`` (a 0-d bool on the
    env's device), and the consumer picks the fresh ones itself: simlab's rsl_rl logger does, once
    per iteration, so a GPU rollout runs without a host sync per step."""

    def __init__(self, cfg: ManagerBasedRLEnvCfg, render_mode: str | None = None, **kwargs):
        if render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}")
        self.render_mode = render_mode
        length = cfg.episode_length_s  # MISSING is left to the config's validation, which names every missing field
        if length is not MISSING and not (isinstance(length, (int, float)) and length > 0):
            raise ValueError(f"cfg.episode_length_s must be a positive number of seconds, got {cfg.episode_length_s!r}")
        self.common_step_counter = 0
        super().__init__(cfg)
        self.metadata = dict(self.metadata, render_fps=1.0 / self.step_dt)
        self._stepper = EnvStepper(self, self._step_body)
        print("[INFO]: Completed setting up the environment...")

    # -- properties --------------------------------------------------------------------------------

    # -- building ----------------------------------------------------------------------------------

    def load_managers(self) -> None:
        # before the managers, whose terms may read it; not earlier: sim.reset() has just checked
        # that the worlds fit in memory
        self.episode_length_buf = torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
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
            else:  # a term's clip range bounds its space (Isaac Lab's)
                terms = zip(names, om.group_obs_term_dim[group], om._group_obs_term_cfgs[group])
                self.single_observation_space[group] = gym.spaces.Dict(
                    {
                        name: gym.spaces.Box(*((-np.inf, np.inf) if cfg.clip is None else cfg.clip), shape=dim)
                        for name, dim, cfg in terms
                    }
                )
        self.single_action_space = gym.spaces.Box(-np.inf, np.inf, shape=(self.action_manager.total_action_dim,))
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, self.num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)

    # -- operations --------------------------------------------------------------------------------

    def step(self, action: torch.Tensor) -> VecEnvStepReturn:
        action = self.action_manager.check_action(action)
        # Host counters first: eager hooks (curricula, events) read them during the step.
        self._sim_step_counter += self.cfg.decimation
        self.common_step_counter += 1
        obs, reward, terminated, truncated, final_obs, log = self._stepper(action)
        self.obs_buf, self.reward_buf = obs, reward
        self.reset_terminated, self.reset_time_outs = terminated, truncated
        if final_obs is not None:
            self.extras["final_obs"] = final_obs
        self.extras["time_outs"] = truncated
        # Episode logs are means over the envs that finished; as in Isaac Lab they are refreshed
        # only in steps where some env finished (one read of a flag per step, unless the consumer
        # reads the flags itself: log_refresh_on_device).
        if self.log_refresh_on_device:
            self.extras["log"] = log
            self.extras["log_refreshed"] = self.reset_buf.any()
        elif bool(self.reset_buf.any()):
            self.extras["log"] = log
        return obs, reward, terminated, truncated, self.extras

    def graph_blockers(self) -> list[str]:
        """What makes this env's step select envs by ids (so it cannot be captured as a graph)."""
        blockers = self.event_manager.graph_blockers() + self.command_manager.graph_blockers()
        blockers += self.curriculum_manager.graph_blockers()
        if self.recorder_manager.active_terms:
            blockers.append("recorder terms are active (recording reads which envs reset)")
        if type(self)._reset_idx is not ManagerBasedRLEnv._reset_idx:
            blockers.append(f"{type(self).__name__} overrides _reset_idx")
        return blockers

    def _step_body(self, action: torch.Tensor):
        """The step, with fixed shapes: run eagerly or replayed as one CUDA graph."""
        self.action_manager.process_action(action)
        recording = bool(self.recorder_manager.active_terms)
        if recording:
            self.recorder_manager.record_pre_step()
        self._physics_steps(self.action_manager.apply_action, self._post_physics_recording())
        diverged = self._restart_diverged()
        self.episode_length_buf += 1
        self._step_count += 1
        self.reset_buf = self.termination_manager.compute()
        terminated, truncated = self.termination_manager.terminated, self.termination_manager.time_outs
        terminated |= diverged  # the managers' own buffers: the reset and the logs see it
        self.reset_buf |= diverged
        reward = self.reward_manager.compute(dt=self.step_dt)
        # The observation the finished episodes ended in, before their reset (for bootstrapping).
        final_obs = None
        if self.cfg.final_observations or recording:
            final_obs = self.observation_manager.compute(update_history=False)
        if recording:  # eager only (a graph blocker): the recorders take env ids
            self.obs_buf = final_obs
            self.recorder_manager.record_post_step()
            finished = self.reset_buf.nonzero().flatten()
            if len(finished):
                self.recorder_manager.record_pre_reset(finished)
        log = self._reset_envs(self.reset_buf)
        if recording and len(finished):
            self.recorder_manager.record_post_reset(finished)
        log["Physics/diverged"] = diverged.sum()
        self.command_manager.compute(dt=self.step_dt)
        if "interval" in self.event_manager.available_modes:
            self.event_manager.apply(mode="interval", dt=self.step_dt)
        obs = self.observation_manager.compute(update_history=True)
        return obs, reward, terminated, truncated, final_obs, log

    def reset(
        self, seed: int | None = None, env_ids: Sequence[int] | torch.Tensor | None = None, options: dict | None = None
    ) -> tuple[VecEnvObs, dict]:
        self.extras.pop("final_obs", None)
        return super().reset(seed=seed, env_ids=env_ids, options=options)

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
            if getattr(self, "command_manager", None) is not None:
                self.command_manager.set_debug_vis(False)  # else its arrows show in a later env's renders
            super().close()

    # -- helpers -------------------------------------------------------------------------------------

    def _reset_idx(self, env_ids: Sequence[int] | torch.Tensor) -> None:
        """Reset the envs ``env_ids`` (Isaac Lab's hook; ids or a bool mask); logs go to ``extras["log"]``."""
        self.extras["log"] = self._reset_envs(env_mask(env_ids, self.num_envs, self.device))

    def _reset_envs(self, mask: torch.Tensor) -> dict[str, Any]:
        """Reset where ``mask`` is set: curricula, scene, reset events, every manager, counters.
        Returns the episode log of those envs."""
        self.curriculum_manager.compute(env_ids=mask)
        self.scene.reset(mask)
        if "reset" in self.event_manager.available_modes:
            self.event_manager.apply(mode="reset", env_ids=mask, global_env_step_count=self._step_count)
        log: dict[str, Any] = {}
        for manager in (
            self.observation_manager,
            self.action_manager,
            self.reward_manager,
            self.curriculum_manager,
            self.command_manager,
            self.event_manager,
            self.termination_manager,
            self.recorder_manager,
        ):
            log.update(manager.reset(mask))
        masked_copy_(self.episode_length_buf, mask, 0)
        self.sim.physics.mark_reset(mask)  # the next physics step writes the scene's targets
        return log

    def _render_human(self) -> None:
        show_in_viewer(self)
