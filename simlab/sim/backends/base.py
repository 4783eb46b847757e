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
* ``reset(env_ids)`` restores the initial state (``initial_qpos``, zero velocities, zero
  controls and applied forces) in the selected worlds, then runs forward there. ``initial_qpos``
  is the model's ``qpos0`` unless ``set_initial_qpos`` gave another (the assets' default joint
  positions): ``qpos0`` itself stays the configuration the model's geometry is written in,
  because MuJoCo turns a hinge by ``qpos - qpos0``.
* ``forward(env_ids)`` recomputes derived quantities from ``qpos``/``qvel`` after a state write.
* ``mark_reset(env_ids)`` follows an env reset's writes: each selected world then starts from exactly
  the state its tensors show (solver warm start cleared, no float64 digits beyond the float32
  tensors on the CPU), so an episode follows from its recorded initial state alone.

Derived quantities are computed when first read, as Isaac Lab's lazy data buffers are. A step
without its final forward, or a state write announced with ``mark_stale(env_ids)``, leaves the
worlds *stale*; ``ensure_forward()`` forwards the stale worlds, if any, and is called by every
reader of derived quantities (sensors). Readers of body poses and velocities only (asset data) call
``ensure_kinematics()``, which runs just the kinematics, centre-of-mass and velocity passes on a
backend that has them (MuJoCo Warp: no collision, constraints or accelerations) and leaves the rest
stale. A step whose observations and rewards read only joint states therefore runs no forward at
all: the physics work equals ``mj_step``'s.
Forward is a pure function of the state, so when it runs changes no value and no trajectory.
What the last physics step applied (``qacc``, ``actuator_force``, the contact forces in
``cfrc_ext``) is read as that step left it, without a forward: a forward would recompute it at the
new state, which is not what was applied.

Nothing above the backend knows which backend runs.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence

import mujoco
import torch

from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.versions import warn_once

EnvIds = Sequence[int] | torch.Tensor | None

MAX_STATE_VALUE = 1e10
"""MuJoCo's ``mjMAXVAL``: a world whose position or velocity entry exceeds it has blown up (MuJoCo C
restarts such a world; ``take_diverged`` applies the same bound on every backend)."""

LAST_STEP_FIELDS = ("qacc", "actuator_force", "qfrc_actuator")
"""MjData fields of what the last physics step applied, read as it left them (no forward: see above);
``restart`` zeroes them in the worlds it restarts."""

# The MjData fields of MuJoCo's post-constraint pass (mj_rnePostConstraint): body accelerations and
# the forces on each body from outside its tree and from its parent (PhysX's incoming joint forces).
POST_CONSTRAINT_FIELDS = ("cacc", "cfrc_int", "cfrc_ext")

# The sensor types whose evaluation makes MuJoCo's forward pass run the post-constraint pass.
_POST_CONSTRAINT_SENSORS = frozenset(
    int(t)
    for t in (
        mujoco.mjtSensor.mjSENS_ACCELEROMETER,
        mujoco.mjtSensor.mjSENS_FORCE,
        mujoco.mjtSensor.mjSENS_TORQUE,
        mujoco.mjtSensor.mjSENS_FRAMELINACC,
        mujoco.mjtSensor.mjSENS_FRAMEANGACC,
    )
)


def _max_abs(rows: torch.Tensor) -> torch.Tensor:
    """(num_worlds,) the largest |entry| of each row (one kernel; 0 for rows without entries; NaN stays NaN)."""
    if rows.shape[1] == 0:
        return torch.zeros(rows.shape[0], dtype=rows.dtype, device=rows.device)
    return torch.linalg.vector_norm(rows, float("inf"), dim=1)


def runs_post_constraint(model: mujoco.MjModel) -> bool:
    """Whether the forward pass of ``model`` runs the post-constraint pass (it has such a sensor)."""
    return any(int(t) in _POST_CONSTRAINT_SENSORS for t in model.sensor_type)


# Model constants that MuJoCo's set_const writes; a backend makes them per world (in its own dtype)
# before the first set_const, so they read as model fields afterwards.
SET_CONST_OUTPUTS = (
    "body_subtreemass",
    "dof_invweight0",
    "body_invweight0",
    "tendon_length0",
    "tendon_invweight0",
    "actuator_acc0",
    "stat.meaninertia",
)


