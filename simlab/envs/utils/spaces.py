"""Gymnasium spaces from the short specs that env configs use, and torch samples of them.

A config declares a space either as a Gymnasium space or with plain Python values (Isaac Lab's
convention):

=======================  ===================================================
Python spec              Gymnasium space
=======================  ===================================================
``7``, ``[64, 64, 3]``   ``Box(-inf, inf, shape)``
``{2}``                  ``Discrete(2)``
``[{2}, {5}]``           ``MultiDiscrete([2, 5])``
``{"a": 7, "b": {2}}``   ``Dict`` of the above
``(7, {2})``             ``Tuple`` of the above
=======================  ===================================================
"""

from __future__ import annotations

import json
from typing import Any

import gymnasium as gym
import numpy as np
import torch

SpaceType = gym.spaces.Space | int | set | list | tuple | dict
"""What a config may give as a space (see the module docstring)."""


def spec_to_gym_space(spec: SpaceType) -> gym.spaces.Space:
    """The Gymnasium space a config spec stands for (see the module docstring)."""
    if isinstance(spec, gym.spaces.Space):
        return spec
    if isinstance(spec, bool):
        raise ValueError(f"Unsupported space spec {spec!r}: {_ALLOWED}")
    if isinstance(spec, (int, np.integer)):
        if spec < 0:
            raise ValueError(f"A Box size must be >= 0, got {spec}")
        return gym.spaces.Box(low=-np.inf, high=np.inf, shape=(int(spec),))
    if isinstance(spec, set):
        if len(spec) == 1 and isinstance(next(iter(spec)), int):
            return gym.spaces.Discrete(n=next(iter(spec)))
    elif isinstance(spec, list) and spec:
        if all(isinstance(x, int) and not isinstance(x, bool) for x in spec):
            return gym.spaces.Box(low=-np.inf, high=np.inf, shape=tuple(spec))
        if all(isinstance(x, set) and len(x) == 1 for x in spec):
            return gym.spaces.MultiDiscrete(nvec=[next(iter(x)) for x in spec])
    elif isinstance(spec, tuple):
        return gym.spaces.Tuple([spec_to_gym_space(x) for x in spec])
    elif isinstance(spec, dict):
        return gym.spaces.Dict({k: spec_to_gym_space(v) for k, v in spec.items()})
    raise ValueError(f"Unsupported space spec {spec!r}: {_ALLOWED}")


_ALLOWED = (
    "use a gymnasium space, an int or list of ints (Box), a one-element set (Discrete), a list of "
    "one-element sets (MultiDiscrete), or a dict / tuple of these"
)


def sample_space(
    space: gym.spaces.Space, device: str | torch.device, batch_size: int = -1, fill_value: float | None = None
) -> Any:
    """A sample of ``space`` as torch tensors (a dict / tuple of them for composite spaces).

    With ``batch_size > 0`` every leaf gets a leading batch dimension; ``fill_value`` overwrites the
    random values (e.g. 0 for an initial action buffer).
    """
    if isinstance(space, gym.spaces.Dict):
        return {k: sample_space(s, device, batch_size, fill_value) for k, s in space.items()}
    if isinstance(space, gym.spaces.Tuple):
        return tuple(sample_space(s, device, batch_size, fill_value) for s in space)
    batch = (batch_size,) if batch_size > 0 else ()
    if isinstance(space, gym.spaces.Box):
        shape, dtype = batch + space.shape, torch.float32
    elif isinstance(space, gym.spaces.Discrete):
        shape, dtype = batch + (1,), torch.int64
    elif isinstance(space, gym.spaces.MultiDiscrete):
        shape, dtype = batch + space.shape, torch.int64
    else:
        raise ValueError(
            f"Cannot sample a {type(space).__name__} space as tensors: use Box, Discrete, MultiDiscrete, Dict or Tuple"
        )
    if fill_value is not None:
        return torch.full(shape, fill_value, dtype=dtype, device=device)
    sampled = (gym.vector.utils.batch_space(space, batch_size) if batch_size > 0 else space).sample()
    return torch.as_tensor(np.asarray(sampled), dtype=dtype, device=device).reshape(shape)


# -- actions checked against the env's action space ------------------------------------------------


