"""Running the env step: eagerly, or replayed as one CUDA graph.

Every env class has one step body, ``env._step_body(action) -> outputs``, written with fixed
shapes: envs that finish are reset by mask (``simlab.utils.env_mask``), nothing reads a device
value back to the host. :class:`EnvStepper` runs that body:

* **eagerly**, call by call, where the simulation cannot capture steps (the CPU), where the user
  turned capture off (``cfg.sim.use_cuda_graph=False``), or where something in the step selects envs
  by ids or reads the host (``env.graph_blockers()`` names it: an Isaac Lab-style ``_reset_idx``, an
  event term without ``takes_env_mask``, one whose ``host_read`` says why for its params, ...);
* **graphed**, where the sim can capture (``sim.can_capture_steps``): ``warmup`` eager calls (lazy
  initialisation, index caches), one capture with ``torch.cuda.graph`` (MuJoCo Warp records its
  kernels into the same capture), then one replay per step. If the capture fails (a hook that
  synchronises), the env keeps stepping eagerly and says why, once.

A graph reads and writes fixed addresses, which leaves two things to handle here:

* Isaac Lab code indexes with Python lists (``joint_pos[:, self._pole_dof_idx]``); torch copies such
  a list to the device on every call, which a capture cannot record. While warming up and capturing,
  :class:`DeviceListIndices` (a ``TorchFunctionMode``, active on this thread only) indexes through
  cached device tensors instead.
* Isaac Lab code rebinds tensors (``self.potentials = ...``, ``self.metrics["error"] = ...``) in the env,
  its managers, terms, commands, sensors and assets. Inside the capture, each tensor the step put in a
  slot of any object reachable from the env is copied back into the tensor the slot held before, and
  the slot keeps that one, so the next replay reads this step's values, as eager code does
  (:mod:`simlab.envs.utils.tensor_slots`; a rebinding that cannot be replayed keeps the step eager,
  naming the slot). docs/env_step.md states the contract.

Value checks: actions (finite; a discrete action in its range, given ``action_space``) and
observations and rewards (finite) are checked every step. Eagerly the check raises at once; graphed,
flags accumulate on the device and are read every ``check_interval`` replays, since a read each step
would stall the GPU. The observation check (:class:`OutputCheck`) keeps, per world and per output
column, where a value was not finite, and the largest position, velocity and action those worlds had
then, so that its error names the observation columns (term names where the env gives them), the
worlds, and whether their physics was sane. Returned tensors are fresh copies, so callers may keep
them across steps.
"""

from __future__ import annotations

import logging
import math
import os
import traceback
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
import torch
from torch.overrides import TorchFunctionMode

from simlab.utils.cuda import gc_paused
from simlab.utils.env_mask import masked_copy_
from simlab.utils.errors import SimlabError, describe

from .spaces import ActionValueCheck
from .tensor_slots import GraphContractError, TensorSlots


class SimulationDivergedError(SimlabError, RuntimeError):
    """A world's physics blew up and ``sim.on_divergence`` is ``"raise"``."""


logger = logging.getLogger(__name__)

# Worlds whose qpos/qvel blew up are put back before the task's terms read them (take_diverged),
# so what is left is the task's own math or a derived quantity
_CAUSE = (
    "blown-up worlds (a position or velocity non-finite or above 1e10) are reset before the task reads them, so a task"
    " term divides by zero or leaves its domain (asin, acos, sqrt, log), or reads a non-finite physics quantity"
)


