"""The direct workflow: one class computes observations, rewards and dones itself.

A task subclasses :class:`DirectRLEnv` and writes the hooks (Isaac Lab's API)::

    _setup_scene()            # create assets (Articulation(cfg), spawners) before the model compiles
    _pre_physics_step(a)      # once per env step: store / scale the actions
    _apply_action()           # every physics step: set joint targets from the stored actions
    _get_dones()              # -> (terminated, time_out), each (num_envs,) bool
    _get_rewards()            # -> (num_envs,) reward
    _reset_mask(env_mask)     # write the initial state where the (num_envs,) bool mask is set
      or _reset_idx(env_ids)  # Isaac Lab's form: the same for a list of env ids (call super() first)
    _get_observations()       # -> {"policy": (num_envs, ...)[, "critic": ...]}
    _get_states()             # -> critic observation, optional (asymmetric actor-critic)

``step(action)`` runs ``_pre_physics_step`` once and ``decimation`` physics steps, then counts the
step, asks for dones and rewards, resets the envs that finished (Gymnasium's SAME_STEP autoreset)
and returns ``(obs, reward, terminated, truncated, extras)``; ``docs/env_step.md`` states what the
returned values and ``extras`` mean, the same for every workflow.

Resets. A task written with ``_reset_mask`` draws its random initial states for every env and writes
them where the mask is set (the asset writers take the mask with values for every env): the step
then has fixed shapes and, on the GPU, replays as one CUDA graph. A task that overrides Isaac Lab's
``_reset_idx`` instead works unchanged, with its step run eagerly (the ids are data-dependent).
Calling ``_reset_idx(env_ids)`` on a ``_reset_mask`` task resets those envs through the mask.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import MISSING
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
import torch

from simlab.scene import InteractiveScene
from simlab.sim import SimulationContext
from simlab.utils.debug_vis import DebugVisHooks
from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.errors import ConfigError

from .common import SimulatedEnv
from .direct_rl_env_cfg import DirectRLEnvCfg
from .utils.cuda_graph import EnvStepper
from .utils.spaces import check_action, sample_space, spec_to_gym_space
from .utils.viewer import camera_pose, close_renderer, render_frame, show_in_viewer  # noqa: F401 - camera_pose re-exported

logger = logging.getLogger(__name__)

RENDER_MODES = [None, "human", "rgb_array"]


class DirectRLEnv(DebugVisHooks, SimulatedEnv, gym.Env):
    """A vectorized environment of ``num_envs`` copies; tensors have the env dimension first."""

    is_vector_env: ClassVar[bool] = True
    metadata: ClassVar[dict[str, Any]] = {
        "render_modes": RENDER_MODES,
        "autoreset_mode": gym.vector.AutoresetMode.SAME_STEP,
    }

    def __init__(self, cfg: DirectRLEnvCfg, render_mode: str | None = None, **kwargs):
        apply_deprecated_space_fields(
            cfg,
            ("observation_space", "num_observations"),
            ("action_space", "num_actions"),
            ("state_space", "num_states"),
        )
        cfg.validate()
        check_env_cfg(cfg)
        build_simulation(self, cfg, render_mode)

        self.extras: dict[str, Any] = {}
        self._sim_step_counter = 0
        self.common_step_counter = 0
        self.episode_length_buf = torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
        self.reset_terminated = torch.zeros(self.num_envs, dtype=torch.bool, device=self.device)
        self.reset_time_outs = torch.zeros_like(self.reset_terminated)
        self.reset_buf = torch.zeros_like(self.reset_terminated)
        self._all_env_ids = torch.arange(self.num_envs, dtype=torch.long, device=self.device)
        self._step_count = torch.zeros((), dtype=torch.long, device=self.device)
        """Env steps taken, on the device (what a graphed step's event terms read)."""
        self._configure_gym_env_spaces()
        self._action_noise_model = self._noise_model(cfg.action_noise_model, self.single_action_space)
        self._observation_noise_model = self._noise_model(
            cfg.observation_noise_model, self.single_observation_space["policy"]
        )

        if self.event_manager is not None and "startup" in self.event_manager.available_modes:
            self.event_manager.apply(mode="startup")
        self.metadata["render_fps"] = 1.0 / self.step_dt
        self._stepper = EnvStepper(self, self._step_body, action_space=self.single_action_space)

    def __del__(self):
        if getattr(self, "_is_closed", True) is False:
            self.close()

    # -- operations -------------------------------------------------------------------------------

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[dict, dict]:
        """Reset every environment; returns ``(obs, extras)``. Call once, then only ``step``."""
        if seed is not None:
            self.seed(seed)
        self._reset_idx(self._all_env_ids)
        self.scene.write_data_to_sim()
        self.sim.physics.mark_reset()
        self.obs_buf = self._observations()
        return self.obs_buf, self.extras

    def step(self, action: torch.Tensor) -> tuple[dict, torch.Tensor, torch.Tensor, torch.Tensor, dict]:
        """Apply ``action`` (num_envs, ...) for ``decimation`` physics steps; see the module docstring."""
        action = check_action(action, self.single_action_space, self.num_envs, self.device)
        # Host counters first: eager hooks (curricula, events) read them during the step.
        self._sim_step_counter += self.cfg.decimation
        self.common_step_counter += 1
        obs, reward, terminated, truncated, final_obs, diverged = self._stepper(action)
        self.obs_buf, self.reward_buf = obs, reward
        if final_obs is not None:
            self.extras["final_obs"] = final_obs
        self.extras["time_outs"] = truncated
        # a new dict each step: loggers keep one per step (rsl_rl averages them), so one shared dict
        # would report only the last step's count
        self.extras["log"] = {**self.extras.get("log", {}), "Physics/diverged": diverged}
        return obs, reward, terminated, truncated, self.extras

    def graph_blockers(self) -> list[str]:
        """What makes this env's step select envs by ids (so it cannot be captured as a graph)."""
        blockers = []
        if not self._resets_by_mask:
            blockers.append(
                f"{type(self).__name__} overrides _reset_idx (resets by env ids); override _reset_mask(env_mask)"
                " instead to let the step replay as a CUDA graph"
            )
        if self.event_manager is not None:
            blockers += self.event_manager.graph_blockers()
        return blockers

    def _step_body(self, action: torch.Tensor):
        """The step (Isaac Lab's order), with fixed shapes: run eagerly or replayed as a graph."""
        if self._action_noise_model is not None:
            action = self._action_noise_model(action)
        self._pre_physics_step(action)
        self._physics_steps(self._apply_action)
        diverged = self._restart_diverged()
        self.episode_length_buf += 1
        self._step_count += 1
        terminated, time_outs = self._get_dones()
        torch.logical_or(terminated, diverged, out=self.reset_terminated)
        self.reset_time_outs.copy_(time_outs)
        torch.logical_or(self.reset_terminated, self.reset_time_outs, out=self.reset_buf)
        reward = self._get_rewards()
        # what the finished envs ended in, for bootstrapping (cfg.final_observations)
        final_obs = self._observations() if self.cfg.final_observations else None
        self._reset_finished(self.reset_buf)
        if self.event_manager is not None and "interval" in self.event_manager.available_modes:
            self.event_manager.apply(mode="interval", dt=self.step_dt)
        obs = self._observations()
        if self._observation_noise_model is not None:  # as Isaac Lab: the step's policy obs, not reset()'s
            obs["policy"] = self._observation_noise_model(obs["policy"])
        return obs, reward, self.reset_terminated, self.reset_time_outs, final_obs, diverged.sum()

    @property
    def _resets_by_mask(self) -> bool:
        return type(self)._reset_idx is DirectRLEnv._reset_idx

    def _reset_finished(self, finished: torch.Tensor) -> None:
        """SAME_STEP autoreset of the envs where ``finished`` is set."""
        if self._resets_by_mask:
            self._reset_mask(finished)
        else:  # the task's Isaac Lab-style _reset_idx: ids, so this step runs eagerly
            env_ids = finished.nonzero().flatten()
            if len(env_ids):
                self._reset_idx(env_ids)
        self.sim.physics.mark_reset(finished)  # body poses follow when read

    def render(self, recompute: bool = False) -> np.ndarray | None:
        """An RGB frame (H, W, 3) of env ``cfg.viewer.env_index`` for ``render_mode="rgb_array"``;
        ``"human"`` shows the envs in the live viewer (``simlab.viewer``); None renders nothing."""
        if self.render_mode == "human":
            return show_in_viewer(self)
        if self.render_mode != "rgb_array":
            return None
        return render_frame(self, self.cfg.viewer)

    def close(self) -> None:
        """Release the simulation (the SimulationContext instance is cleared)."""
        if self._is_closed:
            return
        close_renderer(self)
        self.event_manager = None
        if getattr(self, "_stepper", None) is not None:  # the MARL env shares this close
            self._stepper.release()
        if SimulationContext.instance() is getattr(self, "sim", None):
            SimulationContext.clear_instance()
        self._is_closed = True

    def _debug_vis_simulation(self) -> SimulationContext:
        return self.sim

    # -- helpers ----------------------------------------------------------------------------------

    def _configure_gym_env_spaces(self) -> None:
        """Single and batched spaces; ``observation_space`` batches the policy space (as Isaac Lab)."""
        self.single_observation_space = gym.spaces.Dict()
        self.single_observation_space["policy"] = spec_to_gym_space(self.cfg.observation_space)
        self.single_action_space = spec_to_gym_space(self.cfg.action_space)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space["policy"], self.num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)
        self.state_space = None
        if self.cfg.state_space:
            self.single_observation_space["critic"] = spec_to_gym_space(self.cfg.state_space)
            self.state_space = gym.vector.utils.batch_space(self.single_observation_space["critic"], self.num_envs)
        # tasks whose observations include the last action read it before the first step
        self.actions = sample_space(self.single_action_space, self.device, batch_size=self.num_envs, fill_value=0)

    def _noise_model(self, cfg, space: gym.spaces.Space):
        """The noise model ``cfg`` describes (None for none), sized for a batch of ``space``."""
        if cfg is None:
            return None
        if not isinstance(space, gym.spaces.Box) or len(space.shape) != 1:
            raise ConfigError(
                f"{type(self.cfg).__name__}: a noise model needs a flat Box space (one vector per env), got {space}"
            )
        model = cfg.class_type(cfg, num_envs=self.num_envs, device=self.device)
        # a first batch sizes per-component state now, so that no step allocates it
        model(torch.zeros((self.num_envs, space.shape[0]), device=self.device))
        return model

    def _observations(self) -> dict:
        """The task's observations, with ``"critic"`` from ``_get_states`` when a state space is set."""
        obs = self._get_observations()
        if self.cfg.state_space and "critic" not in obs:
            states = self._get_states()
            if states is not None:
                obs["critic"] = states
        return obs

    def _reset_idx(self, env_ids: Sequence[int] | torch.Tensor) -> None:
        """Reset the envs ``env_ids`` (Isaac Lab's hook): through ``_reset_mask`` unless a task
        overrides this with its own index-based reset (calling ``super()._reset_idx`` first)."""
        self._reset_mask(env_mask(env_ids, self.num_envs, self.device))

    def _reset_mask(self, env_mask: torch.Tensor) -> None:
        """Reset the scene's entities, reset events and episode counters where ``env_mask`` is set;
        tasks extend it (call ``super()._reset_mask`` first) to write their initial states."""
        self.scene.reset(env_mask)
        if self.event_manager is not None and "reset" in self.event_manager.available_modes:
            self.event_manager.apply(mode="reset", env_ids=env_mask, global_env_step_count=self._step_count)
        masked_copy_(self.episode_length_buf, env_mask, 0)
        for model in (self._action_noise_model, self._observation_noise_model):
            if model is not None:  # a new bias for each new episode
                model.reset(env_mask)

    # -- the task's hooks -------------------------------------------------------------------------

    def _setup_scene(self) -> None:
        """Create the task's assets (``Articulation(cfg)``, ground, lights) before the model compiles."""

    def _pre_physics_step(self, actions: torch.Tensor) -> None:
        raise NotImplementedError(f"Please implement the '_pre_physics_step' method for {type(self).__name__}.")

    def _apply_action(self) -> None:
        raise NotImplementedError(f"Please implement the '_apply_action' method for {type(self).__name__}.")

    def _get_observations(self) -> dict:
        raise NotImplementedError(f"Please implement the '_get_observations' method for {type(self).__name__}.")

    def _get_states(self) -> torch.Tensor | dict | None:
        """The critic's observation for asymmetric actor-critic; None without a state space."""
        return None

    def _get_rewards(self) -> torch.Tensor:
        raise NotImplementedError(f"Please implement the '_get_rewards' method for {type(self).__name__}.")

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        raise NotImplementedError(f"Please implement the '_get_dones' method for {type(self).__name__}.")


