"""The direct workflow for several agents acting in the same environments (Isaac Lab's ``DirectMARLEnv``).

Same life cycle and hooks as :class:`~simlab.envs.DirectRLEnv`, with dicts keyed by agent name
where the single-agent env has tensors: ``step({agent: action})`` returns per-agent observations,
rewards, terminations and time-outs, each with the env dimension first. ``state()`` is the shared
state of centralized critics. An environment resets once every agent in it is done (the flags are
ANDed over agents) and, as in the single-agent env, in the same step (SAME_STEP autoreset); the
observations reached before the reset are kept in ``extras[agent]["final_obs"]`` and the state in
``final_state_buf``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar

import gymnasium as gym
import torch

from simlab.utils.debug_vis import DebugVisHooks

from .common import SimulatedEnv
from .direct_marl_env_cfg import DirectMARLEnvCfg
from .direct_rl_env import (
    RENDER_MODES,
    DirectRLEnv,
    apply_deprecated_space_fields,
    build_simulation,
    check_env_cfg,
)
from .utils.cuda_graph import EnvStepper
from .utils.spaces import check_action, sample_space, spec_to_gym_space


class DirectMARLEnv(DebugVisHooks, SimulatedEnv, gym.Env):
    """``num_envs`` environments, each with the agents of ``cfg.possible_agents``."""

    metadata: ClassVar[dict[str, Any]] = {
        "render_modes": RENDER_MODES,
        "autoreset_mode": gym.vector.AutoresetMode.SAME_STEP,
    }

    def __init__(self, cfg: DirectMARLEnvCfg, render_mode: str | None = None, **kwargs):
        apply_deprecated_space_fields(
            cfg,
            ("observation_spaces", "num_observations"),
            ("action_spaces", "num_actions"),
            ("state_space", "num_states"),
        )
        cfg.validate()
        check_env_cfg(cfg)
        check_agents(cfg)
        build_simulation(self, cfg, render_mode)

        self.extras: dict[str, dict] = {agent: {} for agent in cfg.possible_agents}
        self._sim_step_counter = 0
        self.common_step_counter = 0
        self.episode_length_buf = torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
        self.reset_buf = torch.zeros(self.num_envs, dtype=torch.bool, device=self.device)
        self.final_state_buf: torch.Tensor | None = None
        self._all_env_ids = torch.arange(self.num_envs, dtype=torch.long, device=self.device)
        self._step_count = torch.zeros((), dtype=torch.long, device=self.device)
        self._configure_env_spaces()

        if self.event_manager is not None and "startup" in self.event_manager.available_modes:
            self.event_manager.apply(mode="startup")
        self.metadata["render_fps"] = 1.0 / self.step_dt
        self._stepper = EnvStepper(self, self._step_body, action_space=gym.spaces.Dict(self.action_spaces))

    def __del__(self):
        if getattr(self, "_is_closed", True) is False:
            self.close()

    # -- properties -------------------------------------------------------------------------------

    @property
    def num_agents(self) -> int:
        """Agents currently acting (those that returned observations)."""
        return len(self.agents)

    @property
    def max_num_agents(self) -> int:
        return len(self.possible_agents)

    @property
    def unwrapped(self) -> DirectMARLEnv:
        return self

    def observation_space(self, agent: str) -> gym.Space:
        """The observation space of one agent in one environment."""
        return self.observation_spaces[agent]

    @property
    def action_space(self) -> AgentActionSpaces | Callable[[str], gym.Space]:
        """Isaac Lab's ``action_space(agent)``: the action space of one agent in one environment.

        Also the batched space of all agents' actions side by side, for scripts written for
        single-agent envs (Isaac Lab's ``zero_agent.py`` reads ``env.action_space.shape`` and steps
        with one tensor, which :meth:`step` splits among the agents). Agents with other than Box
        spaces have no joint Box: then it is only the per-agent lookup."""
        if all(isinstance(space, gym.spaces.Box) for space in self.action_spaces.values()):
            return AgentActionSpaces(self.action_spaces, self.possible_agents, self.num_envs)
        return self.action_spaces.__getitem__

    # -- operations -------------------------------------------------------------------------------

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[dict, dict]:
        """Reset every environment; returns ``({agent: obs}, extras)``."""
        if seed is not None:
            self.seed(seed)
        self._reset_idx(self._all_env_ids)
        self.scene.write_data_to_sim()
        self.sim.physics.mark_reset()
        self.obs_dict = self._get_observations()
        self.agents = [agent for agent in self.possible_agents if agent in self.obs_dict]
        return self.obs_dict, self.extras

    def step(self, actions: dict[str, torch.Tensor] | torch.Tensor) -> tuple[dict, dict, dict, dict, dict]:
        """Apply each agent's action (num_envs, ...) for ``decimation`` physics steps.

        One tensor (num_envs, total) holds the agents' actions side by side in ``possible_agents`` order."""
        if isinstance(actions, torch.Tensor) and isinstance(self.action_space, AgentActionSpaces):
            actions = self.action_space.split(actions)
        missing = [agent for agent in self.agents if agent not in actions]
        if missing:
            raise KeyError(
                f"No action for agents {missing}; step() takes a dict with an action for each of {self.agents}"
            )
        unknown = [agent for agent in actions if agent not in self.action_spaces]
        if unknown:
            raise KeyError(f"Actions for unknown agents {unknown}; agents: {self.possible_agents}")
        actions = {
            agent: check_action(action, self.action_spaces[agent], self.num_envs, self.device)
            for agent, action in actions.items()
        }
        # Host counters first: eager hooks (curricula, events) read them during the step.
        self._sim_step_counter += self.cfg.decimation
        self.common_step_counter += 1
        obs, rewards, terminated, time_outs, final_obs, self.final_state_buf = self._stepper(actions)
        self.obs_dict, self.reward_dict = obs, rewards
        # terminated_dict / time_out_dict stay the step body's own: a graphed step's replays refill
        # them, so they must not be the tensors handed to the caller (the caller may keep those)
        self.agents = [agent for agent in self.possible_agents if agent in self.obs_dict]
        for agent in self.possible_agents:
            extras = self.extras.setdefault(agent, {})
            if agent in final_obs:
                extras["final_obs"] = final_obs[agent]
        return self.obs_dict, self.reward_dict, terminated, time_outs, self.extras

    def _step_body(self, actions: dict[str, torch.Tensor]):
        """The step, as the single-agent env's (fixed shapes: eager or replayed as a graph)."""
        self._pre_physics_step(actions)
        self._physics_steps(self._apply_action)
        diverged = self._restart_diverged()
        self.episode_length_buf += 1
        self._step_count += 1
        terminated, time_outs = self._get_dones()
        terminated = {agent: done | diverged for agent, done in terminated.items()}
        self.terminated_dict, self.time_out_dict = terminated, time_outs  # tasks' rewards read them
        # an environment resets once all its agents are done
        torch.logical_or(all_agents(terminated), all_agents(time_outs), out=self.reset_buf)
        rewards = self._get_rewards()
        final_obs = self._get_observations()
        final_state = self._state_of(final_obs)
        self._reset_finished(self.reset_buf)
        if self.event_manager is not None and "interval" in self.event_manager.available_modes:
            self.event_manager.apply(mode="interval", dt=self.step_dt)
        return self._get_observations(), rewards, terminated, time_outs, final_obs, final_state

    def state(self) -> torch.Tensor | None:
        """The shared state (num_envs, ...): the agents' observations concatenated for
        ``state_space=-1``, ``_get_states()`` for a declared space, None for ``state_space=0``.

        After a step that reset envs, ``final_state_buf`` holds the state reached before the reset.
        """
        self.state_buf = self._state_of(self.obs_dict)
        return self.state_buf

    def _state_of(self, obs_dict: dict[str, torch.Tensor]) -> torch.Tensor | None:
        if not self.cfg.state_space:
            return None
        if isinstance(self.cfg.state_space, int) and self.cfg.state_space < 0:
            return torch.cat([obs_dict[agent].reshape(self.num_envs, -1) for agent in self.possible_agents], dim=-1)
        return self._get_states()

    # Rendering, closing and debug visualisation work as in the single-agent direct env.
    render = DirectRLEnv.render
    close = DirectRLEnv.close
    _debug_vis_simulation = DirectRLEnv._debug_vis_simulation

    # -- helpers ----------------------------------------------------------------------------------

    def _configure_env_spaces(self) -> None:
        self.agents = list(self.cfg.possible_agents)
        self.possible_agents = list(self.cfg.possible_agents)
        self.observation_spaces = {a: spec_to_gym_space(self.cfg.observation_spaces[a]) for a in self.possible_agents}
        self.action_spaces = {a: spec_to_gym_space(self.cfg.action_spaces[a]) for a in self.possible_agents}
        if not self.cfg.state_space:
            self.state_space = None
        elif isinstance(self.cfg.state_space, int) and self.cfg.state_space < 0:
            self.state_space = gym.spaces.flatten_space(
                gym.spaces.Tuple([self.observation_spaces[a] for a in self.possible_agents])
            )
        else:
            self.state_space = spec_to_gym_space(self.cfg.state_space)
        self.actions = {
            a: sample_space(self.action_spaces[a], self.device, batch_size=self.num_envs, fill_value=0)
            for a in self.possible_agents
        }

    # Resets (by mask, or a task's own _reset_idx) and stepping work as in the single-agent env,
    # which also resets its noise models' state: the multi-agent env has none.
    _action_noise_model = None
    _observation_noise_model = None
    _reset_idx = DirectRLEnv._reset_idx
    _reset_mask = DirectRLEnv._reset_mask
    _reset_finished = DirectRLEnv._reset_finished
    _resets_by_mask = DirectRLEnv._resets_by_mask
    graph_blockers = DirectRLEnv.graph_blockers

    # -- the task's hooks -------------------------------------------------------------------------

    def _setup_scene(self) -> None:
        """Create the task's assets before the model compiles."""

    def _pre_physics_step(self, actions: dict[str, torch.Tensor]) -> None:
        raise NotImplementedError(f"Please implement the '_pre_physics_step' method for {type(self).__name__}.")

    def _apply_action(self) -> None:
        raise NotImplementedError(f"Please implement the '_apply_action' method for {type(self).__name__}.")

    def _get_observations(self) -> dict[str, torch.Tensor]:
        raise NotImplementedError(f"Please implement the '_get_observations' method for {type(self).__name__}.")

    def _get_states(self) -> torch.Tensor:
        raise NotImplementedError(
            f"Please implement the '_get_states' method for {type(self).__name__} "
            "(or set state_space to -1 to concatenate the observations, or 0 for no state)."
        )

    def _get_rewards(self) -> dict[str, torch.Tensor]:
        raise NotImplementedError(f"Please implement the '_get_rewards' method for {type(self).__name__}.")

    def _get_dones(self) -> tuple[dict[str, torch.Tensor], dict[str, torch.Tensor]]:
        raise NotImplementedError(f"Please implement the '_get_dones' method for {type(self).__name__}.")


