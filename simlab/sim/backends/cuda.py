"""The ``cuda`` backend: MuJoCo Warp (``mujoco_warp``) on an NVIDIA GPU.

All ``num_envs`` worlds live in one ``mujoco_warp.Data`` (``put_data(nworld=num_envs)``). MjData
fields are exposed as zero-copy torch views (``wp.to_torch``) of the warp arrays, so nothing is
copied per step; the views stay valid because the backend never replaces a Data array.

Each physics call (``step(nstep)``, ``forward``, ``reset``) is captured once as a CUDA graph and
then replayed, which removes the Python and launch overhead of the few hundred kernels in a step.
Graphs are captured on Warp's stream and *replayed on torch's current stream*, so torch writes into
``ctrl``/``qpos``/... issued before a call are ordered before the physics, and torch reads issued
after it see the result, without any extra synchronisation.

Model fields are batched by MuJoCo Warp over a leading world dimension that is 1 by default.
``model_field`` tiles a field to ``num_envs`` once (a new array), which changes the pointers baked
into the captured graphs: every expansion therefore drops the graphs, and the next call captures
them again.

Nothing here imports ``warp`` at module import time: ``require_cuda_backend`` does, lazily, so that
``import simlab`` works on machines without a GPU or without the ``gpu`` extra.
"""

from __future__ import annotations

import dataclasses
import functools
import time
from collections.abc import Callable
from typing import Any

import mujoco
import numpy as np
import torch

from simlab.utils.cuda import gc_paused, is_capturing
from simlab.utils.memory import available_memory, check_env_memory

from .base import SET_CONST_OUTPUTS, EnvIds, PhysicsBackend
from .warp_compile import Precompile, compile_ahead, compile_ahead_enabled

_INSTALL_HINT = 'the cuda backend needs an NVIDIA GPU and MuJoCo Warp: pip install "simlab[gpu]"'

# mujoco_warp.OverflowType bits that mean "a buffer sized at construction was too small", with the
# constructor argument that sizes it. The other bits (solver iteration limits, EPA horizon, ...)
# are accuracy warnings, not lost constraints, and are not raised.
_OVERFLOW_SETTINGS = {
    1 << 0: ("nefc > njmax: constraint rows were dropped", "njmax"),
    1 << 1: ("constraint Jacobian non-zeros overflowed njmax_nnz", "njmax"),
    1 << 2: ("broadphase found more candidate contacts than nconmax * num_envs", "nconmax"),
    1 << 3: ("narrowphase produced more contacts than nconmax * num_envs", "nconmax"),
    1 << 4: ("CCD produced more contacts than its buffer (sized from nconmax)", "nconmax"),
    1 << 6: ("a contact sensor matched more contacts than its slots (sized from nconmax, at most 64)", "nconmax"),
}
_MAX_CONTACT_MATCH_SLOTS = 64  # MuJoCo Warp's default contact_sensor_maxmatch


@functools.cache
def _restart_kernel(wp: Any) -> Any:
    """The Warp kernel of ``CudaBackend.restart``: one thread per world."""

    @wp.kernel(module="unique")
    def restart_worlds(
        mask: wp.array(dtype=bool),
        qpos0: wp.array(dtype=float),
        qpos: wp.array2d(dtype=float),
        qvel: wp.array2d(dtype=float),
        act: wp.array2d(dtype=float),
        qacc_warmstart: wp.array2d(dtype=float),
        ctrl: wp.array2d(dtype=float),
        qfrc_applied: wp.array2d(dtype=float),
        qacc: wp.array2d(dtype=float),
        actuator_force: wp.array2d(dtype=float),
        qfrc_actuator: wp.array2d(dtype=float),
        xfrc_applied: wp.array2d(dtype=wp.spatial_vector),
    ):
        world = wp.tid()
        if not mask[world]:
            return
        for i in range(qpos.shape[1]):
            qpos[world, i] = qpos0[i]
        for i in range(qvel.shape[1]):
            qvel[world, i] = 0.0
            qacc_warmstart[world, i] = 0.0
            qfrc_applied[world, i] = 0.0
            qacc[world, i] = 0.0
            qfrc_actuator[world, i] = 0.0
        for i in range(act.shape[1]):
            act[world, i] = 0.0
        for i in range(ctrl.shape[1]):
            ctrl[world, i] = 0.0
        for i in range(actuator_force.shape[1]):
            actuator_force[world, i] = 0.0
        for i in range(xfrc_applied.shape[1]):
            xfrc_applied[world, i] = wp.spatial_vector()

    return restart_worlds


