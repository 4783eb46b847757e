"""The ``cpu`` backend: MuJoCo C on a thread pool, through ``mjbatch.Batch``.

mjbatch keeps each world's integration state and steps the worlds on a C++ thread pool with the
GIL released. ``Batch.bind(field, float32)`` returns a float32 array that mjbatch synchronises
with the float64 simulation both ways around every call, so ``torch.from_numpy`` on it is a live,
zero-copy tensor: nothing is copied per step on the Python side.

mjbatch copies a float32 binding into the simulation only where its value changed since the last
call, so a write of the value a tensor already shows leaves the float64 state as it was, with its
digits beyond float32. After an env reset (``mark_reset``) this backend therefore copies the
tensors' values into the worlds' float64 state at their next call: else an episode would start from
a state that depends on the world's past (the float64 digits of a cube that rests where it rested
before) and could not be replayed from its recorded initial state.
"""

from __future__ import annotations

import os
from collections.abc import Callable

import mjbatch
import mujoco
import numpy as np
import torch

from simlab.utils.memory import available_memory, check_env_memory

from .base import MAX_STATE_VALUE, POST_CONSTRAINT_FIELDS, SET_CONST_OUTPUTS, EnvIds, PhysicsBackend


def check_host_memory(model: mujoco.MjModel, data: mujoco.MjData, num_envs: int, num_threads: int) -> None:
    """Refuse ``num_envs`` worlds that cannot fit in the free host memory, before allocating them.

    A world is counted as one MjData's arrays (``data.nbuffer``). What an env of the CPU backend
    holds per world (mjbatch's state and bound fields, the managers' tensors) measured 0.36 to 0.55
    of that (cartpole, humanoid, ANYmal-C, 256 vs 2304 envs), so the estimate leaves room for the
    learner's rollout storage. Each worker thread holds a model copy and an MjData with its arena.
    """
    fixed = num_threads * (model.nbuffer + data.nbuffer + model.narena)
    check_env_memory(num_envs, data.nbuffer, fixed, available_memory())