def check_action(action: Any, space: gym.spaces.Space, num_envs: int, device: str | torch.device) -> Any:
    """A batch of actions for ``space`` (one env's space) as detached torch tensors on ``device``.

    Shapes are ``(num_envs, *space.shape)``; a Discrete action is ``(num_envs, 1)`` (as
    :func:`sample_space` and skrl give it) or ``(num_envs,)`` (as ``env.action_space.sample()`` gives
    it). Box actions become float32; Discrete and MultiDiscrete ones must be integers and become int64.
    A Dict or Tuple space takes a dict or tuple of these. Values (finite, in range) are checked where
    the step runs, without a host read on the graphed path: :class:`ActionValueCheck`.
    """
    return _check_action(action, space, num_envs, torch.device(device), "Actions")


def _check_action(action: Any, space: gym.spaces.Space, num_envs: int, device: torch.device, name: str) -> Any:
    if isinstance(space, gym.spaces.Dict):
        if not isinstance(action, dict) or set(action) != set(space.spaces):
            given = f"keys {list(action)}" if isinstance(action, dict) else f"a {type(action).__name__}"
            raise ValueError(f"{name} for a Dict space must be a dict with the keys {list(space.spaces)}, got {given}")
        return {k: _check_action(action[k], s, num_envs, device, f"{name}[{k!r}]") for k, s in space.spaces.items()}
    if isinstance(space, gym.spaces.Tuple):
        if not isinstance(action, (tuple, list)) or len(action) != len(space.spaces):
            given = f"{len(action)} items" if isinstance(action, (tuple, list)) else f"a {type(action).__name__}"
            raise ValueError(f"{name} for a Tuple space must be a tuple of {len(space.spaces)} actions, got {given}")
        return tuple(
            _check_action(a, s, num_envs, device, f"{name}[{i}]") for i, (a, s) in enumerate(zip(action, space))
        )
    if not isinstance(action, torch.Tensor):
        try:
            action = torch.as_tensor(np.asarray(action))
        except (TypeError, ValueError, RuntimeError) as err:
            raise ValueError(
                f"{name} must be a tensor or array of numbers for {space}, got {type(action).__name__}"
            ) from err
    action = action.detach()
    discrete = isinstance(space, gym.spaces.Discrete)
    if discrete and tuple(action.shape) == (num_envs,):
        action = action.reshape(num_envs, 1)  # env.action_space.sample() gives one int per env
    expected = (num_envs, 1) if discrete else (num_envs, *space.shape)
    if tuple(action.shape) != expected:
        also = f" or {(num_envs,)}" if discrete else ""
        raise ValueError(
            f"{name} for {space} must have shape {expected}{also} (num_envs, *action shape), got {tuple(action.shape)}"
        )
    if isinstance(space, gym.spaces.Box):
        return action.to(device=device, dtype=torch.float32)
    if isinstance(space, (gym.spaces.Discrete, gym.spaces.MultiDiscrete)):
        if action.is_floating_point() or action.is_complex() or action.dtype == torch.bool:
            raise ValueError(f"{name} for {space} must hold integers ({_allowed(space)}), got {action.dtype}")
        return action.to(device=device, dtype=torch.int64)
    return action.to(device)


