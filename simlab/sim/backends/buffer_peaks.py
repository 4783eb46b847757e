"""How many contacts and constraint rows the worlds of a MuJoCo Warp simulation really use.

MuJoCo Warp allocates its buffers once: ``nconmax`` contacts per world (one pool of
``nconmax * num_envs`` shared by all worlds) and ``njmax`` constraint rows per world. A task must
reserve what its worst physics step needs; anything beyond is dropped (``CudaBackend`` raises).
:class:`BufferPeaks` records, after every physics step, the most contacts and rows any world had,
and :func:`simlab.tasks.utils.contact_buffers.measure_task_buffers` measures a task's need with it
(a layer above: it makes the task's env).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import torch

__all__ = ["BufferPeaks"]


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
