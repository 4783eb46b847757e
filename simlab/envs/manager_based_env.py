"""The manager-based environment: a scene stepped by actions, observed through managers.

Construction follows Isaac Lab: the simulation and the scene are built, the event manager (its
``prestartup`` events edit the model before it compiles), ``sim.reset()`` compiles and starts the
physics, then the action and observation managers, then the ``startup`` events.

``step(action)``: the action manager processes the action once, then for ``decimation`` physics
steps applies it, writes the scene to the simulation, steps, and updates the scene's sensors;
``interval`` events run, and observations are computed. No rewards: see ``ManagerBasedRLEnv``.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Sequence
from typing import Any

import numpy as np
import torch

from simlab.managers import ActionManager, EventManager, ObservationManager, RecorderManager
from simlab.managers.manager_term_cfg import ManagerTermBaseCfg, ObservationGroupCfg
from simlab.scene import InteractiveScene
from simlab.sim import SimulationContext
from simlab.utils.configclass import MissingFieldError
from simlab.utils.env_mask import env_mask
from simlab.utils.quat_order import refuse_other_order

from .common import SimulatedEnv, VecEnvObs
from .manager_based_env_cfg import ManagerBasedEnvCfg
from .utils import io_descriptors
from .utils.viewer import camera_pose, close_renderer, render_frame


class ManagerBasedEnv(SimulatedEnv):
    def __init__(self, cfg: ManagerBasedEnvCfg):
        try:
            cfg.validate()
        except MissingFieldError as err:
            raise MissingFieldError(f"The environment config is incomplete: {err}") from err
        # an Isaac Lab 3.0 config (an action's body_offset, a spawner) read as (w, x, y, z) would turn silently
        refuse_other_order(type(cfg).__name__, cfg, "env")
        if not isinstance(cfg.decimation, int) or cfg.decimation < 1:
            raise ValueError(f"cfg.decimation must be an int >= 1 (physics steps per env step), got {cfg.decimation!r}")
        self.cfg = cfg
        self._is_closed = False
        self._renderer = None
        self._viewer = None
        if cfg.seed is not None:
            cfg.seed = self.seed(cfg.seed)

        # A fresh simulation: a previous env's (or script's) context would hold the old model.
        SimulationContext.clear_instance()
        self.sim = SimulationContext(cfg.sim)
        self.sim.set_camera_view(cfg.viewer.eye, cfg.viewer.lookat)
        if cfg.sim.render_interval < cfg.decimation:
            print(
                f"[simlab] sim.render_interval ({cfg.sim.render_interval}) < decimation ({cfg.decimation}):"
                " renders happen once per env step anyway (render() is on demand)."
            )
        print("[INFO]: Base environment:")
        print(f"\tEnvironment device    : {self.device}")
        print(f"\tEnvironment seed      : {cfg.seed}")
        print(f"\tPhysics step-size     : {self.physics_dt}")
        print(f"\tEnvironment step-size : {self.step_dt}")

        self.scene = InteractiveScene(cfg.scene)
        print("[INFO]: Scene manager:", self.scene)

        # Events first: "prestartup" terms change the model before it is compiled.
        self.event_manager = EventManager(cfg.events, self)
        self.event_manager.apply(mode="prestartup")

        # Terms that need something of the model (a MuJoCo pass, a sensor) add it before it compiles.
        for term in _term_cfgs(cfg):
            prepare = getattr(term.func, "before_compile", None)
            if prepare is not None:
                prepare(self)

        self.sim.reset()
        self.scene.update(dt=self.physics_dt)

        self._sim_step_counter = 0
        self._step_count = torch.zeros((), dtype=torch.long, device=self.device)
        """Env steps taken, on the device (what a graphed step's event terms read)."""
        self.extras: dict[str, Any] = {}
        self.load_managers()
        print("[INFO]: Event Manager:", self.event_manager)
        self.obs_buf: VecEnvObs = {}
        if cfg.export_io_descriptors:
            self.export_IO_descriptors()

    def __del__(self):
        with contextlib.suppress(Exception):  # at interpreter shutdown modules may be gone
            self.close()

    # -- properties ------------------------------------------------------------------------------

    @property
    def unwrapped(self) -> ManagerBasedEnv:
        return self

    @property
    def get_IO_descriptors(self) -> dict[str, Any]:  # noqa: N802 - Isaac Lab's name
        """The policy's inputs and outputs (observations, actions), the articulations and time steps."""
        return io_descriptors.io_descriptors(self)

    def export_IO_descriptors(self, output_dir: str | None = None) -> str:  # noqa: N802 - Isaac Lab's name
        """Write ``IO_descriptors.yaml`` into ``output_dir`` (default: ``<cfg.log_dir>/io_descriptors``)."""
        if output_dir is None:
            if self.cfg.log_dir is None:
                raise ValueError(
                    "export_IO_descriptors: no output folder. Pass output_dir, or set env_cfg.log_dir"
                    " (simlab train sets it to the run folder)."
                )
            output_dir = os.path.join(self.cfg.log_dir, "io_descriptors")
        path = io_descriptors.export_io_descriptors(self, output_dir)
        print(f"[INFO]: Exported IO descriptors to {path}")
        return path

    # -- building ----------------------------------------------------------------------------------

    def load_managers(self) -> None:
        self.recorder_manager = RecorderManager(self.cfg.recorders, self)
        print("[INFO]: Recorder Manager:", self.recorder_manager)
        self.action_manager = ActionManager(self.cfg.actions, self)
        print("[INFO]: Action Manager:", self.action_manager)
        self.observation_manager = ObservationManager(self.cfg.observations, self)
        print("[INFO]: Observation Manager:", self.observation_manager)
        if type(self) is ManagerBasedEnv:
            self.event_manager.apply(mode="startup")

    # -- operations ----------------------------------------------------------------------------------

    def reset(
        self, seed: int | None = None, env_ids: Sequence[int] | torch.Tensor | None = None, options: dict | None = None
    ) -> tuple[VecEnvObs, dict]:
        """Reset the given envs (all by default); returns ``(obs, extras)``."""
        if seed is not None:
            self.seed(seed)
        mask = env_mask(env_ids, self.num_envs, self.device)
        self.recorder_manager.record_pre_reset(mask)
        self._reset_idx(mask)
        self.scene.write_data_to_sim()
        self.sim.physics.mark_reset(mask)
        self.recorder_manager.record_post_reset(mask)
        self.obs_buf = self.observation_manager.compute(update_history=True)
        return self.obs_buf, self.extras

    def reset_to(
        self,
        state: dict[str, dict[str, dict[str, torch.Tensor]]],
        env_ids: Sequence[int] | torch.Tensor | None = None,
        seed: int | None = None,
        is_relative: bool = False,
    ) -> tuple[VecEnvObs, dict]:
        """Reset ``env_ids`` (all by default), then put them in ``state`` (``scene.get_state``'s
        layout, one row per env of ``env_ids``): how a recorded demonstration is replayed."""
        mask = env_mask(env_ids, self.num_envs, self.device)
        ids = mask.nonzero().flatten()
        self.recorder_manager.record_pre_reset(ids)
        if seed is not None:
            self.seed(seed)
        self._reset_idx(mask)
        self.scene.reset_to(state, ids, is_relative=is_relative)  # marks the worlds reset
        self.recorder_manager.record_post_reset(ids)
        self.obs_buf = self.observation_manager.compute(update_history=True)
        return self.obs_buf, self.extras

    def step(self, action: torch.Tensor) -> tuple[VecEnvObs, dict]:
        self.action_manager.process_action(action)
        self.recorder_manager.record_pre_step()
        self._sim_step_counter += self.cfg.decimation  # host counters first, as in the RL envs
        self._physics_steps(self.action_manager.apply_action, self._post_physics_recording())
        self._step_count += 1
        if "interval" in self.event_manager.available_modes:
            self.event_manager.apply(mode="interval", dt=self.step_dt)
        self.obs_buf = self.observation_manager.compute(update_history=True)
        self.recorder_manager.record_post_step()
        return self.obs_buf, self.extras

    def render(self, recompute: bool = False) -> np.ndarray:
        """An RGB image (H, W, 3) of env ``cfg.viewer.env_index`` from the viewer camera."""
        return self._render_rgb()

    def close(self) -> None:
        if self._is_closed:
            return
        close_renderer(self)
        if getattr(self, "recorder_manager", None) is not None:
            self.recorder_manager.close()  # exports the open episodes if cfg.recorders.export_in_close
        if getattr(self, "_stepper", None) is not None:  # the RL env's stepper
            self._stepper.release()
        if SimulationContext.instance() is getattr(self, "sim", None):
            SimulationContext.clear_instance()
        self._is_closed = True

    # -- helpers -------------------------------------------------------------------------------------

    def _reset_idx(self, env_ids: Sequence[int] | torch.Tensor) -> None:
        """Reset the envs ``env_ids`` (ids or a bool mask): scene, reset events, managers."""
        mask = env_mask(env_ids, self.num_envs, self.device)
        self.scene.reset(mask)
        if "reset" in self.event_manager.available_modes:
            self.event_manager.apply(mode="reset", env_ids=mask, global_env_step_count=self._step_count)
        self.extras["log"] = {}
        self.extras["log"].update(self.observation_manager.reset(mask))
        self.extras["log"].update(self.action_manager.reset(mask))
        self.extras["log"].update(self.event_manager.reset(mask))
        self.extras["log"].update(self.recorder_manager.reset(mask))

    def _post_physics_recording(self):
        """The recorders' after-each-physics-step hook, or None when nothing records."""
        return self.recorder_manager.record_post_physics_decimation_step if self.recorder_manager.active_terms else None

    def _camera_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """The viewer camera's eye and lookat in the frame of the rendered MuJoCo world."""
        return camera_pose(self, self.cfg.viewer)

    def _render_rgb(self) -> np.ndarray:
        return render_frame(self, self.cfg.viewer)


def _term_cfgs(cfg: ManagerBasedEnvCfg) -> list[ManagerTermBaseCfg]:
    """Every manager term of ``cfg`` (observation groups' terms included)."""
    terms: list[ManagerTermBaseCfg] = []
    for name in ("observations", "actions", "events", "rewards", "terminations", "curriculum", "commands"):
        section = getattr(cfg, name, None)
        for value in vars(section).values() if section is not None else ():
            if isinstance(value, ObservationGroupCfg):
                terms += [term for term in vars(value).values() if isinstance(term, ManagerTermBaseCfg)]
            elif isinstance(value, ManagerTermBaseCfg):
                terms.append(value)
    return [term for term in terms if callable(getattr(term, "func", None))]
