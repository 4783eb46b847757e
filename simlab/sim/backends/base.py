"""The interface every physics backend implements.

A backend runs ``num_envs`` copies ("worlds") of one compiled ``mujoco.MjModel`` and exposes

* MjData fields as live torch tensors of shape ``(num_envs, *field_shape)``: reading one gives the
  current state, writing into one (in place) reaches the simulation at the next ``step``,
  ``forward`` or ``reset``. Floating-point fields are float32 on every backend.
* MjModel fields per world (``model_field``), so each world can carry its own masses, frictions,
  gains or gravity (``"opt.gravity"`` names an ``mjOption`` field).

Simulation semantics shared by all backends:

* ``step(nstep)`` advances every world by ``nstep`` physics steps with the controls, applied
  forces and model fields currently in the tensors, then runs ``mj_forward`` once so that
  derived quantities (``xpos``, ``xquat``, ``cvel``, ``sensordata``, ...) agree with the new
  ``qpos``/``qvel``. Without that final forward, MuJoCo leaves them one substep behind.
* ``reset(env_ids)`` restores the model's initial state (``qpos0``, zero velocities, zero
  controls and applied forces) in the selected worlds, then runs forward there.
* ``forward(env_ids)`` recomputes derived quantities from ``qpos``/``qvel`` after a state write.

Nothing above the backend knows which backend runs.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence

import mujoco
import torch

EnvIds = Sequence[int] | torch.Tensor | None


class PhysicsBackend(ABC):
    """``num_envs`` worlds of one MuJoCo model, with MjData fields as live torch tensors."""

    name: str = "base"

    def __init__(self, model: mujoco.MjModel, num_envs: int, device: str):
        self.model = model
        self.num_envs = num_envs
        self.device = torch.device(device)

    @abstractmethod
    def data(self, name: str) -> torch.Tensor:
        """A live ``(num_envs, ...)`` tensor over the MjData field ``name`` (float32 for reals)."""

    @abstractmethod
    def model_field(self, name: str) -> torch.Tensor:
        """A live per-world ``(num_envs, ...)`` tensor over the MjModel field ``name``.

        The first call makes the field per-world (seeded from the model); later writes into the
        returned tensor reach each world at its next physics call. ``"opt.<field>"`` names an
        ``mjOption`` field such as ``"opt.gravity"``.
        """

    @abstractmethod
    def step(self, nstep: int = 1, forward: bool = True) -> None:
        """Advance every world by ``nstep`` physics steps, then forward (see module docstring).

        ``forward=False`` skips the final forward: derived quantities then stay one substep
        behind, as after a plain ``mj_step``. Envs use it for all but the last of the decimated
        physics steps of an env step, when nothing reads derived quantities in between.
        """

    @abstractmethod
    def forward(self, env_ids: EnvIds = None) -> None:
        """Recompute derived quantities of the selected worlds (all when ``None``)."""

    @abstractmethod
    def reset(self, env_ids: EnvIds = None) -> None:
        """Restore the initial state of the selected worlds (all when ``None``), then forward."""

    def bound_data(self) -> dict[str, torch.Tensor]:
        """The MjData fields handed out so far by ``data``, by name."""
        return self._data

    def set_const(self, env_ids: EnvIds = None) -> None:
        """Recompute derived model constants (body inertias, ...) after editing model fields."""
        raise NotImplementedError(f"the {self.name} backend does not support set_const")

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release backend resources."""

    # -- helpers shared by the backends -------------------------------------------------------

    def _ids_numpy(self, env_ids: EnvIds):
        import numpy as np

        if env_ids is None:
            return None
        if isinstance(env_ids, torch.Tensor):
            if env_ids.dtype == torch.bool:
                env_ids = env_ids.nonzero().flatten()
            return np.ascontiguousarray(env_ids.detach().cpu().numpy().astype(np.int64))
        return np.ascontiguousarray(np.asarray(env_ids, dtype=np.int64))