class ActionValueCheck:
    """Finds actions outside the action space by value: NaN or inf, or a Discrete / MultiDiscrete entry
    out of its range (Box bounds are not checked: Isaac Lab's policies act unbounded and tasks clip).

    :meth:`any_outside` is device ops only, so a graphed step can accumulate it and read it at its
    periodic check; :meth:`raise_if_outside` reads it back (eager steps). With ``space=None`` only NaN
    and inf are looked for, in every floating tensor of the action.
    """

    def __init__(self, space: gym.spaces.Space | None, device: str | torch.device):
        self.space = space
        # each discrete space's (lowest, highest) value: built once, no host-to-device copy per step
        self._ranges: dict[int, tuple] = {}
        for leaf in _leaf_spaces(space):
            if isinstance(leaf, gym.spaces.Discrete):
                self._ranges[id(leaf)] = (int(leaf.start), int(leaf.start + leaf.n - 1))
            elif isinstance(leaf, gym.spaces.MultiDiscrete):
                low, high = torch.as_tensor(leaf.start), torch.as_tensor(leaf.start + leaf.nvec - 1)
                self._ranges[id(leaf)] = (low.to(device), high.to(device))
        discrete = [leaf for leaf in _leaf_spaces(space) if id(leaf) in self._ranges]
        self.allowed = "actions must be finite" + "".join(f"; {leaf}: {_allowed(leaf)}" for leaf in discrete)
        self.has_discrete = bool(discrete)

    def any_outside(self, action: Any) -> torch.Tensor:
        """A 0-d bool tensor: whether any env's action lies outside the space (no host read)."""
        flags = [bad.any() for _, _, _, bad in self._checked(action, self.space, "Actions")]
        if not flags:
            return torch.zeros((), dtype=torch.bool)
        return flags[0] if len(flags) == 1 else torch.stack(flags).any()

    def raise_if_outside(self, action: Any) -> None:
        """Raise naming the envs whose action lies outside the space (reads the result back)."""
        if not bool(self.any_outside(action)):
            return
        for name, space, tensor, bad in self._checked(action, self.space, "Actions"):
            envs = bad.reshape(tensor.shape[0], -1).any(dim=1).nonzero().flatten().tolist()
            if envs:
                where = f"envs {envs[:10]}{'...' if len(envs) > 10 else ''}"
                if space is None or isinstance(space, gym.spaces.Box):
                    raise ValueError(f"{name} contain NaN or inf ({where}); actions must be finite")
                raise ValueError(f"{name} outside {space} ({where}); allowed: {_allowed(space)}")

    def _checked(self, action: Any, space: gym.spaces.Space | None, name: str):
        """(name, space, tensor, where it is outside the space) for each tensor of the action."""
        if isinstance(action, dict):
            for k, sub in action.items():
                sub_space = space[k] if isinstance(space, gym.spaces.Dict) else None
                yield from self._checked(sub, sub_space, f"{name}[{k!r}]")
        elif isinstance(action, (tuple, list)):
            for i, sub in enumerate(action):
                sub_space = space[i] if isinstance(space, gym.spaces.Tuple) else None
                yield from self._checked(sub, sub_space, f"{name}[{i}]")
        elif isinstance(action, torch.Tensor):
            if id(space) in self._ranges:
                low, high = self._ranges[id(space)]
                yield name, space, action, (action < low) | (action > high)
            elif action.is_floating_point():
                yield name, space, action, ~torch.isfinite(action)


def _leaf_spaces(space: gym.spaces.Space | None) -> list[gym.spaces.Space]:
    if isinstance(space, gym.spaces.Dict):
        return [leaf for s in space.spaces.values() for leaf in _leaf_spaces(s)]
    if isinstance(space, gym.spaces.Tuple):
        return [leaf for s in space.spaces for leaf in _leaf_spaces(s)]
    return [] if space is None else [space]


def _allowed(space: gym.spaces.Space) -> str:
    """The values a discrete space allows, in words."""
    if isinstance(space, gym.spaces.Discrete):
        return f"integers {space.start} to {space.start + space.n - 1}"
    if isinstance(space, gym.spaces.MultiDiscrete):
        starts = "" if not space.start.any() else f" + start {space.start.tolist()}"
        return f"integers 0 to nvec - 1{starts} in each entry, nvec {space.nvec.tolist()}"
    return "numbers"


# -- JSON round trip (how Isaac Lab stores spaces in env.yaml) -------------------------------------


def serialize_space(space: SpaceType) -> str:
    """A JSON string for a Gymnasium space or a Python space spec, in Isaac Lab's format.

    ``{"type": "gymnasium" | "python", "space": "Box" | ..., ...}``; the members of Tuple and Dict
    spaces are themselves serialized strings. :func:`deserialize_space` gives the space back.
    """
    if isinstance(space, gym.spaces.Discrete):
        return json.dumps({"type": "gymnasium", "space": "Discrete", "n": int(space.n), "start": int(space.start)})
    if isinstance(space, gym.spaces.Box):
        return json.dumps(
            {
                "type": "gymnasium",
                "space": "Box",
                "low": space.low.tolist(),
                "high": space.high.tolist(),
                "shape": list(space.shape),
                "dtype": str(space.dtype),
            }
        )
    if isinstance(space, gym.spaces.MultiDiscrete):
        return json.dumps(
            {
                "type": "gymnasium",
                "space": "MultiDiscrete",
                "nvec": space.nvec.tolist(),
                "start": space.start.tolist(),
                "dtype": str(space.dtype),
            }
        )
    if isinstance(space, gym.spaces.Tuple):
        return json.dumps({"type": "gymnasium", "space": "Tuple", "spaces": [serialize_space(s) for s in space.spaces]})
    if isinstance(space, gym.spaces.Dict):
        members = {k: serialize_space(v) for k, v in space.spaces.items()}
        return json.dumps({"type": "gymnasium", "space": "Dict", "spaces": members})
    if isinstance(space, gym.spaces.Space):
        raise ValueError(
            f"Cannot serialize a {type(space).__name__} space: use Box, Discrete, MultiDiscrete, Tuple, Dict"
        )
    # Python specs (see the module docstring)
    is_int = lambda x: isinstance(x, int) and not isinstance(x, bool)  # noqa: E731
    if is_int(space) or (isinstance(space, list) and space and all(is_int(x) for x in space)):
        return json.dumps({"type": "python", "space": "Box", "value": space})
    if isinstance(space, set) and len(space) == 1:
        return json.dumps({"type": "python", "space": "Discrete", "value": next(iter(space))})
    if isinstance(space, list) and space and all(isinstance(x, set) and len(x) == 1 for x in space):
        return json.dumps({"type": "python", "space": "MultiDiscrete", "value": [next(iter(x)) for x in space]})
    if isinstance(space, tuple):
        return json.dumps({"type": "python", "space": "Tuple", "value": [serialize_space(x) for x in space]})
    if isinstance(space, dict):
        return json.dumps(
            {"type": "python", "space": "Dict", "value": {k: serialize_space(v) for k, v in space.items()}}
        )
    raise ValueError(f"Cannot serialize the space spec {space!r}: {_ALLOWED}")