class EnvStepper:
    """Runs ``env._step_body`` eagerly or as a replayed CUDA graph; see the module docstring."""

    def __init__(
        self,
        env,
        body: Callable[[torch.Tensor], Any],
        warmup: int = 2,
        check_interval: int = 100,
        action_space: gym.spaces.Space | None = None,
    ):
        self.env = env
        self.body = body
        self.warmup = warmup
        self.check_interval = check_interval
        self.graph: torch.cuda.CUDAGraph | None = None
        self.eager_reason: str | None = None
        blockers = env.graph_blockers()
        if not env.sim.can_capture_steps:
            self.eager_reason = "the simulation cannot capture steps"
        elif not env.cfg.sim.use_cuda_graph:
            self.eager_reason = "cfg.sim.use_cuda_graph is False"
        elif blockers:
            self.eager_reason = "; ".join(blockers)
            print(f"[simlab] the env step runs eagerly (not as a CUDA graph): {self.eager_reason}")
        self._calls = 0
        self._index_cache: dict[tuple[int, ...], torch.Tensor] = {}
        self._static_action: torch.Tensor | None = None
        self._packed: PackedOutputs | None = None
        self.write_backs = 0  # tensors the step rebinds, copied back at each replay (see TensorSlots)
        # The env's tensors as the capture found them: the graph reads and writes these addresses, so they
        # are held here (a CUDA graph holds no tensor) even where eager code (a reset) rebinds their slots
        self._slots: TensorSlots | None = None
        self._check_actions = bool(getattr(env.cfg, "check_finite_actions", True))
        self._action_values = ActionValueCheck(action_space, env.device)  # finite; discrete ones in range
        self._bad_action = torch.zeros((), dtype=torch.bool, device=env.device)
        self._outputs = OutputCheck(env)

    @property
    def is_graphed(self) -> bool:
        """Whether steps replay a captured graph (False before the capture and when eager)."""
        return self.graph is not None

    @property
    def mode(self) -> str:
        """'graphed', 'warming up' (before the capture) or 'eager (<why>)'."""
        if self.graph is not None:
            return "graphed"
        return "warming up" if self.eager_reason is None else f"eager ({self.eager_reason})"

    def __call__(self, action: torch.Tensor) -> Any:
        self._calls += 1
        if self.eager_reason is None and self.env.sim.has_step_callbacks:
            # Python that must run at every physics / render step cannot be replayed: step eagerly from now on
            self.eager_reason = "sim.add_physics_callback / add_render_callback(name, ...) callbacks are registered"
            self.graph = None
        if self.eager_reason is not None:
            if self._check_actions:
                self._action_values.raise_if_outside(action)
            self._outputs.before_step(action)
            outputs = self.body(action)
            self._outputs.track(outputs, action)
            self._outputs.raise_if_bad("in this step")
            self._check_divergence()
            return outputs
        if self._check_actions:
            self._bad_action |= self._action_values.any_outside(action)
        if self.graph is None and self._calls > self.warmup:
            self._capture(action)
        if self.graph is not None and self._slots is not None:
            self._refill_slots()
        if self.graph is not None:
            self.env.sim.physics.before_replay()
            for static, given in zip(_tensors(self._static_action), _tensors(action)):
                static.copy_(given)
            self.graph.replay()
            outputs = self._packed.fresh_copy()  # the next replay overwrites the graph's buffers
        else:
            # the body gets copies: what the env keeps of them (``self.actions = actions``) the
            # capture's write-back refills at each replay, which must not be the caller's tensors
            self._outputs.before_step(action)
            with DeviceListIndices(torch.device(self.env.device), self._index_cache):
                outputs = self.body(_map_tensors(action, torch.clone))
            self._outputs.track(outputs, action)
            # copies: the capture's write-back refills the tensors the env holds, which may be these
            outputs = _map_tensors(outputs, torch.clone)
        if self._calls % self.check_interval == 0:
            self.check()
        return outputs

    def check(self) -> None:
        """Raise if an action or observation since the last check was not finite, or a physics
        buffer overflowed (reads a few flags back from the device)."""
        if bool(self._bad_action):
            self._bad_action.zero_()
            what = (
                "NaN or inf, or a discrete action out of range," if self._action_values.has_discrete else "NaN or inf"
            )
            raise ValueError(
                f"Actions contained {what} in a step among the last {self.check_interval} (the GPU fast path "
                f"checks periodically); {self._action_values.allowed}"
            )
        physics = self.env.sim.physics
        try:
            physics.check_overflow()  # first: physics that dropped contacts may be what made an output non-finite
        except RuntimeError as err:
            if self._outputs.any_bad():
                where = self._outputs.describe()
                self._outputs.clear()
                raise RuntimeError(f"{err} Observations or rewards were non-finite too: {where}.") from None
            raise
        self._outputs.raise_if_bad(f"in a step among the last {self.check_interval}")
        self._check_divergence()

    def _check_divergence(self) -> None:
        """With ``sim.on_divergence == "raise"``, raise if a world blew up (a host read of a count)."""
        count = self.env.sim.physics.diverged_count
        if self.env.sim.on_divergence == "raise" and bool(count > 0):
            n = int(count)
            count.zero_()
            raise SimulationDivergedError(
                f"{n} world(s) diverged (non-finite or unstable physics state): lower the actions' scale or the "
                "gains, or the time step (sim.dt). With sim.on_divergence='reset' such worlds end their episode."
            )

    def _refill_slots(self) -> None:
        """Before a replay: slots that eager code (``env.reset()``) pointed at new tensors since the last
        step go back to the graph's tensors, refilled with the new values (``TensorSlots.refill``). Else
        the graph would write into tensors nobody holds any more, which torch hands out again (the weights
        of a policy loaded next: a checkpoint judged in a running env read them overwritten), and eager
        readers would see values the graph no longer updates. A slot the graph cannot refill (another
        shape) ends the graph: the env steps eagerly from then on, saying why."""
        try:
            self._slots.refill(self.env.device)
        except GraphContractError as err:
            self.release()
            self.eager_reason = f"a tensor the graph holds was rebound outside the step: {describe(err)}"
            print(f"[simlab] the env step runs eagerly from now on: {self.eager_reason}")

    def recapture(self) -> None:
        """Drop the captured graph: the next steps warm up and capture the step again (after what the
        step runs was changed: a benchmark that leaves the physics out). Eager steppers are unaffected."""
        if self.graph is None:
            return
        self.graph = None
        self._packed = None
        self._static_action = None
        self._slots = None
        self._calls = 0

    def release(self) -> None:
        """Drop the graph and its buffers now (``env.close()``), not whenever garbage collection runs."""
        self.graph = None
        self._packed = None
        self._static_action = None
        self._slots = None
        self.eager_reason = self.eager_reason or "released"

    def _capture(self, action: torch.Tensor) -> None:
        env = self.env
        self._static_action = _map_tensors(action, lambda t: t.detach().clone())
        graph = torch.cuda.CUDAGraph()
        generator = torch.cuda.default_generators[torch.device(env.device).index or 0]
        rng_state = generator.clone_state()  # a failed capture leaves the generator mid-capture
        slots = TensorSlots(env, "env", skip=(self,))  # where every tensor of the env's objects sits now
        try:
            torch.cuda.synchronize()
            env.sim.physics.before_capture()
            # thread_local: only this thread's calls are checked (Warp may query the driver meanwhile)
            with (
                gc_paused(),
                DeviceListIndices(torch.device(env.device), self._index_cache),
                torch.cuda.graph(graph, capture_error_mode="thread_local"),
            ):
                self._outputs.before_step(self._static_action)
                outputs = self.body(self._static_action)
                self._outputs.track(outputs, self._static_action)
                self._packed = PackedOutputs(outputs)  # before the write-back, which may overwrite an output
                self.write_backs = slots.write_back(env.device)
            self.graph = graph
            self._slots = slots
        except Exception as err:  # noqa: BLE001 - any capture failure means: stay eager
            # the first error, not the failed end of the capture (a contract error names the slot itself)
            while err.__context__ is not None and not isinstance(err, GraphContractError):
                err = err.__context__
            frames = [
                f
                for f in traceback.extract_tb(err.__traceback__)
                if "site-packages" not in f.filename and f.filename != __file__  # the hook, not this module
            ]
            where = f" at {frames[-1].filename}:{frames[-1].lineno}" if frames else ""
            if isinstance(err, GraphContractError):
                where = ""  # the message names the slot; the frame would be the write-back
            self.eager_reason = f"capture failed: {describe(err)}{where}"
            self.failed_traceback = traceback.format_exc()
            self._packed = None
            torch.cuda.synchronize()
            generator.graphsafe_set_state(rng_state)
            slots.restore()  # the failed body may have rebound slots to capture memory
            logger.warning("CUDA-graph capture of the env step failed; stepping eagerly. (%s)", self.eager_reason)
            print(f"[simlab] CUDA-graph capture of the env step failed, stepping eagerly: {self.eager_reason}")