class PhysicsBackend(ABC):
    """``num_envs`` worlds of one MuJoCo model, with MjData fields as live torch tensors."""

    name: str = "base"

    # A forward over all worlds may cost the same as one over a few (one GPU launch): such a
    # backend tracks staleness with one flag and forwards every world.
    forwards_all_worlds: bool = False

    # Whether a whole env step (torch work and physics calls) may be recorded as one CUDA graph and
    # replayed (simlab.envs.utils.cuda_graph); the backend's kernels then join that capture.
    can_capture_steps: bool = False

    def __init__(self, model: mujoco.MjModel, num_envs: int, device: str):
        self.model = model
        self.num_envs = num_envs
        self.device = torch.device(device)
        self._stale_all = False
        self._stale = torch.zeros(num_envs, dtype=torch.bool)  # per world, when not forwards_all_worlds
        self._any_stale = False
        self.diverged_count = torch.zeros((), dtype=torch.long, device=self.device)
        """Worlds found blown up so far (``take_diverged``), on the device."""
        self._qpos0 = torch.as_tensor(model.qpos0, dtype=torch.float32, device=self.device)
        self._moves_from_qpos0 = False  # set_initial_qpos gave a start other than qpos0
        self._compiled_post_constraint = runs_post_constraint(model)  # else post_constraint runs it when read
        self._post_constraint_version: int | None = None  # the state_version the pass was last run at
        self.state_version = 0
        """Counts the changes of state (steps, resets, writes announced with ``mark_stale`` or followed
        by a forward, and each capture or replay of a graphed env step): values computed from the
        state at one version may be reused until it changes (``RootedAssetData``'s per-state
        quantities)."""

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

    def per_world_model_field(self, name: str) -> torch.Tensor | None:
        """The per-world tensor of model field ``name`` if something made it per-world
        (``model_field``), else None: the compiled model's value then holds in every world."""
        return getattr(self, "_model", {}).get(name)

    def step(self, nstep: int = 1, forward: bool = True) -> None:
        """Advance every world by ``nstep`` physics steps, then forward (see module docstring).

        ``forward=False`` skips the final forward and marks every world stale: derived quantities
        then stay one substep behind until ``ensure_forward``, as after a plain ``mj_step``.
        """
        self._step(nstep, forward)
        self.state_version += 1
        if forward:
            self._clear_stale()
        else:
            self.mark_stale()

    def forward(self, env_ids: EnvIds = None) -> None:
        """Recompute derived quantities of the selected worlds (all when ``None``)."""
        self._forward(env_ids)
        self.state_version += 1  # also covers state writes announced by a forward instead of mark_stale
        if env_ids is None or self.forwards_all_worlds:
            self._clear_stale()

    def post_constraint(self, name: str) -> torch.Tensor:
        """``cacc``, ``cfrc_int`` or ``cfrc_ext`` (``POST_CONSTRAINT_FIELDS``) at the current state.

        MuJoCo computes them in its post-constraint pass, which the forward pass runs only for a model
        with an acceleration-stage sensor (``sim_utils.compute_body_interaction_forces`` adds one
        before the model compiles). For another model the backend runs the pass itself when these are
        read, once per state, with the values the compiled-in pass gives (``_post_constraint``).
        """
        if name not in POST_CONSTRAINT_FIELDS:
            raise ValueError(f"the post-constraint pass computes {', '.join(POST_CONSTRAINT_FIELDS)}, not '{name}'")
        self.ensure_forward()
        if self._compiled_post_constraint:
            return self.data(name)
        if self._post_constraint_version != self.state_version:
            warn_once(
                "This model's forward pass does not run MuJoCo's post-constraint pass (cacc, cfrc_int, cfrc_ext:"
                " incoming joint forces); simlab runs it when they are read"
                f" ({self._post_constraint_cost}). sim_utils.compute_body_interaction_forces(sim.spec) before"
                " sim.reset() compiles it into every forward pass instead."
            )
            self._post_constraint()
            self._post_constraint_version = self.state_version
        return self._post_constraint_data(name)

    _post_constraint_cost = "one pass per read"
    """What running the pass on demand costs on this backend (for the one-time note)."""

    def _post_constraint(self) -> None:
        """Run the post-constraint pass at the current state of every world (forwarded: see
        ``post_constraint``), giving what a model compiled with the pass has after its forward."""
        raise NotImplementedError(f"the {self.name} backend cannot run MuJoCo's post-constraint pass on demand")

    def _post_constraint_data(self, name: str) -> torch.Tensor:
        """Where ``_post_constraint`` left field ``name``: (num_envs, nbody, 6)."""
        return self.data(name)

    def set_initial_qpos(self, qpos) -> None:
        """The joint positions ``reset`` and ``restart`` put the worlds in (``nq`` values)."""
        self._qpos0 = torch.as_tensor(qpos, dtype=torch.float32, device=self.device).clone()
        self._moves_from_qpos0 = bool((self._qpos0.cpu() != torch.as_tensor(self.model.qpos0).float()).any())

    @property
    def initial_qpos(self) -> torch.Tensor:
        """The joint positions ``reset`` puts the worlds in (``nq`` values; read, do not write)."""
        return self._qpos0

    def reset(self, env_ids: EnvIds = None) -> None:
        """Restore the initial state of the selected worlds (all when ``None``), then forward."""
        self._reset(env_ids)
        self.state_version += 1
        if env_ids is None or self.forwards_all_worlds:
            self._clear_stale()
        if self._moves_from_qpos0:
            qpos = self.data("qpos")
            if env_ids is None:
                qpos.copy_(self._qpos0.expand(self.num_envs, -1))
            elif isinstance(env_ids, torch.Tensor) and env_ids.dtype == torch.bool:
                masked_copy_(qpos, env_ids.to(self.device), self._qpos0.expand(self.num_envs, -1))
            else:
                qpos[torch.as_tensor(env_ids, dtype=torch.long, device=self.device)] = self._qpos0
            self.mark_stale(env_ids)

    # -- lazy derived quantities -----------------------------------------------------------------

    def mark_stale(self, env_ids: EnvIds = None) -> None:
        """Note that the state of these worlds (all when ``None``) changed since their last forward."""
        self.state_version += 1
        if env_ids is None or self.forwards_all_worlds:
            self._stale_all = True
        elif isinstance(env_ids, torch.Tensor) and env_ids.dtype == torch.bool:
            mask = env_ids.cpu()  # a host backend: no device sync
            self._stale |= mask
            self._any_stale = self._any_stale or bool(mask.any())
        else:
            self._stale[self._ids_cpu(env_ids)] = True
            self._any_stale = True

    def mark_reset(self, env_ids: EnvIds = None) -> None:
        """Note that these worlds (all when ``None``) were reset and their new state written: an
        episode starts there from exactly the state the tensors show, with nothing of the worlds'
        past carried over, so that it follows from its recorded initial state alone. Clears the
        solver's warm start (as ``mj_resetData`` does); a backend that simulates in more precision
        than the tensors drops the digits beyond them (``_forget_past``). Marks the worlds stale."""
        mask = env_mask(env_ids, self.num_envs, self.device)
        masked_copy_(self.data("qacc_warmstart"), mask, 0.0)
        self._forget_past(mask)
        self.mark_stale(env_ids)

    def _forget_past(self, mask: torch.Tensor) -> None:  # noqa: B027 - optional hook
        """Make the masked worlds' simulation state exactly the tensors' values (a backend whose
        tensors are the state itself has nothing to do)."""

    @property
    def is_stale(self) -> bool:
        """Whether some world's derived quantities lag its state."""
        return self._stale_all or self._any_stale

    def ensure_forward(self) -> None:
        """Forward the stale worlds, if any, so that derived quantities match the state. The state
        itself does not change (marking the worlds stale counted that): what was computed from it at
        this ``state_version`` stays valid (a base-frame velocity read before and after a body pose)."""
        version = self.state_version
        if self._stale_all:
            self.forward()
        elif self._any_stale:
            self.forward(self._stale.nonzero().flatten())
            self._clear_stale()
        self.state_version = version

    @property
    def kinematics_stale(self) -> bool:
        """Whether some world's body poses and velocities lag its state (``ensure_kinematics``)."""
        return self.is_stale and getattr(self, "_kinematics_version", None) != self.state_version

    def ensure_kinematics(self) -> None:
        """Bring the bodies' poses and velocities (``xpos``, ``xquat``, ``xmat``, ``xipos``,
        ``subtree_com``, ``cvel``, site and geom poses) up to the state, if some world lags it: what
        reading body poses needs. A backend with a kinematics pass (``_kinematics``) runs only that,
        not collision, constraints and accelerations; the worlds stay stale for the rest, which
        ``ensure_forward`` computes when something reads it. Others run the forward pass."""
        if not self.kinematics_stale:
            return
        if type(self)._kinematics is PhysicsBackend._kinematics:
            self.ensure_forward()
        else:
            self._kinematics()
            self._kinematics_version = self.state_version  # until the state changes again

    def _kinematics(self) -> None:
        """Recompute the fields ``ensure_kinematics`` names in every world (optional: a backend
        without it forwards)."""
        raise NotImplementedError

    def _clear_stale(self) -> None:
        self._stale_all = False
        if self._any_stale:
            self._stale.zero_()
            self._any_stale = False

    # -- what each backend implements ------------------------------------------------------------

    @abstractmethod
    def _step(self, nstep: int, forward: bool) -> None:
        """``nstep`` physics steps of every world, then a forward of all when ``forward``."""

    @abstractmethod
    def _forward(self, env_ids: EnvIds) -> None:
        """Recompute derived quantities of the selected worlds."""

    @abstractmethod
    def _reset(self, env_ids: EnvIds) -> None:
        """Restore the initial state of the selected worlds, then forward them."""

    # -- captured env steps ---------------------------------------------------------------------

    def before_capture(self) -> None:
        """Called before an env step is captured: what the replays may take as current.

        The capture records a forward at the start of the step only where one was due then.
        """
        self._stale_at_capture = self.is_stale
        self.state_version += 1  # nothing computed before the capture is reused inside it

    def before_replay(self) -> None:
        """Called before each replay: forward now if state was written since the last step and
        the captured step does not forward at its start."""
        self.state_version += 1  # the replay changes the state without running the step's Python
        if self.is_stale and not getattr(self, "_stale_at_capture", True):
            self.ensure_forward()

    def check_overflow(self) -> None:  # noqa: B027 - optional hook
        """Raise if a buffer sized at construction overflowed (backends with fixed buffers)."""

    # -- divergence ----------------------------------------------------------------------------

    def take_diverged(self) -> torch.Tensor:
        """(num_envs,) bool: the worlds whose state blew up since the last call; also counted in
        ``diverged_count``. Fixed shape, no host read: an env step calls it after its physics.

        A blown-up world has a ``qpos`` or ``qvel`` entry that is non-finite or above ``MAX_STATE_VALUE``
        (what MuJoCo Warp leaves), or was restarted by the simulator itself (``_restarted_by_simulator``:
        MuJoCo C resets a world whose state or acceleration is non-finite or huge, with only a console
        warning). Huge but finite counts too: a cube 1e20 m away is finite, but its squared distance in
        a reward term overflows float32 to inf.
        """
        qpos, qvel = self.data("qpos"), self.data("qvel")
        # each world's largest |entry| (NaN propagates through the max-norm and compares False, so a
        # non-finite row is not sane either)
        largest = torch.maximum(_max_abs(qpos), _max_abs(qvel))
        diverged = torch.le(largest, MAX_STATE_VALUE).logical_not_()
        restarted = self._restarted_by_simulator()
        if restarted is not None:
            diverged |= restarted
        self.diverged_count += diverged.sum()
        return diverged

    def restart(self, mask: torch.Tensor) -> None:
        """Put the masked worlds back to the model's initial state (``qpos0``, at rest), by mask (no
        host read), so that no non-finite value survives in them; marks them stale.

        What the last step applied there (``LAST_STEP_FIELDS``: read as the step left it, without a
        forward) is zeroed, as MuJoCo's own restart (``mj_resetData``) leaves it: a restarted world
        has had no acceleration and no actuator force. Other derived fields follow at the next read
        (the worlds are stale)."""
        masked_copy_(self.data("qpos"), mask, self._qpos0.expand(self.num_envs, -1))
        for name in ("qvel", "act", "qacc_warmstart", "ctrl", "qfrc_applied", "xfrc_applied"):
            tensor = self.data(name)
            if tensor.numel():
                masked_copy_(tensor, mask, 0.0)
        bound = self.bound_data()
        for name in LAST_STEP_FIELDS:  # only those something reads (bound): no kernel for the others
            tensor = bound.get(name)
            if tensor is not None and tensor.numel():
                masked_copy_(tensor, mask, 0.0)
        self.mark_stale(mask)

    def _restarted_by_simulator(self) -> torch.Tensor | None:
        """(num_envs,) bool: worlds the simulator restarted itself since the last call; None for a
        simulator that never does (MuJoCo Warp leaves the non-finite state in place)."""
        return None

    def bound_data(self) -> dict[str, torch.Tensor]:
        """The MjData fields handed out so far by ``data``, by name."""
        return self._data

    def set_const(self, env_ids: EnvIds = None) -> None:
        """Recompute derived model constants (body inertias, ...) after editing model fields."""
        raise NotImplementedError(f"the {self.name} backend does not support set_const")

    def device_memory_bytes(self) -> int:
        """Bytes of device memory the physics holds (model and data of all worlds); 0 on the host."""
        return 0

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release backend resources."""

    # -- helpers shared by the backends -------------------------------------------------------

    @staticmethod
    def _ids_cpu(env_ids) -> slice | torch.Tensor:
        """``env_ids`` (a slice, an index or bool tensor on any device, a list) as a CPU index."""
        if isinstance(env_ids, slice):
            return env_ids
        if isinstance(env_ids, torch.Tensor):
            return env_ids.detach().cpu()
        return torch.as_tensor(list(env_ids), dtype=torch.long)

    def _ids_numpy(self, env_ids: EnvIds):
        import numpy as np

        if env_ids is None:
            return None
        if isinstance(env_ids, torch.Tensor):
            if env_ids.dtype == torch.bool:
                env_ids = env_ids.nonzero().flatten()
            return np.ascontiguousarray(env_ids.detach().cpu().numpy().astype(np.int64))
        return np.ascontiguousarray(np.asarray(env_ids, dtype=np.int64))
