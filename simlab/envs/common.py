"""Types and configs shared by the environments."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Literal

import torch

from simlab.utils import configclass
from simlab.utils.seed import set_seed


@configclass
class ViewerCfg:
    """Where the viewer camera (``env.render()``) looks from and at."""

    eye: tuple[float, float, float] = (7.5, 7.5, 7.5)
    """Camera position [m], in the frame given by ``origin_type``."""
    lookat: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Point the camera looks at [m], in the same frame."""
    cam_prim_path: str = "/OmniverseKit_Persp"
    """Kept for Isaac Lab configs; simlab renders with a MuJoCo free camera."""
    resolution: tuple[int, int] = (640, 480)
    """Rendered image size (width, height) in pixels."""
    origin_type: Literal["world", "env", "asset_root", "asset_body"] = "world"
    """Frame of ``eye`` and ``lookat``: the world, env ``env_index``'s origin, or an asset's root."""
    env_index: int = 0
    """The environment that is rendered (each environment is its own MuJoCo world)."""
    asset_name: str | None = None
    """For ``origin_type="asset_root"``: the scene entity the camera follows."""
    body_name: str | None = None
    """For ``origin_type="asset_body"``: the body of ``asset_name`` the camera follows."""


VecEnvObs = dict[str, torch.Tensor | dict[str, torch.Tensor]]
"""Observations of all envs: group name -> tensor (num_envs, ...) or dict of such tensors."""

VecEnvStepReturn = tuple[VecEnvObs, torch.Tensor, torch.Tensor, torch.Tensor, dict]
"""``(obs, reward, terminated, truncated, extras)``, each with the env dimension first."""


class SimulatedEnv:
    """What every simlab env reads off its config and simulation (``cfg``, ``sim``, ``scene``)."""

    @property
    def num_envs(self) -> int:
        return self.scene.num_envs

    @property
    def physics_dt(self) -> float:
        """The physics time step [s]."""
        return self.cfg.sim.dt

    def _physics_steps(self, apply_action: Callable[[], None], after_each: Callable[[], None] | None = None) -> None:
        """One env step's ``decimation`` physics steps, ``apply_action`` before each (``after_each``,
        if given, after each: the recorders' post-physics hook).

        Derived quantities (body poses, sensor data) are recomputed only when something reads
        them (``PhysicsBackend.ensure_forward``). Callers count ``_sim_step_counter``: a graphed
        step runs this Python once, at capture, and counts outside the graph.
        """
        render_steps = self.sim.has_step_callbacks  # Isaac Lab's render step: only when someone listens
        first = self._sim_step_counter - self.cfg.decimation  # the host counter already counts this step
        for i in range(self.cfg.decimation):
            apply_action()
            self.scene.write_data_to_sim()
            self.sim.step(render=False)
            if render_steps and (first + i + 1) % self.cfg.sim.render_interval == 0:
                self.sim.render()
            self.scene.update(dt=self.physics_dt)
            if after_each is not None:
                after_each()

    @property
    def step_is_graphed(self) -> bool:
        """Whether ``step`` replays one captured CUDA graph (see ``simlab.envs.utils.cuda_graph``)."""
        stepper = getattr(self, "_stepper", None)  # the RL envs run their step through one
        return stepper is not None and stepper.is_graphed

    @property
    def step_mode(self) -> str:
        """How ``step`` runs: 'graphed', 'warming up' (before the capture) or 'eager (<why>)'."""
        stepper = getattr(self, "_stepper", None)
        return stepper.mode if stepper is not None else "eager (ManagerBasedEnv steps eagerly)"

    def _restart_diverged(self) -> torch.Tensor:
        """The worlds whose physics blew up in this step (``PhysicsBackend.take_diverged``), put back
        to the model's initial state, with what the scene derived from the blown-up state cleared
        (``InteractiveScene.restart``: torques, actuator and contact histories), so that terminations
        and rewards read finite values there; the step ends their episodes (terminated)."""
        diverged = self.sim.physics.take_diverged()
        self.sim.physics.restart(diverged)
        self.scene.restart(diverged)
        return diverged

    @property
    def step_dt(self) -> float:
        """Seconds of simulation per env step: ``sim.dt * decimation``."""
        return self.cfg.sim.dt * self.cfg.decimation

    @property
    def device(self) -> str:
        return self.sim.device

    @property
    def max_episode_length_s(self) -> float:
        return self.cfg.episode_length_s

    @property
    def max_episode_length(self) -> int:
        """Env steps per episode: ``ceil(episode_length_s / step_dt)``."""
        return math.ceil(self.max_episode_length_s / self.step_dt)

    @staticmethod
    def seed(seed: int = -1) -> int:
        """Seed python, numpy and torch; returns the seed used (a drawn one for -1)."""
        return set_seed(seed)