class OutputCheck:
    """Where a step's observations or rewards were not finite: per world and per output column, with the
    largest ``|qpos|``, ``|qvel|`` and ``|action|`` those worlds had in those steps.

    :meth:`track` is device ops on buffers made at its first call (a warm-up step, before any capture),
    so a captured step accumulates into them; :meth:`any_bad` and :meth:`describe` read them back (the
    periodic check, or an eager step). The state read is the one the observations came from (after the
    step's resets): it says whether the physics was sane there, or blew up below the divergence guard.
    """

    SNAPSHOT_FIELDS = ("qpos", "qvel", "qacc_warmstart", "ctrl", "act")
    """What a snapshot keeps of a world's state at the start of the step: with the action, what its
    physics step follows from (the task's own state, e.g. a goal, aside)."""

    def __init__(self, env: Any, snapshot_path: str | None = None):
        self.env = env
        # kept as "all finite so far" (fewer kernels per step than "some value bad"): False marks a bad one
        self._columns: dict[str, torch.Tensor] = {}  # output name -> (columns,) bool
        self._worlds: torch.Tensor | None = None  # (num_worlds,) bool
        self._extent: torch.Tensor | None = None  # (num_worlds, 3): max |qpos|, |qvel|, |action| there
        # SIMLAB_SNAPSHOT_BAD_WORLDS=<file.pt>: keep each bad world's state from the start of its first bad
        # step (a copy of the state per step: a debugging aid, off by default) and write them there on error
        self.snapshot_path = snapshot_path or os.environ.get("SIMLAB_SNAPSHOT_BAD_WORLDS")
        self._before: dict[str, torch.Tensor] = {}  # the state at the start of this step
        self._snapshot: dict[str, torch.Tensor] = {}  # ... at the start of each bad world's first bad step

    def before_step(self, action: Any) -> None:
        """Keep the state the step starts from, where snapshots are on (device copies, no host read)."""
        if not self.snapshot_path:
            return
        physics = self.env.sim.physics
        current = {name: physics.data(name) for name in self.SNAPSHOT_FIELDS if _has_data(physics, name)}
        current |= {f"action{i}": t for i, t in enumerate(_tensors(action))}
        for name, tensor in current.items():
            if name not in self._before:  # first call: a warm-up step, before any capture
                self._before[name] = torch.empty_like(tensor)
                self._snapshot[name] = torch.zeros_like(tensor)
            self._before[name].copy_(tensor)

    def track(self, outputs: Any, action: Any) -> None:
        """Note the worlds and columns of this step's non-finite observations and rewards (no host read;
        some fifteen small kernels per step)."""
        named = [(name, t) for name, t in _named_tensors(_observations(outputs)) if t.is_floating_point() and t.dim()]
        if not named:
            return
        good_worlds = None
        for name, tensor in named:
            finite = torch.isfinite(tensor.reshape(tensor.shape[0], -1))
            if name not in self._columns:
                self._columns[name] = torch.ones(finite.shape[1], dtype=torch.bool, device=finite.device)
            self._columns[name] &= finite.all(dim=0)
            worlds = finite.all(dim=1)
            good_worlds = worlds if good_worlds is None else good_worlds & worlds
        extent = self._state_extent(action, good_worlds.shape[0])
        if self._worlds is None:
            self._worlds = torch.ones_like(good_worlds)
            self._extent = torch.zeros_like(extent)
        if self._snapshot:
            first = self._worlds > good_worlds  # good until now, bad in this step
            for name, snapshot in self._snapshot.items():
                masked_copy_(snapshot, first, self._before[name])
        self._worlds &= good_worlds
        # NaN wins in maximum: a NaN state or action shows as nan
        torch.maximum(self._extent, torch.where(good_worlds.unsqueeze(1), 0.0, extent), out=self._extent)

    def _state_extent(self, action: Any, num_worlds: int) -> torch.Tensor:
        """(num_worlds, 3): each world's largest |qpos|, |qvel| and |action| entry (one kernel each)."""
        physics = self.env.sim.physics
        columns = []
        for name in ("qpos", "qvel"):
            data = physics.data(name) if hasattr(physics, "data") else None
            fits = data is not None and data.dim() == 2 and data.shape[0] == num_worlds and data.shape[1] > 0
            columns.append(torch.linalg.vector_norm(data, math.inf, dim=1) if fits else None)
        actions = [
            torch.linalg.vector_norm(t.reshape(num_worlds, -1).float(), math.inf, dim=1)
            for t in _tensors(action)
            if t.numel()
        ]
        columns.append(actions[0] if len(actions) == 1 else torch.stack(actions).amax(dim=0) if actions else None)
        if any(column is None for column in columns):  # a stand-in physics or no action: zeros there
            zeros = torch.zeros(num_worlds, device=self.env.device)
            columns = [zeros if column is None else column for column in columns]
        return torch.stack(columns, dim=1)

    def any_bad(self) -> bool:
        """Whether a tracked step had a non-finite output (reads one flag back)."""
        return self._worlds is not None and not bool(self._worlds.all())

    def clear(self) -> None:
        for tensor in (*self._columns.values(), self._worlds):
            tensor.fill_(True)
        for tensor in (*self._snapshot.values(), self._extent):
            tensor.zero_()

    def raise_if_bad(self, when: str) -> None:
        if self.any_bad():
            where = self.describe() + self.save_snapshot()
            self.clear()
            raise ValueError(f"Observations or rewards contained NaN or inf {when}: {where}; {_CAUSE}")

    def save_snapshot(self) -> str:
        """Write the bad worlds' snapshots (``{"worlds", "qpos", ..., "action0"}``, a row per world) to
        ``snapshot_path``; returns what the error adds ('' where snapshots are off)."""
        if not self._snapshot or self._worlds is None:
            return ""
        worlds = (~self._worlds).nonzero().flatten()
        rows = {name: tensor[worlds].cpu() for name, tensor in self._snapshot.items()}
        torch.save({"worlds": worlds.cpu(), **rows}, self.snapshot_path)
        return f" (the state each started its first such step from, and its action: {self.snapshot_path})"

    def describe(self) -> str:
        """Which outputs and columns, how many worlds (the first few), and their largest state and action."""
        parts = []
        for name, columns in self._columns.items():
            ids = (~columns).nonzero().flatten().tolist()
            if ids and columns.numel() == 1:  # a reward, one value per world
                parts.append(name)
            elif ids:
                labels = _column_labels(self.env, name, columns.numel())
                shown = ", ".join(labels[i] for i in ids[:8]) + (", ..." if len(ids) > 8 else "")
                parts.append(f"{name} columns {shown}")
        worlds = (~self._worlds).nonzero().flatten()
        qpos, qvel, action = self._extent[worlds].amax(dim=0).tolist() if len(worlds) else (0.0, 0.0, 0.0)
        shown = ", ".join(map(str, worlds[:5].tolist())) + (", ..." if len(worlds) > 5 else "")
        return (
            f"{' and '.join(parts)}, in {len(worlds)} world(s) ({shown}), whose largest |qpos| was {qpos:.3g}, "
            f"|qvel| {qvel:.3g} and |action| {action:.3g} then"
        )


