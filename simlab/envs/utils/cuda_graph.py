"""The GPU fast path: a whole env step replayed as one CUDA graph.

On the GPU an env step is a few hundred small kernels (action processing, the decimated physics
steps, dones, rewards, resets, observations). Launched one by one from Python they cost more than
the physics itself at a few thousand envs, and the resets' ``nonzero()`` stalls the pipeline every
step. ``CudaGraphStep`` records the step once with ``torch.cuda.graph`` (MuJoCo Warp's kernels join
the same capture on the same stream) and then replays it for each call.

A graph has fixed shapes, so resets are done by mask instead of by index: the step resets *every*
env and keeps the reset state only where the env finished. Which tensors a reset touches is learnt
once, eagerly, from a full reset (the physics state plus every env-sized tensor whose in-place
version counter moved); those are saved before the reset and blended back after it::

    saved = [t.clone() for t in touched]
    env._reset_idx(all_envs)
    t.copy_(torch.where(finished, t, saved))   # for each touched tensor

What cannot be captured (a task hook that synchronises, reads ``.item()``, or copies from the
host) makes the capture fail; the env then keeps stepping eagerly and says so once. Returned
tensors are copies of the graph's static buffers, so a caller may keep them across steps.
Finite actions and observations (a diverged state shows there first) are checked on the device and
reported at the next periodic check (every ``check_interval`` steps), since checking each step
would stall the pipeline.
"""

from __future__ import annotations

import contextlib
import logging
import traceback
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
import torch

from simlab.utils.cuda import gc_paused

logger = logging.getLogger(__name__)

# MjData fields that hold a world's dynamic state: what a reset may write, what a blend restores.
PHYSICS_STATE = (
    "qpos",
    "qvel",
    "act",
    "ctrl",
    "mocap_pos",
    "mocap_quat",
    "qfrc_applied",
    "xfrc_applied",
    "qacc_warmstart",
)


Location = tuple  # (container, key): an attribute of an object, an item of a dict or list


def env_sized_tensors(root: Any, num_envs: int, device: torch.device, depth: int = 4) -> dict[tuple, Location]:
    """Where tensors of leading size ``num_envs`` on ``device`` live, reachable from ``root``.

    Walks attributes, dicts, lists and tuples of simlab objects (env, scene, assets, managers,
    terms, actuators) and of the task, not into foreign libraries. Returns locations rather than
    tensors: a reset may *replace* a tensor (``self.potentials = ...``), and the blend must act on
    what the attribute holds after the reset. Keys are ``(id(container), key)``.
    """
    found: dict[tuple, Location] = {}
    seen: set[int] = set()

    def visit(obj: Any, level: int) -> None:
        if level > depth or id(obj) in seen or isinstance(obj, torch.Tensor):
            return
        seen.add(id(obj))
        if isinstance(obj, dict):
            items: Iterable = obj.items()
        elif isinstance(obj, list):
            items = enumerate(obj)
        elif hasattr(obj, "__dict__") and _is_simlab_or_task(obj):
            items = vars(obj).items()
        else:
            return
        for key, child in list(items):
            if isinstance(child, torch.Tensor):
                if child.dim() > 0 and child.shape[0] == num_envs and child.device == device:
                    found[(id(obj), key)] = (obj, key)
            else:
                visit(child, level + 1)

    visit(root, 0)
    return found


def _get(location: Location) -> Any:
    container, key = location
    return container[key] if isinstance(container, (dict, list)) else getattr(container, key, None)


def _is_simlab_or_task(obj: Any) -> bool:
    module = type(obj).__module__
    return not module.startswith(("torch", "numpy", "mujoco", "warp", "gymnasium", "builtins"))


