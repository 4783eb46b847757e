"""Where the tensors of an env live, and which ones a step rebinds: the CUDA graph's contract.

A CUDA graph replays the kernels of one captured step at the addresses they had then. A step that
*rebinds* a tensor (``self.metrics["error"] = torch.norm(...)``, ``self._buf = self._buf * 2``,
Isaac Lab's own idiom) leaves the name pointing at the tensor made during the capture, while the
graph keeps reading the tensor the name held before: replayed, such code would read stale values.

:class:`TensorSlots` records every slot that holds a tensor in the objects reachable from the env
(attributes of objects, dict entries, list items: the managers, their terms, commands and their
``metrics``, the scene's assets and sensors and their data, the env), walking ``__dict__``\\ s, dicts,
lists and tuples once with a visited set. :meth:`TensorSlots.write_back`, called inside the capture
after the step, finds the slots the step rebound and records a copy of each new tensor into the
tensor the slot held before, then points the slot at that old tensor again: each replay then leaves
this step's values where the next replay (and any reader) looks for them, as eager code does.

What cannot be made so (a tensor rebound to one of another shape, dtype or device, or made on the
host each step) raises :class:`GraphContractError` naming the slot
(``env.reward_manager._terms['track'].metrics['error']``); the capture then fails and the step runs
eagerly, saying why once. Python values (ints, floats) are
not tensors and not replayed: a step must keep its per-step state in tensors.
"""

from __future__ import annotations

import types
from collections.abc import Iterator
from typing import Any

import torch

from simlab.utils.errors import SimlabError

# objects whose attributes are not step state: code, classes, modules
_OPAQUE = (type, types.ModuleType, types.FunctionType, types.MethodType, types.BuiltinFunctionType)


class GraphContractError(SimlabError, RuntimeError):
    """A step rebinds a tensor in a way a replayed CUDA graph cannot reproduce."""


class TensorSlots:
    """The slots (container, key) holding tensors, dicts, lists or tuples reachable from ``root``.

    ``skip``: objects not to walk into (the stepper itself: its caches are not step state).
    """

    def __init__(self, root: Any, name: str = "env", skip: tuple[Any, ...] = ()):
        self.slots: list[tuple[Any, Any, Any, str]] = []  # (container, key, value, path)
        self.written: list[tuple[Any, Any, Any, str]] = []  # the slots the step rebinds (write_back)
        skipped = {id(obj) for obj in skip}
        visited: set[int] = set()
        stack: list[tuple[Any, str]] = [(root, name)]
        while stack:
            obj, path = stack.pop()
            if id(obj) in visited or id(obj) in skipped:
                continue
            visited.add(id(obj))
            for key, value, value_path, writable in _items(obj, path):
                if isinstance(value, (torch.Tensor, dict, list, tuple)) and writable:
                    self.slots.append((obj, key, value, value_path))
                if not isinstance(value, torch.Tensor) and not isinstance(value, _OPAQUE):
                    stack.append((value, value_path))

    def rebound(self) -> list[tuple[str, Any, Any]]:
        """``(path, before, now)`` of each slot whose value is no longer the same object."""
        changed = []
        for container, key, before, path in self.slots:
            now = _get(container, key)
            if now is not before and now is not _MISSING:
                changed.append((path, before, now))
        return changed

    def write_back(self, device: torch.device | str) -> int:
        """Inside the capture, after the step on ``device``: copy each rebound tensor into the tensor its
        slot held before and point the slot at that one again. Returns how many tensors are copied per replay.
        The slots it found rebound are kept (``written``, with what they hold now) for :meth:`refill`."""
        self.written = [slot for slot in self.slots if _rebound(slot)]
        return self._copy_back(device)

    def refill(self, device: torch.device | str) -> int:
        """Outside the capture, before a replay: where code run eagerly since (an env's ``reset()``, whose
        observations rebind what the step rebinds) pointed a slot of :attr:`written` at a new tensor, copy
        it into the tensor the graph holds and point the slot back there. The graph then starts from what
        that code wrote, and nobody is left holding a tensor the graph does not update. Returns how many
        slots were refilled (a look at each slot the step rebinds when none was: a few microseconds)."""
        rebound = sum(_rebound(slot) for slot in self.written)
        if rebound:
            self._copy_back(device)
        return rebound

    def _copy_back(self, device: torch.device | str) -> int:
        """Point each rebound slot of :attr:`written` at its old tensors, refilled by copies (recorded in a
        capture, run at once outside one); ``written`` then holds what the slots hold."""
        device = torch.device(device)
        copies: list[tuple[torch.Tensor, torch.Tensor, str]] = []  # (old, new, path)
        for i, (container, key, before, path) in enumerate(self.written):
            now = _get(container, key)
            if now is before or now is _MISSING:
                continue
            value = _restored(before, now, path, copies, device)  # the old tensors (in a new tuple, say)
            _set(container, key, value)
            self.written[i] = (container, key, value, path)
        # A new tensor may share memory with another slot's old one (``self.prev = self.cur;
        # self.cur = new``): read every such source before anything is written.
        targets = {old.untyped_storage().data_ptr() for old, _, _ in copies}
        sources = [new.clone() if new.untyped_storage().data_ptr() in targets else new for _, new, _ in copies]
        for (old, _, path), new in zip(copies, sources):
            try:
                old.copy_(new)
            except RuntimeError as error:  # e.g. an expanded tensor: its elements share memory
                raise GraphContractError(
                    f"the step rebinds {path}, and its old tensor cannot be refilled: {error}"
                ) from error
        return len(copies)

    def restore(self) -> None:
        """Point every slot at what it held when recorded (after a failed capture)."""
        for container, key, before, _ in self.slots:
            if _get(container, key) is not before:
                _set(container, key, before)