class CpuBackend(PhysicsBackend):
    name = "cpu"

    def __init__(
        self,
        model: mujoco.MjModel,
        num_envs: int,
        device: str = "cpu",
        num_threads: int = 0,
        nconmax: int | None = None,
        njmax: int | None = None,
        post_constraint_model: Callable[[], mujoco.MjModel] | None = None,
    ):
        """``post_constraint_model`` compiles ``model`` with one more sensor, which makes its forward
        pass run the post-constraint pass: how this backend runs that pass on demand (``post_constraint``)."""
        # nconmax / njmax size the GPU's fixed buffers; MuJoCo C grows its arena as needed.
        self._probe = mujoco.MjData(model)  # for field dtypes: a binding's dtype is fixed at first bind
        # first: nothing of size num_envs before the check (the base class's buffers included)
        check_host_memory(model, self._probe, num_envs, min(num_threads or os.cpu_count() or 1, num_envs))
        super().__init__(model, num_envs, device)
        # Two views of the same worlds would not share state, so one batch without the built-in
        # forward; step() asks for the forward explicitly (one more pool dispatch, same work).
        self.batch = mjbatch.Batch(model, num_envs, num_threads=num_threads, forward=False)
        # torch's own worker threads spin after each op and take the cores from mjbatch's pool:
        # measured on 2 cores, a 4096-env cartpole step took 27.7 ms with 2 torch threads and 17.7 ms
        # with 1. The per-env tensor math is small next to the physics, so torch gets one thread.
        if self.batch.num_threads > 1:
            torch.set_num_threads(1)
        self._data: dict[str, torch.Tensor] = {}
        self._model: dict[str, torch.Tensor] = {}
        # Each world's time, to see MuJoCo restart a world (see _step), and the worlds it restarted.
        self._time_view = torch.from_numpy(self.batch.bind("time", np.float64))
        self._restarted = torch.zeros(num_envs, dtype=torch.bool)
        # The post-constraint pass on demand: a second batch, made at the first read (_post_constraint).
        self._post_constraint_model = post_constraint_model
        self._post: mjbatch.Batch | None = None
        self._constants_set = np.zeros(num_envs, dtype=bool)  # worlds set_const ran in, for the second batch
        # The worlds' float64 integration states, and where each state field lies in a row.
        self._state = self.batch.bind("state")
        self._state_columns = _state_columns(model)
        if max(c.stop for c in self._state_columns.values()) != self.batch.nstate:
            raise RuntimeError("mjbatch's state rows are not laid out as mj_getState's integration state")
        self._forget = np.zeros(num_envs, dtype=bool)  # worlds whose state becomes the tensors' at the next call

    @property
    def num_threads(self) -> int:
        return self.batch.num_threads

    def data(self, name: str) -> torch.Tensor:
        if name not in self._data:
            native = getattr(self._probe, name, None)
            if not isinstance(native, np.ndarray):
                raise ValueError(f"MjData has no array field '{name}'")
            dtype = np.float32 if native.dtype == np.float64 else None
            self._data[name] = torch.from_numpy(self.batch.bind(name, dtype))
            # mjbatch fills a new binding at its next call; make it current now (forward is pure).
            self.batch.forward()
        return self._data[name]

    def model_field(self, name: str) -> torch.Tensor:
        key = name.removeprefix("opt.")
        if key not in self._model:
            source = self.model.opt if name.startswith("opt.") else self.model
            native = getattr(source, key, None)
            if native is None:
                raise ValueError(f"MjModel has no field '{name}'")
            is_real = np.asarray(native).dtype == np.float64
            try:
                expanded = self.batch.expand(key, np.float32 if is_real else None)
            except ValueError as err:
                raise ValueError(f"MjModel field '{name}' cannot be made per-world: {err}") from err
            self._model[key] = torch.from_numpy(expanded)
        return self._model[key]

    def _step(self, nstep: int, forward: bool) -> None:
        # MuJoCo restarts a world whose state blew up (mj_resetData, then goes on): its time then
        # falls back instead of advancing by nstep * dt. Noted here, reported by take_diverged.
        # MuJoCo's own tests on what a step starts from (mj_checkPos / mj_checkVel restart the world,
        # a control above 1e10 is zeroed; both with a console warning only) catch what time cannot
        # show (a world at time 0).
        self._commit_reset_worlds()
        time = self._time_view
        before = time.clone()
        self._restarted |= _blown_up(self.data("qpos")) | _blown_up(self.data("qvel")) | _blown_up(self.data("ctrl"))
        self.batch.step(nstep=nstep)
        self._restarted |= time < before + 0.5 * nstep * self.model.opt.timestep
        if forward:
            self.batch.forward()

    def _restarted_by_simulator(self) -> torch.Tensor:
        restarted = self._restarted.clone()
        self._restarted.zero_()
        return restarted

    def _forward(self, env_ids: EnvIds) -> None:
        self._commit_reset_worlds()
        self.batch.forward(self._ids_numpy(env_ids))

    def _reset(self, env_ids: EnvIds) -> None:
        self._commit_reset_worlds()
        self.batch.reset(self._ids_numpy(env_ids))

    def _forget_past(self, mask: torch.Tensor) -> None:
        # at the next call, not now: a later write of the value the simulation held before would go unseen
        self._forget |= mask.cpu().numpy()

    def _commit_reset_worlds(self) -> None:
        """The float32 tensors' values into the float64 state of the worlds ``mark_reset`` named (those
        of the state fields bound so far: the others were not written)."""
        if not self._forget.any():
            return
        rows = np.flatnonzero(self._forget)
        for name, tensor in self._data.items():
            columns = self._state_columns.get(name)
            if columns is not None and tensor.dtype == torch.float32:
                self._state[rows, columns] = tensor.numpy()[rows].reshape(len(rows), -1)
        self._forget[:] = False

    def set_const(self, env_ids: EnvIds = None) -> None:
        # mjbatch makes each constant it changes per world in float64 unless it is already: bind them
        # in float32 first, as model_field does, or reading one afterwards fails on the dtype
        for name in SET_CONST_OUTPUTS:
            try:
                self.model_field(name)
            except ValueError:
                continue  # not a model array (stat.meaninertia is a scalar of a struct)
        ids = self._ids_numpy(env_ids)
        self.batch.set_const(ids)
        self._constants_set[slice(None) if ids is None else ids] = True

    # -- the post-constraint pass on demand ------------------------------------------------------

    _post_constraint_cost = "one more forward pass per read, in a second batch of the worlds"

    def _post_constraint(self) -> None:
        """mjbatch runs MuJoCo's pipeline, not its single passes: the worlds' forward pass is run
        again in a second batch of the model compiled with the pass on, from each world's state
        (``bind("state")``: what this batch's last forward started from) and its per-world model
        fields. The same computation as the compiled-in pass, so the same values."""
        if self._post is None:
            if self._post_constraint_model is None:
                raise NotImplementedError(
                    "this cpu backend was made without post_constraint_model, so it cannot run MuJoCo's post-constraint"
                    " pass on demand: compile it in (sim_utils.compute_body_interaction_forces before sim.reset())"
                )
            model = self._post_constraint_model()
            sizes = ("nq", "nv", "na", "nu", "nbody", "ngeom", "nsite", "neq", "nmocap", "nuserdata")
            if any(getattr(model, n) != getattr(self.model, n) for n in sizes):  # one more sensor only
                raise RuntimeError(
                    "MuJoCo's post-constraint pass runs on demand in the scene's spec compiled again, and that spec"
                    " no longer matches the simulated model (was it edited after sim.reset()?)"
                )
            self._post = mjbatch.Batch(model, self.num_envs, num_threads=self.num_threads)
            if self._post.nstate != self.batch.nstate:
                raise RuntimeError("the model with the post-constraint pass has another state size than the model")
            self._post_state = self._post.bind("state")
            self._post_fields: dict[str, np.ndarray] = {}
            self._post_out = {n: torch.from_numpy(self._post.bind(n, np.float32)) for n in POST_CONSTRAINT_FIELDS}
        self._copy_model_fields()
        if self._constants_set.any():  # derived constants from the same inputs, then the values this batch holds
            self._post.set_const(np.flatnonzero(self._constants_set))
            self._constants_set[:] = False
            self._copy_model_fields()
        np.copyto(self._post_state, self._state)
        self._post.forward()

    def _copy_model_fields(self) -> None:
        """The per-world model fields into the second batch (sensor fields: its model has one more sensor)."""
        for key, values in self._model.items():
            target = self._post_fields.get(key)
            if target is None:
                dtype = np.float32 if values.dtype == torch.float32 else None
                target = self._post_fields[key] = self._post.expand(key, dtype)
            target[tuple(slice(0, n) for n in values.shape)] = values.numpy()

    def _post_constraint_data(self, name: str) -> torch.Tensor:
        return self._post_out[name]


