"""How many contacts and constraint rows the worlds of a MuJoCo Warp simulation really use.

MuJoCo Warp allocates its buffers once: ``nconmax`` contacts per world (one pool of
``nconmax * num_envs`` shared by all worlds) and ``njmax`` constraint rows per world. A task must
reserve what its worst physics step needs; anything beyond is dropped (``CudaBackend`` raises).
:class:`BufferPeaks` records, after every physics step, the most contacts and rows any world had,
and :func:`measure_task_buffers` measures a task's need over a random-action rollout with buffers
far larger than its config's, so that nothing overflows while measuring.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import torch

__all__ = ["BufferPeaks", "measure_task_buffers"]


@dataclass
class BufferPeaks:
    """The peaks seen so far over the physics steps of one :class:`CudaBackend` (see ``watch``)."""

    contacts_per_world: int = 0
    """Most contacts in one world after a physics step."""
    contacts_pooled: int = 0
    """Most contacts of all worlds together, divided by the number of worlds (rounded up): what
    ``nconmax`` must cover, since the worlds share one pool."""
    constraint_rows: int = 0
    """Most constraint rows (``nefc``) in one world: what ``njmax`` must cover."""
    solver_iterations: int = 0
    """Most iterations the constraint solver took in one world and physics step (``solver_niter``):
    what ``sim.mujoco.iterations`` caps, and what a step waits for (the slowest world)."""
    samples: int = 0
    """Backend step calls sampled (one per physics step when an env steps)."""
    _backend: Any = field(default=None, repr=False)
    _wrapped_step: Any = field(default=None, repr=False)

    def watch(self, backend: Any) -> BufferPeaks:
        """Sample ``backend``'s counts after each of its physics steps until ``unwatch``.

        Each sample reads the counts back to the host (a sync), so this is for measuring runs only;
        steps replayed from a captured CUDA graph are not seen (measure with ``use_cuda_graph=False``).
        """
        if not hasattr(backend, "wp_data"):
            raise TypeError(
                f"BufferPeaks measures MuJoCo Warp's buffers; {type(backend).__name__} has none (MuJoCo C grows"
                " its own). Run the task with SimulationCfg.engine='mujoco_warp' (device 'cpu' works)."
            )
        self._backend, self._wrapped_step = backend, backend._step

        def step_and_sample(nstep: int, forward: bool) -> None:
            self._wrapped_step(nstep, forward)
            self.sample()

        backend._step = step_and_sample
        return self

    def unwatch(self) -> None:
        if self._backend is not None:
            del self._backend._step  # the class's method again
            self._backend = self._wrapped_step = None

    def sample(self) -> None:
        """Take the current counts of the watched backend into the peaks."""
        backend = self._backend
        wp, data = backend._wp, backend.wp_data
        num_contacts = int(data.nacon.numpy()[0])
        if num_contacts:
            world_of_contact = wp.to_torch(data.contact.worldid)[:num_contacts].long()
            per_world = int(torch.bincount(world_of_contact, minlength=backend.num_envs).max())
            self.contacts_per_world = max(self.contacts_per_world, per_world)
            pooled = -(-num_contacts // backend.num_envs)
            self.contacts_pooled = max(self.contacts_pooled, pooled)
        self.constraint_rows = max(self.constraint_rows, int(wp.to_torch(data.nefc).max()))
        self.solver_iterations = max(self.solver_iterations, int(wp.to_torch(data.solver_niter).max()))
        self.samples += 1


def measure_task_buffers(
    task: str,
    num_envs: int = 16,
    env_steps: int = 200,
    device: str = "cpu",
    seed: int = 0,
    headroom: int = 4,
    episode_length_s: float | None = None,
    configure: Callable[[Any], None] | None = None,
) -> tuple[BufferPeaks, int, dict[str, int]]:
    """Peak contacts and constraint rows of ``task`` over ``env_steps`` steps of uniform random
    actions in [-1, 1], on MuJoCo Warp (``device`` "cpu" runs its kernels on Warp's CPU device).

    The run reserves ``headroom`` times the task's configured buffers (or MuJoCo Warp's estimate
    where the task sets none), so that the measurement itself does not overflow.
    ``episode_length_s`` shortens the episodes so that the rollout crosses resets; ``configure``
    may change the env config further before the env is made.

    Returns the peaks, the number of worlds that diverged (their counts are not meaningful) and
    the sizes a run of the task reserves per world, ``{"nconmax": ..., "njmax": ...}`` (its config's,
    or the backend's estimate where it sets none), with its solver's ``"iterations"`` cap.
    """
    import gymnasium as gym

    from simlab.tasks.utils import parse_env_cfg

    from .cuda import CudaBackend

    cfg = parse_env_cfg(task, device=device, num_envs=num_envs)
    cfg.sim.engine = "mujoco_warp"
    cfg.sim.use_cuda_graph = False  # every physics step is sampled
    cfg.seed = seed
    if episode_length_s is not None:
        cfg.episode_length_s = episode_length_s
    if configure is not None:
        configure(cfg)
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        if not isinstance(env.sim.physics, CudaBackend):
            raise TypeError(f"{task} did not run on MuJoCo Warp ({type(env.sim.physics).__name__})")
        # what a run of the task reserves: its config's sizes, or the backend's estimate
        configured = {"nconmax": env.sim.physics.nconmax, "njmax": env.sim.physics.njmax}
        iterations = cfg.sim.mujoco.iterations
        if headroom != 1:  # measure in a simulation with larger buffers
            env.close()
            cfg.sim.mujoco.nconmax = headroom * max(configured["nconmax"], 1)
            cfg.sim.mujoco.njmax = headroom * max(configured["njmax"], 1)
            env = gym.make(task, cfg=cfg).unwrapped
        backend = env.sim.physics
        env.reset(seed=seed)
        peaks = BufferPeaks().watch(backend)
        actions = torch.Generator(device=env.device).manual_seed(seed)
        shape = (num_envs, env.single_action_space.shape[-1])
        for _ in range(env_steps):
            env.step(torch.rand(shape, generator=actions, device=env.device) * 2 - 1)
        backend.check_overflow()
        peaks.unwatch()
        return peaks, int(backend.diverged_count), {**configured, "iterations": iterations}
    finally:
        env.close()