def contact_match_slots(nconmax: int) -> int:
    """Contacts each MuJoCo contact sensor keeps per world: ``nconmax`` (the contacts a world reserves on
    average in the shared pool; one world may use more, and a sensor matching more than its slots
    raises, naming nconmax) rounded up to a power of two, at most MuJoCo Warp's 64. Every physics step fills
    (worlds, sensors, slots) buffers, so fewer slots are less memory to write."""
    return min(_MAX_CONTACT_MATCH_SLOTS, 1 << max(0, nconmax - 1).bit_length())


def require_cuda_backend(device: str = "cuda") -> tuple[Any, Any]:
    """Import ``warp`` and ``mujoco_warp`` and check that ``device`` is usable.

    Returns the two modules. Raises ``RuntimeError`` (with the install hint) when either package
    is missing, or when no CUDA device is visible to Warp or to PyTorch.
    """
    try:
        import warp as wp
    except ImportError as err:
        raise RuntimeError(f"{_INSTALL_HINT} (warp is not installed: {err})") from err
    wp.config.quiet = True  # no start-up banner or kernel-load lines (before mujoco_warp inits warp)
    try:
        import mujoco_warp as mjw
    except ImportError as err:
        raise RuntimeError(f"{_INSTALL_HINT} (mujoco_warp is not installed: {err})") from err

    if device == "cpu":  # MuJoCo Warp's CPU device: slow, for debugging without a GPU
        return wp, mjw
    wp.init()
    if not wp.is_cuda_available():
        raise RuntimeError(f"{_INSTALL_HINT} (Warp finds no CUDA device; asked for '{device}')")
    if not torch.cuda.is_available():
        raise RuntimeError(
            f"{_INSTALL_HINT} (this PyTorch build has no CUDA support, so GPU tensors cannot be "
            f"shared with Warp; install a CUDA build of torch)"
        )
    index = torch.device(device).index or 0
    count = wp.get_cuda_device_count()
    if index >= count:
        raise RuntimeError(f"cuda device '{device}' does not exist: {count} CUDA device(s) visible")
    return wp, mjw


def contacts_possible(model: mujoco.MjModel) -> bool:
    """Whether any two geoms of ``model`` can ever collide (MuJoCo's contype/affinity filtering)."""
    if model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT:
        return False
    if model.npair > 0 or model.nflex > 0:
        return True
    g1, g2 = np.triu_indices(model.ngeom, k=1)
    b1, b2 = model.geom_bodyid[g1], model.geom_bodyid[g2]
    w1, w2 = model.body_weldid[b1], model.body_weldid[b2]
    affinity = (model.geom_contype[g1] & model.geom_conaffinity[g2]) | (
        model.geom_contype[g2] & model.geom_conaffinity[g1]
    )
    candidate = (affinity != 0) & (w1 != w2)  # bodies welded together never collide
    if not model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_FILTERPARENT:
        p1, p2 = model.body_weldid[model.body_parentid[w1]], model.body_weldid[model.body_parentid[w2]]
        candidate &= ~((w1 != 0) & (w2 != 0) & ((w1 == p2) | (w2 == p1)))
    if model.nexclude:
        excluded = set(model.exclude_signature.tolist())
        sig = (b1.astype(np.int64) << 16) + b2
        candidate &= ~np.isin(sig, list(excluded))
    return bool(candidate.any())


def static_constraint_rows(model: mujoco.MjModel) -> int:
    """An upper bound on the constraint rows a world can have without contacts."""
    eq_rows = {
        mujoco.mjtEq.mjEQ_CONNECT: 3,
        mujoco.mjtEq.mjEQ_WELD: 6,
        mujoco.mjtEq.mjEQ_JOINT: 1,
        mujoco.mjtEq.mjEQ_TENDON: 1,
    }
    rows = sum(eq_rows.get(int(t), 0) for t in model.eq_type)
    rows += int(np.count_nonzero(model.dof_frictionloss > 0))
    rows += int(np.count_nonzero(model.tendon_frictionloss > 0))
    # a limited slide/hinge joint or tendon can touch both limits when its range is tiny
    rows += 2 * int(np.count_nonzero(model.jnt_limited)) + 2 * int(np.count_nonzero(model.tendon_limited))
    return rows