class CudaGraphStep:
    """Replays ``step_fn(actions)`` as one CUDA graph; see the module docstring.

    Args:
        env: the env (for ``num_envs``, ``device``, ``sim`` and ``_reset_idx``).
        step_fn: the env step written with :meth:`masked_reset` instead of index resets; it
            returns the step's outputs (tensors, or dicts/tuples of tensors).
        warmup: eager calls before the capture (lazy initialisation must not be captured).
        check_interval: replays between two checks of actions and physics buffers (each a sync).
    """

    def __init__(self, env, step_fn: Callable[[torch.Tensor], Any], warmup: int = 2, check_interval: int = 100):
        self.env = env
        self.step_fn = step_fn
        self.warmup = warmup
        self.check_interval = check_interval
        self.graph: torch.cuda.CUDAGraph | None = None
        self.failed: str | None = None
        self._calls = 0
        self._touched: list[torch.Tensor] | None = None
        self._static_action: torch.Tensor | None = None
        self._index_cache: dict[tuple[int, ...], torch.Tensor] = {}
        self._packed: PackedOutputs | None = None
        self._nonfinite = torch.zeros((), dtype=torch.bool, device=env.device)
        self._nonfinite_outputs = torch.zeros((), dtype=torch.bool, device=env.device)
        self._stale_at_capture = True

    # -- masked resets ---------------------------------------------------------------------------

    def learn_reset_footprint(self) -> None:
        """Find what a full reset writes: run ``env._reset_idx`` on all envs, eagerly, once.

        Call it where the env resets every env anyway (``reset()``), in place of that reset.
        """
        env = self.env
        device = torch.device(env.device)
        physics = env.sim.physics
        bound = physics.bound_data()  # the backend's name -> tensor table (a dict location)
        state = {(id(bound), name): (bound, name) for name in PHYSICS_STATE if _has_field(physics, name)}
        before = {**state, **env_sized_tensors(env, env.num_envs, device)}
        versions = {key: (id(_get(loc)), _get(loc)._version) for key, loc in before.items()}
        with _calls_noted(physics, "_reset") as physics_resets:
            env._reset_idx(env._all_env_ids)
        after = {**state, **env_sized_tensors(env, env.num_envs, device)}
        # A backend reset writes the whole physics state in kernels that torch's version counters
        # do not see; without one, the state fields count as touched only where torch wrote them.
        touched = dict(state) if physics_resets else {}
        for key, loc in after.items():
            tensor = _get(loc)
            if versions.get(key) != (id(tensor), tensor._version):  # written in place, or replaced
                touched.setdefault(key, loc)
        # One location per tensor (an asset's qpos view is the backend's qpos), none for empty ones.
        by_tensor: dict[int, Location] = {}
        for loc in touched.values():
            tensor = _get(loc)
            if tensor.numel() > 0:
                by_tensor.setdefault(id(tensor), loc)
        self._touched = list(by_tensor.values())

    def masked_reset(self, finished: torch.Tensor) -> None:
        """Reset the envs where ``finished`` is True without data-dependent shapes."""
        env = self.env
        if self._touched is None:
            raise RuntimeError("learn_reset_footprint() must run before masked_reset()")
        saved = [_get(loc).clone() for loc in self._touched]
        env._reset_idx(env._all_env_ids)
        for loc, old in zip(self._touched, saved):
            tensor = _get(loc)  # what the location holds now (a reset may replace it)
            if tensor is None or tensor.shape != old.shape:
                continue
            mask = finished.view(-1, *([1] * (tensor.dim() - 1)))
            torch.where(mask, tensor, old, out=tensor)  # elementwise, so writing in place is safe

    # -- stepping --------------------------------------------------------------------------------

    def __call__(self, action: torch.Tensor) -> Any:
        self._nonfinite |= ~torch.isfinite(action).all()
        self._calls += 1
        if self.graph is None and self.failed is None and self._calls > self.warmup:
            self._capture(action)
        if self.graph is None and self._calls == self.warmup:
            with list_indices_on_device(torch.device(self.env.device), self._index_cache):
                outputs = self.step_fn(action)  # also prepares the index tensors for the capture
        elif self.graph is None:
            outputs = self.step_fn(action)
        else:
            physics = self.env.sim.physics
            if physics.is_stale and not self._stale_at_capture:
                physics.ensure_forward()  # state written since the last step; the graph assumes it forwarded
            self._static_action.copy_(action)
            self.graph.replay()
            # Fresh tensors, as an eager step returns: the next replay overwrites the graph's buffers,
            # and learners keep references (rsl_rl stores the observation it acted on until after
            # the next step returns; aliased, it would store the next observation instead).
            outputs = self._packed.fresh_copy()
        if self._calls % self.check_interval == 0:
            self.check()
        return outputs

    def release(self) -> None:
        """Drop the graph and its buffers now (``env.close()``), not whenever garbage collection runs."""
        self.graph = None
        self._packed = None
        self._static_action = None
        self.failed = self.failed or "released"  # a released step stays eager

    def check(self) -> None:
        """Raise if an action since the last check was not finite, or a physics buffer overflowed."""
        if bool(self._nonfinite):
            self._nonfinite.zero_()
            raise ValueError(
                f"Actions contained NaN or inf in a step among the last {self.check_interval} (the GPU fast path "
                "checks periodically); actions must be finite"
            )
        if bool(self._nonfinite_outputs):
            self._nonfinite_outputs.zero_()
            raise ValueError(
                f"Observations contained NaN or inf in a step among the last {self.check_interval}: the "
                "simulation diverged (large actions or gains for the time step?) or a task term divides by zero"
            )
        check_overflow = getattr(self.env.sim.physics, "check_overflow", None)
        if check_overflow is not None:
            check_overflow()

    @staticmethod
    def _keep_rebound_tensors(before: dict) -> None:
        """Steps that rebind attributes (``self.potentials = ...``) read the old tensor first.

        A graph reads and writes fixed addresses: code that reads ``self.potentials`` and then
        rebinds it would, on every replay, read the tensor it saw at capture time. So the graph
        ends by copying each rebound tensor back into the old one, and the attribute keeps the
        old one: the next replay then reads this step's values, as eager code does.
        """
        for loc, old in before.values():
            new = _get(loc)
            if isinstance(new, torch.Tensor) and new is not old and new.shape == old.shape and new.dtype == old.dtype:
                old.copy_(new)
                container, key = loc
                if isinstance(container, (dict, list)):
                    container[key] = old
                else:
                    setattr(container, key, old)

    def _capture(self, action: torch.Tensor) -> None:
        self._static_action = action.detach().clone()
        graph = torch.cuda.CUDAGraph()
        generator = torch.cuda.default_generators[torch.cuda.current_device()]
        rng_state = generator.clone_state()  # a failed capture leaves the generator mid-capture
        try:
            torch.cuda.synchronize()
            # thread_local: only this thread's calls are checked (Warp may query the driver meanwhile)
            device = torch.device(self.env.device)
            before = {
                key: (loc, _get(loc)) for key, loc in env_sized_tensors(self.env, self.env.num_envs, device).items()
            }
            # Which derived quantities the replays may take as current at the start of a step (see
            # PhysicsBackend.ensure_forward): the capture records a forward only where one was due.
            self._stale_at_capture = self.env.sim.physics.is_stale
            with (
                gc_paused(),
                list_indices_on_device(device, self._index_cache),
                torch.cuda.graph(graph, capture_error_mode="thread_local"),
            ):
                outputs = self.step_fn(self._static_action)
                self._keep_rebound_tensors(before)
                observations = outputs[0] if isinstance(outputs, tuple) else outputs
                for tensor in _tensors(observations):  # a diverged state shows in the observations
                    if tensor.is_floating_point():
                        self._nonfinite_outputs.logical_or_(~torch.isfinite(tensor).all())
                self._packed = PackedOutputs(outputs)
            self.graph = graph
        except Exception as err:  # noqa: BLE001 - any capture failure means: stay eager
            frames = [f for f in traceback.extract_tb(err.__traceback__) if "site-packages" not in f.filename]
            where = f" at {frames[-1].filename}:{frames[-1].lineno}" if frames else ""
            self.failed = f"{type(err).__name__}: {err}{where}"
            self.failed_traceback = traceback.format_exc()
            self._packed = None
            torch.cuda.synchronize()
            generator.graphsafe_set_state(rng_state)
            logger.warning("CUDA-graph capture of the env step failed; stepping eagerly. (%s)", self.failed)
            print(f"[simlab] CUDA-graph capture of the env step failed, stepping eagerly: {self.failed}")