def all_agents(flags: dict[str, torch.Tensor]) -> torch.Tensor:
    """True where the flag is set for every agent."""
    values = iter(flags.values())
    out = next(values).bool()
    for value in values:
        out = out & value
    return out


def check_agents(cfg: DirectMARLEnvCfg) -> None:
    """Every agent needs an observation and an action space, and nothing else may have one."""
    agents = list(cfg.possible_agents)
    if not agents or len(set(agents)) != len(agents):
        raise ValueError(f"possible_agents must be a non-empty list of distinct names, got {agents}")
    for field in ("observation_spaces", "action_spaces"):
        spaces = getattr(cfg, field)
        if not isinstance(spaces, dict) or set(spaces) != set(agents):
            keys = sorted(spaces) if isinstance(spaces, dict) else spaces
            raise ValueError(f"{type(cfg).__name__}.{field} must have one entry per agent {agents}, got {keys}")
    for name in ("observation_noise_model", "action_noise_model"):
        if getattr(cfg, name, None):
            raise NotImplementedError(
                f"{type(cfg).__name__}.{name}: per-agent noise models are not supported yet; set it to None"
            )


class AgentActionSpaces(gym.spaces.Box):
    """The agents' action spaces: called with an agent's name, that agent's space (Isaac Lab's
    ``env.action_space(agent)``); as a space, the batched Box (num_envs, sum of the agents' sizes)
    of all their actions side by side in ``possible_agents`` order."""

    def __init__(self, spaces: dict[str, gym.spaces.Box], agents: list[str], num_envs: int):
        self._spaces, self._agents = spaces, list(agents)
        boxes = [spaces[a] for a in self._agents]
        low = torch.cat([torch.as_tensor(b.low).reshape(-1) for b in boxes]).numpy()
        high = torch.cat([torch.as_tensor(b.high).reshape(-1) for b in boxes]).numpy()
        super().__init__(low=low[None].repeat(num_envs, 0), high=high[None].repeat(num_envs, 0), dtype=low.dtype)

    def __call__(self, agent: str) -> gym.Space:
        return self._spaces[agent]

    def split(self, actions: torch.Tensor) -> dict[str, torch.Tensor]:
        """One (num_envs, total) tensor -> {agent: (num_envs, *agent's shape)}."""
        if actions.shape[-1] != self.shape[-1]:
            raise ValueError(
                f"One action tensor for all agents must be (num_envs, {self.shape[-1]}): the agents' actions side"
                f" by side in the order {self._agents}; got {tuple(actions.shape)}. Or step with {{agent: action}}."
            )
        sizes = [int(torch.tensor(self._spaces[a].shape).prod()) for a in self._agents]
        parts = torch.split(actions, sizes, dim=-1)
        return {a: p.reshape(-1, *self._spaces[a].shape) for a, p in zip(self._agents, parts)}