def _state_columns(model: mujoco.MjModel) -> dict[str, slice]:
    """Where each MjData field of MuJoCo's integration state lies in a ``bind("state")`` row (the
    components in mj_getState's order, that of their mjtState bits)."""
    fields = {
        mujoco.mjtState.mjSTATE_TIME: "time",
        mujoco.mjtState.mjSTATE_QPOS: "qpos",
        mujoco.mjtState.mjSTATE_QVEL: "qvel",
        mujoco.mjtState.mjSTATE_ACT: "act",
        mujoco.mjtState.mjSTATE_WARMSTART: "qacc_warmstart",
        mujoco.mjtState.mjSTATE_CTRL: "ctrl",
        mujoco.mjtState.mjSTATE_QFRC_APPLIED: "qfrc_applied",
        mujoco.mjtState.mjSTATE_XFRC_APPLIED: "xfrc_applied",
        mujoco.mjtState.mjSTATE_EQ_ACTIVE: "eq_active",
        mujoco.mjtState.mjSTATE_MOCAP_POS: "mocap_pos",
        mujoco.mjtState.mjSTATE_MOCAP_QUAT: "mocap_quat",
        mujoco.mjtState.mjSTATE_USERDATA: "userdata",
        mujoco.mjtState.mjSTATE_PLUGIN: "plugin_state",
    }
    columns, start = {}, 0
    for bit in sorted(fields, key=int):
        size = mujoco.mj_stateSize(model, bit)
        columns[fields[bit]] = slice(start, start + size)
        start += size
    return columns


def _blown_up(state: torch.Tensor) -> torch.Tensor:
    """(num_envs,) bool: rows MuJoCo would restart (a value non-finite or above mjMAXVAL, 1e10)."""
    return ~(state.abs() <= MAX_STATE_VALUE).all(dim=1)  # NaN compares False