@contextlib.contextmanager
def list_indices_on_device(device: torch.device, cache: dict[tuple[int, ...], torch.Tensor]):
    """While capturing, index tensors with Python int lists through cached device tensors, and
    assign Python scalars through device fills.

    Isaac Lab-style code indexes with the lists ``find_joints`` returns
    (``joint_pos[:, self._cart_dof_idx]``). Torch turns such a list into a host tensor and copies
    it to the GPU on every call, which a CUDA graph cannot record. The capture runs the step's
    Python once, so converting the lists then is enough: the replays index with the recorded
    device tensors. Indexing results are the same as with the lists. The last eager step before
    the capture runs with the same ``cache`` so that the device tensors exist before the capture
    starts (creating one is itself a copy that a capture cannot hold).
    """
    get_item, set_item = torch.Tensor.__getitem__, torch.Tensor.__setitem__

    def convert(index, tensor_device):
        if isinstance(index, tuple):
            return tuple(convert(i, tensor_device) for i in index)
        if isinstance(index, list) and index and tensor_device == device and all(_is_int(i) for i in index):
            key = tuple(int(i) for i in index)
            if key not in cache:
                cache[key] = torch.tensor(key, dtype=torch.long, device=device)
            return cache[key]
        return index

    def getitem(self, index):
        return get_item(self, convert(index, self.device))

    def setitem(self, index, value):
        if isinstance(value, (int, float, bool)) and self.device == device:
            # ``x[ids] = 0.0`` would copy a host scalar; a fill on the device records as a kernel.
            value = torch.full((), value, dtype=self.dtype, device=device)
        return set_item(self, convert(index, self.device), value)

    torch.Tensor.__getitem__, torch.Tensor.__setitem__ = getitem, setitem
    try:
        yield cache
    finally:
        torch.Tensor.__getitem__, torch.Tensor.__setitem__ = get_item, set_item


