"""Configuration of a direct-workflow multi-agent environment (Isaac Lab's ``DirectMARLEnvCfg``)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.scene import InteractiveSceneCfg
from simlab.sim import SimulationCfg
from simlab.utils import configclass

from .common import ViewerCfg
from .utils.spaces import SpaceType


@configclass
class DirectMARLEnvCfg:
    """What a :class:`~simlab.envs.DirectMARLEnv` needs; a task subclasses it and adds its own fields.

    Every agent has its own observation and action space (dicts keyed by the names in
    ``possible_agents``); all agents share one ``state_space`` (centralized critics, MAPPO).
    """

    viewer: ViewerCfg = ViewerCfg()
    """Camera of ``env.render()``."""
    sim: SimulationCfg = SimulationCfg()
    """Physics: time step, device, solver options."""
    ui_window_class_type: type | None = None
    """Kept for ported configs; simlab has no GUI window."""
    seed: int | None = None
    """Seed of python, numpy and torch, set before the scene is built (None: not seeded)."""
    decimation: int = MISSING
    """Physics steps per environment step."""
    is_finite_horizon: bool = False
    """Whether time-outs are true ends of the task (no bootstrapping); read by RL wrappers."""
    episode_length_s: float = MISSING
    """Episode duration [s]; ``max_episode_length = ceil(episode_length_s / (sim.dt * decimation))``."""
    scene: InteractiveSceneCfg = MISSING
    """Number of environments, their spacing, and entities declared as config fields."""
    events: object | None = None
    """An event config applied by an ``EventManager``; None for none."""
    possible_agents: list[str] = MISSING
    """Names of every agent the environment can have."""
    observation_spaces: dict[str, SpaceType] = MISSING
    """Observation space of each agent (one environment)."""
    num_observations: dict[str, int] | None = None
    """Deprecated (Isaac Lab): use ``observation_spaces``."""
    state_space: SpaceType = MISSING
    """Shared state: ``-1`` concatenates every agent's observation, ``0`` means none, anything else
    is a space that the task's ``_get_states`` fills."""
    num_states: int | None = None
    """Deprecated (Isaac Lab): use ``state_space``."""
    action_spaces: dict[str, SpaceType] = MISSING
    """Action space of each agent (one environment)."""
    num_actions: dict[str, int] | None = None
    """Deprecated (Isaac Lab): use ``action_spaces``."""
    observation_noise_model: dict | None = None
    """Per-agent observation noise. Noise models are not supported yet: keep None."""
    action_noise_model: dict | None = None
    """Per-agent action noise. Noise models are not supported yet: keep None."""
    xr: object | None = None
    """Kept for ported configs; XR devices are not supported."""
    log_dir: str | None = None
    """Directory of the run's logs, set by the train/play scripts."""