def _has_data(physics: Any, name: str) -> bool:
    """Whether the backend has MjData field ``name`` per world (``act`` is missing where nothing has one)."""
    try:
        physics.data(name)
    except ValueError:
        return False
    return True


def _named_tensors(value: Any, name: str = "") -> list[tuple[str, torch.Tensor]]:
    """The tensors of nested dicts, tuples and lists with their paths: ``obs['policy']``, ``reward``."""
    if isinstance(value, torch.Tensor):
        return [(name, value)]
    if isinstance(value, dict):
        return [pair for key, item in value.items() for pair in _named_tensors(item, f"{name}[{key!r}]")]
    if isinstance(value, (tuple, list)):
        # a step's (observations, rewards): name them so
        names = ("obs", "reward") if not name and len(value) == 2 else [f"{name}[{i}]" for i in range(len(value))]
        return [pair for item, sub in zip(value, names) for pair in _named_tensors(item, sub)]
    return []


def _column_labels(env: Any, name: str, width: int) -> list[str]:
    """A label per column of output ``name`` (``obs['policy']``): the term and index within it where the
    env names them (a manager-based env's observation terms, or a direct env's ``observation_columns``),
    else the column index."""
    labels: list[str] | None = None
    group = name[len("obs['") : -len("']")] if name.startswith("obs['") and name.endswith("']") else None
    if group is not None:
        manager = getattr(env, "observation_manager", None)
        if manager is not None and manager.group_obs_concatenate.get(group, False):
            terms = zip(manager.active_terms[group], manager.group_obs_term_dim[group])
            labels = _term_labels([(term, math.prod(dim)) for term, dim in terms])
        elif hasattr(env, "observation_columns"):
            layout = env.observation_columns(group)
            labels = _term_labels(layout) if layout else None
    if labels is None or len(labels) != width:
        return [str(i) for i in range(width)]
    return labels