def _tensors(value: Any) -> list[torch.Tensor]:
    """The tensors in nested dicts, tuples and lists."""
    if isinstance(value, torch.Tensor):
        return [value]
    items = value.values() if isinstance(value, dict) else value if isinstance(value, (tuple, list)) else ()
    return [tensor for item in items for tensor in _tensors(item)]


class PackedOutputs:
    """A step's output tensors gathered into one flat buffer per dtype, inside the graph.

    Copying them out after each replay then takes one kernel per dtype instead of one per tensor
    (a manager-based step returns a dozen: observations, rewards, dones, episode logs).
    """

    def __init__(self, outputs: Any):
        self.outputs = outputs
        self.layout: list[tuple[torch.dtype, int, torch.Size]] = []
        groups: dict[torch.dtype, list[torch.Tensor]] = {}
        for tensor in _tensors(outputs):
            group = groups.setdefault(tensor.dtype, [])
            self.layout.append((tensor.dtype, sum(t.numel() for t in group), tensor.shape))
            group.append(tensor)
        self.buffers = {dtype: torch.cat([t.reshape(-1) for t in group]) for dtype, group in groups.items()}

    def fresh_copy(self) -> Any:
        """The outputs as views into fresh copies of the buffers."""
        copies = {dtype: buffer.clone() for dtype, buffer in self.buffers.items()}
        views = iter(copies[dtype].narrow(0, start, shape.numel()).view(shape) for dtype, start, shape in self.layout)
        return _map_tensors(self.outputs, lambda _: next(views))


def _map_tensors(value: Any, fn: Callable[[torch.Tensor], Any]) -> Any:
    """``value`` with each tensor in its nested dicts, tuples and lists replaced by ``fn(tensor)``,
    in the order ``_tensors`` lists them."""
    if isinstance(value, torch.Tensor):
        return fn(value)
    if isinstance(value, dict):
        return {key: _map_tensors(item, fn) for key, item in value.items()}
    if isinstance(value, (tuple, list)):
        return type(value)(_map_tensors(item, fn) for item in value)
    return value


def _is_int(value) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


@contextlib.contextmanager
def _calls_noted(obj: Any, method: str):
    """Yields a list that gets one entry per call of ``obj.<method>`` inside the block."""
    calls: list[tuple] = []
    original = getattr(obj, method)

    def noted(*args, **kwargs):
        calls.append(args)
        return original(*args, **kwargs)

    setattr(obj, method, noted)
    try:
        yield calls
    finally:
        delattr(obj, method)  # back to the class's method


def _has_field(physics, name: str) -> bool:
    try:
        physics.data(name)
    except ValueError:
        return False
    return True