def deserialize_space(string: str) -> SpaceType:
    """The space (Gymnasium object or Python spec) that :func:`serialize_space` wrote."""
    try:
        obj = json.loads(string)
        kind, name = obj["type"], obj["space"]
    except (TypeError, ValueError, KeyError) as err:
        raise ValueError(f"Not a serialized space (expected JSON with 'type' and 'space'): {string!r}") from err
    if kind == "gymnasium":
        if name == "Discrete":
            return gym.spaces.Discrete(n=obj["n"], start=obj.get("start", 0))
        if name == "Box":
            dtype = np.dtype(obj.get("dtype", "float32"))
            low, high = np.array(obj["low"], dtype=dtype), np.array(obj["high"], dtype=dtype)
            return gym.spaces.Box(low=low, high=high, shape=obj["shape"], dtype=dtype)
        if name == "MultiDiscrete":
            dtype = np.dtype(obj.get("dtype", "int64"))
            start = np.array(obj.get("start", np.zeros(len(obj["nvec"]))), dtype=dtype)
            return gym.spaces.MultiDiscrete(nvec=np.array(obj["nvec"], dtype=dtype), start=start, dtype=dtype)
        if name == "Tuple":
            return gym.spaces.Tuple(tuple(deserialize_space(s) for s in obj["spaces"]))
        if name == "Dict":
            return gym.spaces.Dict({k: deserialize_space(v) for k, v in obj["spaces"].items()})
    elif kind == "python":
        value = obj["value"]
        if name == "Box":
            return value
        if name == "Discrete":
            return {value}
        if name == "MultiDiscrete":
            return [{x} for x in value]
        if name == "Tuple":
            return tuple(deserialize_space(x) for x in value)
        if name == "Dict":
            return {k: deserialize_space(v) for k, v in value.items()}
    else:
        raise ValueError(f"Unknown serialized space type {kind!r}; expected 'gymnasium' or 'python'.")
    raise ValueError(f"Unknown serialized {kind} space {name!r}; expected Box, Discrete, MultiDiscrete, Tuple or Dict.")


_SINGLE_SPACE_FIELDS = ("observation_space", "action_space", "state_space")
_SPACE_DICT_FIELDS = ("observation_spaces", "action_spaces")


def replace_env_cfg_spaces_with_strings(env_cfg: object) -> object:
    """Serialize the space fields of a direct env config in place (for writing it to yaml); returns it."""
    for attr in _SINGLE_SPACE_FIELDS:
        if getattr(env_cfg, attr, None) is not None:
            setattr(env_cfg, attr, serialize_space(getattr(env_cfg, attr)))
    for attr in _SPACE_DICT_FIELDS:
        if getattr(env_cfg, attr, None) is not None:
            setattr(env_cfg, attr, {k: serialize_space(v) for k, v in getattr(env_cfg, attr).items()})
    return env_cfg


def replace_strings_with_env_cfg_spaces(env_cfg: object) -> object:
    """Undo :func:`replace_env_cfg_spaces_with_strings` in place; returns the config."""
    for attr in _SINGLE_SPACE_FIELDS:
        if isinstance(getattr(env_cfg, attr, None), str):
            setattr(env_cfg, attr, deserialize_space(getattr(env_cfg, attr)))
    for attr in _SPACE_DICT_FIELDS:
        if isinstance(getattr(env_cfg, attr, None), dict):
            # entries that were never serialized (not strings) are kept as they are
            spaces = getattr(env_cfg, attr).items()
            setattr(env_cfg, attr, {k: deserialize_space(v) if isinstance(v, str) else v for k, v in spaces})
    return env_cfg