def _contact_rows_estimate(mjw: Any, model: mujoco.MjModel, mjdata: mujoco.MjData, static_rows: int) -> int | None:
    """Constraint rows per world: the static ones plus MuJoCo Warp's own estimate for contacts (a
    private helper: called only with the release it was checked with; else None, MuJoCo Warp's default)."""
    from simlab.utils.versions import release_mismatch, warn_once

    if (mismatch := release_mismatch("mujoco-warp")) is not None:
        warn_once(f"{mismatch}: njmax is left to MuJoCo Warp's default (set sim.mujoco.njmax if it overflows)")
        return None
    return static_rows + mjw._src.io._default_njmax(model, mjdata)


def warp_data_bytes(wp: Any, mjw: Any, model: mujoco.MjModel, mjdata: mujoco.MjData, nconmax, njmax) -> tuple[int, int]:
    """Bytes of MuJoCo Warp's ``Data`` for ``model``: (per world, for all worlds together).

    Measured rather than modelled, as the layout is MuJoCo Warp's own and changes between releases:
    ``put_data`` of one and of two worlds on Warp's CPU device, array by array (every array grows
    linearly with the worlds; the shapes are the same on a GPU). Takes a fraction of a second.
    """
    sizes = []
    with wp.ScopedDevice("cpu"):
        for nworld in (1, 2):
            data = mjw.put_data(model, mjdata, nworld=nworld, nconmax=nconmax, njmax=njmax)
            sizes.append(_array_bytes(data))
            del data
    per_world = sizes[1] - sizes[0]
    return per_world, sizes[0] - per_world


def _array_bytes(obj: Any) -> int:
    """The bytes held by the Warp arrays of a MuJoCo Warp dataclass (``Data``, its ``Contact`` ...)."""
    total = 0
    for field in dataclasses.fields(obj):
        value = getattr(obj, field.name)
        total += _array_bytes(value) if dataclasses.is_dataclass(value) else int(getattr(value, "capacity", 0) or 0)
    return total


def free_memory(device: str) -> int | None:
    """Free bytes where the worlds will live: the GPU's (CUDA's own count), or the host's for Warp's CPU device."""
    if device.startswith("cuda"):
        return int(torch.cuda.mem_get_info(torch.device(device))[0])
    return available_memory()


def check_warp_memory(
    wp: Any,
    mjw: Any,
    model: mujoco.MjModel,
    mjdata: mujoco.MjData,
    num_envs: int,
    nconmax: int | None,
    njmax: int | None,
    free: int | None,
    device: str,
) -> None:
    """Refuse ``num_envs`` worlds whose MuJoCo Warp data cannot fit in ``free`` bytes, before
    ``put_data`` allocates them. Only the physics is counted: the env's tensors and the learner's
    rollout storage come on top, so a count close to the limit may still run out later."""
    per_world, fixed = warp_data_bytes(wp, mjw, model, mjdata, nconmax, njmax)
    memory = "GPU memory" if device.startswith("cuda") else "memory"
    check_env_memory(num_envs, per_world, fixed, free, memory=f"{memory} for MuJoCo Warp on {device}")


