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