def _term_labels(layout: list[tuple[str, int]]) -> list[str]:
    """``"<column> (<term>[<index in the term>])"`` for each column of terms laid out one after another."""
    labels: list[str] = []
    for term, width in layout:
        labels += [f"{len(labels) + i} ({term}[{i}])" for i in range(width)]
    return labels


def _observations(outputs: Any) -> Any:
    """The observations and rewards of a step's outputs (what a diverged simulation spoils)."""
    return outputs[:2] if isinstance(outputs, tuple) else outputs


class DeviceListIndices(TorchFunctionMode):
    """Index device tensors with Python int lists through cached device tensors, and assign Python
    scalars through device fills (no host-to-device copy, which a capture cannot record).

    The results equal indexing with the lists. Used while warming up and capturing, so that the
    index tensors exist before the capture starts.
    """

    def __init__(self, device: torch.device, cache: dict[tuple[int, ...], torch.Tensor]):
        super().__init__()
        self.device = device
        self.cache = cache

    def __torch_function__(self, func, types, args=(), kwargs=None):
        kwargs = kwargs or {}
        if func in (torch.Tensor.__getitem__, torch.Tensor.__setitem__) and args[0].device == self.device:
            args = (args[0], self._convert(args[1]), *args[2:])
            if func is torch.Tensor.__setitem__ and isinstance(args[2], (int, float, bool)):
                args = (args[0], args[1], torch.full((), args[2], dtype=args[0].dtype, device=self.device))
        return func(*args, **kwargs)

    def _convert(self, index):
        if isinstance(index, tuple):
            return tuple(self._convert(i) for i in index)
        if isinstance(index, list) and index and all(_is_int(i) for i in index):
            key = tuple(int(i) for i in index)
            if key not in self.cache:
                self.cache[key] = torch.tensor(key, dtype=torch.long, device=self.device)
            return self.cache[key]
        return index


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