class CudaBackend(PhysicsBackend):
    """``num_envs`` worlds of one model in MuJoCo Warp, stepped by replaying CUDA graphs.

    Args:
        model: the compiled MuJoCo model.
        num_envs: number of worlds.
        device: ``"cuda"`` or ``"cuda:N"`` (``"cpu"`` runs MuJoCo Warp's slow CPU device, for
            debugging without a GPU).
        nconmax: contacts allocated per world (all worlds share one pool of
            ``nconmax * num_envs``). Default: 0 when no two geoms can collide, MuJoCo Warp's
            heuristic otherwise.
        njmax: constraint rows allocated per world. Default: the rows that joint limits,
            equalities and friction loss can produce, plus MuJoCo Warp's heuristic when contacts
            are possible.
        overflow_check_interval: ``step`` calls between two ``check_overflow`` calls; 0 turns the
            periodic check off. Each check reads one flag back from the GPU, which waits for the
            queued work (a sync): checking every call would stall the CPU-GPU pipeline, checking
            rarely reports an overflow up to this many calls late (the flags are sticky, so none
            is missed, even in worlds reset in between).
    """

    name = "cuda"
    forwards_all_worlds = True  # one graph over all worlds costs what a masked one would

    def __init__(
        self,
        model: mujoco.MjModel,
        num_envs: int,
        device: str = "cuda:0",
        nconmax: int | None = None,
        njmax: int | None = None,
        overflow_check_interval: int = 100,
    ):
        wp, mjw = require_cuda_backend(device)
        if device.startswith("cuda") and torch.device(device).index is None:
            device = f"cuda:{torch.cuda.current_device()}"

        # mj_forward on the host first: put_data copies this state and checks it fits the buffers
        mjdata = mujoco.MjData(model)
        mujoco.mj_forward(model, mjdata)
        if nconmax is None:
            nconmax = None if contacts_possible(model) else 0  # None: mujoco_warp's heuristic
        if njmax is None:
            njmax = static_constraint_rows(model)
            if nconmax != 0:
                njmax = _contact_rows_estimate(mjw, model, mjdata, njmax)
        if nconmax is not None:
            nconmax = max(nconmax, mjdata.ncon)
        if njmax is not None:
            njmax = max(njmax, mjdata.nefc)
        # first: nothing of size num_envs before the check (the base class's buffers included)
        check_warp_memory(wp, mjw, model, mjdata, num_envs, nconmax, njmax, free_memory(device), device)

        super().__init__(model, num_envs, device)
        self._wp, self._mjw = wp, mjw
        self._wp_device = wp.get_device(device)
        self._is_cuda = self._wp_device.is_cuda
        self.can_capture_steps = self._is_cuda
        self.overflow_check_interval = overflow_check_interval
        self._mjdata_shapes = mjdata  # only for MjData field shapes
        with wp.ScopedDevice(self._wp_device):
            self.wp_model = mjw.put_model(model)
            # The backend raises on overflow itself (check_overflow); the kernels' own warnings
            # would print one line per world and step from inside the graph.
            self.wp_model.opt.warn_overflow = 0
            self.wp_data = mjw.put_data(model, mjdata, nworld=num_envs, nconmax=nconmax, njmax=njmax)
            self._reset_mask = wp.zeros(num_envs, dtype=bool)
        # put_* upload on Warp's stream; torch may use the arrays from another stream next
        wp.synchronize_device(self._wp_device)
        self.nconmax = self.wp_data.naconmax // num_envs
        self.njmax = self.wp_data.njmax
        # unless the model sets them (a numeric "contact_sensor_maxmatch"); matches beyond raise (check_overflow)
        if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, "contact_sensor_maxmatch") < 0:
            self.wp_model.opt.contact_sensor_maxmatch = contact_match_slots(self.nconmax)

        self._data_fields = {f.name: f for f in dataclasses.fields(type(self.wp_data))}
        self._data: dict[str, torch.Tensor] = {}
        self._model: dict[str, torch.Tensor] = {}
        self._graphs: dict[Any, Any] = {}
        self._streams: dict[int, Any] = {}
        self.capture_seconds: dict[Any, float] = {}  # wall time of each graph capture (diagnostics)

        self._mask = wp.to_torch(self._reset_mask)
        self._overflow = wp.to_torch(self.wp_data.overflow)
        self._overflow_seen = torch.zeros_like(self._overflow)  # sticky per-world overflow bits
        self._calls_since_check = 0

        # The kernels of step, forward and reset compile on a thread pool while the env and the
        # runner are built; the first capture waits for them (see warp_compile).
        self.precompile: Precompile | None = None
        if compile_ahead_enabled():
            self.precompile = compile_ahead(wp, self._wp_device, self._physics_calls())

    def _physics_calls(self) -> list[Callable[[], None]]:
        """MuJoCo Warp's calls behind step, forward and reset, for compiling their kernels ahead."""
        m, d, mjw = self.wp_model, self.wp_data, self._mjw
        return [lambda: mjw.step(m, d), lambda: mjw.forward(m, d), lambda: mjw.reset_data(m, d, reset=self._reset_mask)]

    # -- fields --------------------------------------------------------------------------------

    def data(self, name: str) -> torch.Tensor:
        if name not in self._data:
            field = self._data_fields.get(name)
            shape = getattr(getattr(field, "type", None), "shape", None)
            if not isinstance(shape, tuple) or shape[0] != "nworld":
                raise ValueError(f"MjData has no per-world field '{name}' in MuJoCo Warp")
            tensor = self._wp.to_torch(getattr(self.wp_data, name))
            self._data[name] = self._mujoco_shape(tensor, getattr(self._mjdata_shapes, name, None))
        return self._data[name]

    def model_field(self, name: str) -> torch.Tensor:
        if name not in self._model:
            owner, attr = self._model_owner(name)
            arr = getattr(owner, attr)
            if arr.shape[0] != self.num_envs:
                arr = self._tile(arr)
                setattr(owner, attr, arr)
                # the captured graphs hold the old array's address: capture again on next use
                self._graphs.clear()
            tensor = self._wp.to_torch(arr)
            self._model[name] = self._mujoco_shape(tensor, self._mujoco_model_value(name))
        return self._model[name]

    def _model_owner(self, name: str) -> tuple[Any, str]:
        """The MuJoCo Warp object holding model field ``name`` and the attribute's name."""
        *path, attr = name.split(".")
        owner = self.wp_model
        for part in path:  # "opt.gravity", "stat.meaninertia"
            owner = getattr(owner, part, None)
        fields = {f.name: f for f in dataclasses.fields(owner)} if dataclasses.is_dataclass(owner) else {}
        spec = getattr(fields.get(attr), "type", None)
        if not isinstance(getattr(spec, "shape", None), tuple) or spec.shape[0] != "*":
            raise ValueError(f"MjModel has no per-world field '{name}' in MuJoCo Warp")
        return owner, attr

    def _mujoco_model_value(self, name: str) -> Any:
        value: Any = self.model
        for part in name.split("."):
            value = getattr(value, part, None)
        return value

    def _tile(self, arr: Any) -> Any:
        """A new ``(num_envs, ...)`` warp array holding ``num_envs`` copies of world 0 of ``arr``."""
        wp = self._wp
        with self._scope():  # allocated on the stream torch then copies on
            tiled = wp.empty((self.num_envs, *arr.shape[1:]), dtype=arr.dtype, device=self._wp_device)
        src = wp.to_torch(arr)[:1]
        wp.to_torch(tiled).copy_(src.expand(self.num_envs, *src.shape[1:]))  # on torch's stream
        return tiled

    def _mujoco_shape(self, tensor: torch.Tensor, mj_value: Any) -> torch.Tensor:
        """View ``tensor`` as ``(num_envs, *mujoco_shape)`` (e.g. xmat as 9 floats, not 3x3).

        Fields whose size differs from MuJoCo's (Warp-only layouts) keep Warp's shape.
        """
        if mj_value is None:
            return tensor
        shape = (self.num_envs, *np.shape(mj_value))
        if tensor.shape != shape and tensor.numel() == int(np.prod(shape)):
            return tensor.view(shape)
        return tensor

    # -- physics -------------------------------------------------------------------------------

    def _step(self, nstep: int, forward: bool) -> None:
        m, d, mjw = self.wp_model, self.wp_data, self._mjw

        def body() -> None:
            for _ in range(nstep):
                mjw.step(m, d)
            if forward:
                mjw.forward(m, d)  # derived fields agree with the new qpos/qvel (base.py semantics)

        self._run(("step", nstep, forward), body)
        # Sticky record of overflows: reset() clears Data.overflow in the worlds it resets.
        self._overflow_seen.bitwise_or_(self._overflow)
        if is_capturing():
            return  # a captured env step checks between replays (EnvStepper.check)
        self._calls_since_check += 1
        if self.overflow_check_interval and self._calls_since_check >= self.overflow_check_interval:
            self.check_overflow()

    def _forward(self, env_ids: EnvIds) -> None:
        """Recompute derived quantities. Runs on *all* worlds whatever ``env_ids`` says.

        Forward is a pure function of the state, so in worlds whose state did not change it
        recomputes the same values; one replayed graph over all worlds is cheaper than a masked
        variant and needs no per-subset graph.
        """
        self._run("forward", lambda: self._mjw.forward(self.wp_model, self.wp_data))

    def _kinematics(self) -> None:
        """Body poses and velocities of all worlds: MuJoCo Warp's kinematics, centre-of-mass and
        velocity passes, the same kernels the forward pass starts with (about a tenth of its launches
        for a hand; no collision, constraints or solver)."""
        m, d, mjw = self.wp_model, self.wp_data, self._mjw

        def body() -> None:
            mjw.kinematics(m, d)
            mjw.com_pos(m, d)
            mjw.com_vel(m, d)

        self._run("kinematics", body)

    def _post_constraint(self) -> None:
        """MuJoCo Warp's post-constraint pass (``rne_postconstraint``) on the last forward's results: a
        graph of its own, or recorded into an env step being captured, as the other physics calls."""
        m, d, mjw = self.wp_model, self.wp_data, self._mjw
        self._run("rne_postconstraint", lambda: mjw.rne_postconstraint(m, d))

    def _reset(self, env_ids: EnvIds) -> None:
        """Reset the selected worlds (``mujoco_warp.reset_data`` with a mask), then forward all."""
        if env_ids is None:
            self._mask.fill_(True)
        elif isinstance(env_ids, torch.Tensor) and env_ids.dtype == torch.bool:
            self._mask.copy_(env_ids)  # a mask: no ids, no host read
        else:
            ids = self._ids_torch(env_ids)
            self._mask.fill_(False)
            self._mask[ids] = True
        m, d, mjw = self.wp_model, self.wp_data, self._mjw

        def body() -> None:
            mjw.reset_data(m, d, reset=self._reset_mask)
            mjw.forward(m, d)

        self._run("reset", body)

    def restart(self, mask: torch.Tensor) -> None:
        """``PhysicsBackend.restart`` in one kernel over the worlds (and the mask's copy), instead of a
        masked select per field, every step: the masked worlds get ``qpos0`` and zero velocities,
        activations, warm start, controls, applied forces and what the last step applied
        (``LAST_STEP_FIELDS``, every one, read or not)."""
        wp, d = self._wp, self.wp_data
        self._mask.copy_(mask)
        kernel = _restart_kernel(wp)
        qpos0 = wp.from_torch(self._qpos0)
        fields = [d.qpos, d.qvel, d.act, d.qacc_warmstart, d.ctrl, d.qfrc_applied, d.qacc, d.actuator_force]
        fields += [d.qfrc_actuator, d.xfrc_applied]

        def body() -> None:
            wp.launch(kernel, dim=self.num_envs, inputs=[self._reset_mask, qpos0, *fields])

        self._run(("restart", self._qpos0.data_ptr()), body)
        self.mark_stale(mask)

    def set_const(self, env_ids: EnvIds = None) -> None:
        """Recompute derived model constants in all worlds (``env_ids`` is ignored), then forward.

        The constants it writes (``body_subtreemass``, ``dof_invweight0``, ...) are made per-world
        first when any model field is, so each world gets its own. Not graph-captured: it
        allocates scratch arrays, and it is rare.
        """
        if self._model:
            for name in SET_CONST_OUTPUTS:
                try:
                    self.model_field(name)
                except ValueError:
                    continue  # a field this model or version does not batch
        with self._scope():
            self._mjw.set_const(self.wp_model, self.wp_data)
        self.forward()

    def device_memory_bytes(self) -> int:
        """Bytes of the Warp arrays of the model, the data of all worlds, and their nested structs."""
        wp = self._wp
        seen: set[int] = set()

        def size(obj: Any) -> int:
            if id(obj) in seen:
                return 0
            seen.add(id(obj))
            if isinstance(obj, wp.array):
                return obj.capacity or 0
            if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
                return sum(size(getattr(obj, f.name, None)) for f in dataclasses.fields(obj))
            return 0

        return size(self.wp_model) + size(self.wp_data)

    def check_overflow(self) -> None:
        """Raise ``RuntimeError`` if any world overflowed a buffer since the last check.

        Reads one flag back from the GPU, so it waits for the queued physics (a sync).
        """
        self._calls_since_check = 0
        bits = torch.tensor(list(_OVERFLOW_SETTINGS), dtype=self._overflow_seen.dtype, device=self.device)
        per_world = (self._overflow_seen.unsqueeze(-1) & bits) != 0  # (num_envs, settings)
        hit = per_world.any(dim=0).tolist()  # the one sync
        problems = [
            f"{what}; raise SimulationCfg.mujoco.{setting} (now {getattr(self, setting)} per world)"
            for (what, setting), flag in zip(_OVERFLOW_SETTINGS.values(), hit)
            if flag
        ]
        if problems:
            self._overflow_seen.zero_()
            raise RuntimeError(
                "MuJoCo Warp buffer overflow: "
                + "; ".join(problems)
                + ". Contacts or constraints beyond the buffers are dropped, so the physics is wrong: set"
                " env_cfg.sim.mujoco.nconmax / njmax (override sim.mujoco.nconmax=N) or pass them to"
                " make_backend(..., nconmax=..., njmax=...). " + self._overflow_diagnosis(per_world.any(dim=-1))
            )

    def _overflow_diagnosis(self, overflowed: torch.Tensor) -> str:
        """Which worlds overflowed and whether the physics blew up (only on the error path: it syncs).

        A world whose state diverged has nearly every pair of geoms in contact, so no buffer size
        is enough: the overflow is then a symptom of an unstable task, not of a small buffer.
        """
        worlds = overflowed.nonzero().flatten().tolist()
        speed = self.data("qvel").abs().amax(dim=-1)[overflowed]
        fastest = float(torch.nan_to_num(speed, nan=float("inf")).max()) if speed.numel() else 0.0
        shown = ", ".join(map(str, worlds[:8])) + (", ..." if len(worlds) > 8 else "")
        return (
            f"{len(worlds)} world(s) overflowed ({shown}); their fastest joint now moves at {fastest:.3g}"
            f" (m or rad)/s, and {int(self.diverged_count)} world(s) have diverged so far. A world that blew"
            " up touches itself everywhere: if these are large, make the task stable (actions, gains, effort"
            " limits, time step) rather than the buffers larger; scripts/tools/measure_contact_buffers.py"
            " measures what a task needs."
        )

    def close(self) -> None:
        if self.precompile is not None:
            self.precompile.wait()
        self._graphs.clear()

    @property
    def wp_device(self) -> Any:
        """The Warp device the worlds live on."""
        return self._wp_device

    def run_warp(self, key: Any, body: Callable[[], None]) -> None:
        """Run Warp launches ``body`` on torch's stream as the physics calls run: replayed from a
        graph captured on first use under ``key``, or recorded into an env step being captured
        (sensors use it for their MuJoCo Warp calls, e.g. ray casts)."""
        self._run(key, body)

    # -- helpers -------------------------------------------------------------------------------

    def _scope(self):
        """Device and stream for eager Warp work: torch's current stream, so it orders with torch."""
        wp = self._wp
        if not self._is_cuda:
            return wp.ScopedDevice(self._wp_device)
        return wp.ScopedStream(self._torch_stream())

    def _torch_stream(self) -> Any:
        """Warp's handle on torch's current stream (cached: one wrapper per torch stream)."""
        stream = torch.cuda.current_stream(self.device)
        handle = self._streams.get(stream.cuda_stream)
        if handle is None:
            handle = self._streams[stream.cuda_stream] = self._wp.stream_from_torch(stream)
        return handle

    def _run(self, key: Any, body: Callable[[], None]) -> None:
        """Replay the graph for ``key``, capturing ``body`` into it on first use."""
        wp = self._wp
        if self.precompile is not None:
            self.precompile.wait()  # no compile threads may touch CUDA while anything captures
        if self._is_cuda and is_capturing():
            # Inside a capture of the whole env step (simlab.envs.utils.cuda_graph): record the
            # kernels into that graph, on torch's capturing stream, instead of launching ours.
            # Warp must allocate its temporaries on that stream too (stream-ordered, capturable).
            stream = self._torch_stream()
            # No stream sync on entry: a wait on uncaptured work would invalidate the capture.
            with (
                wp.ScopedDevice(self._wp_device),
                wp.ScopedStream(stream, sync_enter=False, sync_exit=False),
                wp.ScopedCapture(device=self._wp_device, external=True),
            ):
                body()
            return
        graph = self._graphs.get(key)
        if graph is None:
            start = time.perf_counter()
            # Captured on Warp's own stream: capture cannot run on torch's legacy default stream.
            with gc_paused(), wp.ScopedDevice(self._wp_device), wp.ScopedCapture(device=self._wp_device) as capture:
                body()
            graph = self._graphs[key] = capture.graph
            self.capture_seconds[key] = time.perf_counter() - start
        if self._is_cuda:
            wp.capture_launch(graph, stream=self._torch_stream())
        else:
            wp.capture_launch(graph)

    def _ids_torch(self, env_ids: EnvIds) -> torch.Tensor:
        if isinstance(env_ids, torch.Tensor):
            if env_ids.dtype == torch.bool:
                env_ids = env_ids.nonzero().flatten()
            return env_ids.to(self.device, torch.long)
        return torch.as_tensor(np.asarray(env_ids, dtype=np.int64), device=self.device)