# -- shared with the multi-agent env -----------------------------------------------------------------


def build_simulation(env, cfg, render_mode: str | None) -> None:
    """What a direct env's constructor does first: seed, a new simulation, the scene (declared
    entities, then the task's ``_setup_scene``), ``prestartup`` events, then compile."""
    if render_mode not in RENDER_MODES:
        raise ValueError(f"Unknown render_mode '{render_mode}'; allowed: {RENDER_MODES}")
    env.cfg = cfg
    env.render_mode = render_mode
    env._is_closed = False
    env._renderer = None
    env.metadata = dict(type(env).metadata)  # per instance: render_fps depends on the config
    if cfg.seed is not None:
        cfg.seed = env.seed(cfg.seed)
    else:
        logger.warning("Seed not set for the environment: its creation may not be deterministic.")
    # A new simulation per env: the previous one (and its model) is discarded.
    SimulationContext.clear_instance()
    env.sim = SimulationContext(cfg.sim)
    env.sim.set_camera_view(cfg.viewer.eye, cfg.viewer.lookat)
    env.scene = InteractiveScene(cfg.scene)
    env._setup_scene()
    env.event_manager = make_event_manager(cfg.events, env)
    if env.event_manager is not None and "prestartup" in env.event_manager.available_modes:
        env.event_manager.apply(mode="prestartup")
    env.sim.reset()
    env.scene.update(dt=env.physics_dt)


