"""What the native and web viewer camera tests share: an env built with chosen ``cfg.viewer`` settings,
and one frame drawn by a viewer from the simulation's current state."""

from __future__ import annotations

import time

import gymnasium as gym

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.utils import load_cfg_from_registry


def make_env(task: str, num_envs: int = 2, **viewer):
    """``task`` on the CPU with ``num_envs`` envs, its ``cfg.viewer`` fields set from ``viewer``, reset."""
    cfg = load_cfg_from_registry(task, "env_cfg_entry_point")
    cfg.scene.num_envs, cfg.sim.device = num_envs, "cpu"
    for name, value in viewer.items():
        setattr(cfg.viewer, name, value)
    env = gym.make(task, cfg=cfg)
    env.reset(seed=0)
    return env


def draw_frame(viewer) -> None:
    """One frame drawn from the simulation's current state (the viewer's next frame is due at once)."""
    drawn = viewer.frames_drawn
    viewer._next_frame = 0.0
    viewer.after_step()
    deadline = time.monotonic() + 10
    while viewer.frames_drawn == drawn and time.monotonic() < deadline:
        time.sleep(0.01)
    assert viewer.frames_drawn > drawn and not viewer.failed
