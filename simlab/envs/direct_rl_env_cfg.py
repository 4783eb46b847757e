"""Configuration of a direct-workflow RL environment (Isaac Lab's ``DirectRLEnvCfg``)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.scene import InteractiveSceneCfg
from simlab.sim import SimulationCfg
from simlab.utils import configclass

from .common import ViewerCfg
from .utils.spaces import SpaceType


@configclass
class DirectRLEnvCfg:
    """What a :class:`~simlab.envs.DirectRLEnv` needs; a task subclasses it and adds its own fields.

    Spaces (``observation_space``, ``action_space``, ``state_space``) are Gymnasium spaces or the
    short Python specs of :mod:`simlab.envs.utils.spaces` (``4`` is a 4-vector Box).
    """

    viewer: ViewerCfg = ViewerCfg()
    """Camera of ``env.render()`` (and of recorded videos)."""
    sim: SimulationCfg = SimulationCfg()
    """Physics: time step, device, solver options."""
    ui_window_class_type: type | None = None
    """Kept for ported configs; simlab has no GUI window."""
    seed: int | None = None
    """Seed of python, numpy and torch, set before the scene is built (None: not seeded)."""
    decimation: int = MISSING
    """Physics steps per environment step."""
    is_finite_horizon: bool = False
    """Whether time-outs are true ends of the task (no bootstrapping) rather than truncations.

    The env always reports time-outs in ``truncated`` / ``extras["time_outs"]``; RL wrappers read this
    flag to decide whether to bootstrap on them.
    """
    final_observations: bool = True
    """Compute ``extras["final_obs"]`` each step: the observations the finished envs ended in, from
    which Stable-Baselines3 bootstraps time-outs. rsl_rl, skrl and rl_games do not read them; a camera
    task turns them off, since they would render every camera a second time per step."""
    episode_length_s: float = MISSING
    """Episode duration [s]; ``max_episode_length = ceil(episode_length_s / (sim.dt * decimation))``."""
    scene: InteractiveSceneCfg = MISSING
    """Number of environments, their spacing, and entities declared as config fields."""
    events: object | None = None
    """An event config (``EventTermCfg`` fields) applied by an ``EventManager``; None for none."""
    observation_space: SpaceType = MISSING
    """Space of the ``"policy"`` observation of one environment."""
    num_observations: int | None = None
    """Deprecated (Isaac Lab): use ``observation_space``."""
    state_space: SpaceType | None = None
    """Space of the ``"critic"`` observation (asymmetric actor-critic); None or 0 for none."""
    num_states: int | None = None
    """Deprecated (Isaac Lab): use ``state_space``."""
    observation_noise_model: object | None = None
    """A noise model config (``simlab.utils.noise.NoiseModelCfg``) applied to the ``"policy"`` observation
    each step (not to the one ``reset()`` returns, as Isaac Lab); None for none."""
    action_space: SpaceType = MISSING
    """Space of the action of one environment."""
    num_actions: int | None = None
    """Deprecated (Isaac Lab): use ``action_space``."""
    action_noise_model: object | None = None
    """A noise model config applied to the actions each step, before ``_pre_physics_step``; None for none.
    Per-env state (a bias) is redrawn where an episode restarts."""
    rerender_on_reset: bool = False
    """Kept for ported configs: rendering is on demand, so frames always show the current state."""
    num_rerenders_on_reset: int = 0
    """Kept for ported configs (see ``rerender_on_reset``)."""
    wait_for_textures: bool = True
    """Kept for ported configs; nothing to wait for."""
    xr: object | None = None
    """Kept for ported configs; XR devices are not supported."""
    log_dir: str | None = None
    """Directory of the run's logs, set by the train/play scripts."""