def apply_deprecated_space_fields(cfg, *pairs: tuple[str, str]) -> None:
    """Isaac Lab's old ``num_*`` fields fill the space fields left unset."""
    for space, old in pairs:
        if getattr(cfg, old, None) is not None and getattr(cfg, space, None) is MISSING:
            logger.warning(f"{type(cfg).__name__}.{old} is deprecated: use {space} instead.")
            setattr(cfg, space, getattr(cfg, old))


def check_env_cfg(cfg) -> None:
    """Errors for config values the env cannot run with."""
    if isinstance(cfg.decimation, bool) or not isinstance(cfg.decimation, int) or cfg.decimation < 1:
        raise ValueError(f"{type(cfg).__name__}.decimation must be an int >= 1, got {cfg.decimation!r}")
    if not cfg.episode_length_s > 0:
        raise ValueError(f"{type(cfg).__name__}.episode_length_s must be positive, got {cfg.episode_length_s!r}")


def make_event_manager(events_cfg, env):
    """An ``EventManager`` for ``cfg.events`` (None when there are no events)."""
    if events_cfg is None:
        return None
    try:
        from simlab.managers import EventManager
    except ImportError as err:
        raise ImportError("cfg.events needs simlab.managers.EventManager, which failed to import") from err
    return EventManager(events_cfg, env)