_MISSING = object()


def _rebound(slot: tuple[Any, Any, Any, str]) -> bool:
    """Whether the slot holds another object than when it was recorded (and still exists)."""
    container, key, before, _ = slot
    now = _get(container, key)
    return now is not before and now is not _MISSING


def _items(obj: Any, path: str) -> Iterator[tuple[Any, Any, str, bool]]:
    """``(key, value, path, writable)`` of what ``obj`` holds."""
    if isinstance(obj, dict):
        for key, value in list(obj.items()):
            yield key, value, f"{path}[{key!r}]", True
    elif isinstance(obj, (list, tuple)):
        for i, value in enumerate(obj):
            yield i, value, f"{path}[{i}]", isinstance(obj, list)
    elif not isinstance(obj, _OPAQUE) and isinstance(getattr(obj, "__dict__", None), dict):
        for key, value in list(vars(obj).items()):
            yield key, value, f"{path}.{key}", True


def _get(container: Any, key: Any) -> Any:
    if isinstance(container, (dict, list)):
        try:
            return container[key]
        except (KeyError, IndexError):
            return _MISSING
    return vars(container).get(key, _MISSING)


def _set(container: Any, key: Any, value: Any) -> None:
    if isinstance(container, (dict, list)):
        container[key] = value
    else:
        vars(container)[key] = value  # not setattr: a property or __setattr__ hook must not run twice


def _restored(before: Any, now: Any, path: str, copies: list, device: torch.device) -> Any:
    """What a rebound slot should hold after the write-back: the old tensors, refreshed by a copy."""
    if isinstance(before, torch.Tensor) and isinstance(now, torch.Tensor):
        if now.device.type != device.type:
            raise GraphContractError(
                f"the step rebinds {path} to a tensor on {now.device}, made anew each step; the graph replays "
                f"work on {device} only: make it on {device}, or keep it out of the step"
            )
        if (before.shape, before.dtype, before.device) != (now.shape, now.dtype, now.device):
            raise GraphContractError(
                f"the step rebinds {path} to a tensor of another shape, dtype or device "
                f"({tuple(before.shape)} {before.dtype} {before.device} -> {tuple(now.shape)} {now.dtype} "
                f"{now.device}); a CUDA graph replays fixed buffers: keep it one shape, or write into it in place"
            )
        if not _same_memory(before, now):
            copies.append((before, now, path))
        return before
    if isinstance(before, dict) and isinstance(now, dict):  # a rebuilt dict (``self.metrics = {...}``)
        # ``now`` itself is left as it is: it may be the step's input (a multi-agent task's
        # ``self.actions = actions``: the stepper's static actions, which each replay refills)
        restored = {
            key: _restored(before[key], value, f"{path}[{key!r}]", copies, device) if key in before else value
            for key, value in now.items()
        }
        if before.keys() != now.keys():
            return restored  # other keys: a new dict, holding the old tensors where it can
        before.update(restored)  # the old dict object too: readers may hold it
        return before
    if isinstance(before, (list, tuple)) and isinstance(now, (list, tuple)) and len(before) == len(now):
        items = [_restored(b, n, f"{path}[{i}]", copies, device) for i, (b, n) in enumerate(zip(before, now))]
        if all(item is old for item, old in zip(items, before)) and type(before) is type(now):
            return before
        return type(now)(items)
    return now  # not a tensor (or no longer one): Python values are not replayed (see the module docstring)


def _same_memory(a: torch.Tensor, b: torch.Tensor) -> bool:
    return a.data_ptr() == b.data_ptr() and a.stride() == b.stride()
