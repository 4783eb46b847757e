"""Configuration of a manager-based environment (no rewards: for that see ``ManagerBasedRLEnvCfg``)."""

from __future__ import annotations

from dataclasses import MISSING

import simlab.envs.mdp as mdp
from simlab.managers import EventTermCfg as EventTerm
from simlab.scene import InteractiveSceneCfg
from simlab.sim import SimulationCfg
from simlab.utils import configclass

from .common import ViewerCfg


@configclass
class DefaultEventManagerCfg:
    """Without events of its own, an env resets its scene to the default state."""

    reset_scene_to_default = EventTerm(func=mdp.reset_scene_to_default, mode="reset")


@configclass
class ManagerBasedEnvCfg:
    viewer: ViewerCfg = ViewerCfg()
    sim: SimulationCfg = SimulationCfg()
    ui_window_class_type: type | None = None
    seed: int | None = None
    """Seed of python, numpy and torch at construction (None: leave the generators alone)."""
    decimation: int = MISSING
    """Physics steps per env step; the action is held during them."""
    scene: InteractiveSceneCfg = MISSING
    recorders: object | None = None
    observations: object = MISSING
    actions: object = MISSING
    events: object | None = DefaultEventManagerCfg()
    rerender_on_reset: bool = False
    wait_for_textures: bool = True
    export_io_descriptors: bool = False
    log_dir: str | None = None
    check_finite_actions: bool = True
    """Raise on NaN/inf actions: at once in an eager step (a host read), at the periodic check of a
    graphed one (``simlab.envs.utils.cuda_graph``). False skips the check."""
