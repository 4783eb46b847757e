"""skrl PPO for each showcase space pair: the direct cartpoles' PPO settings (Isaac Lab's showcase
uses the same as its cartpole and camera cartpole) with the models that fit the spaces, as Isaac Lab's
``skrl_<observation>_<action>_ppo_cfg.yaml`` files have them:

- actions: Box -> a Gaussian policy, Discrete -> categorical, MultiDiscrete -> multi-categorical;
- observations: Box -> an MLP (32, 32), Discrete / MultiDiscrete -> the same on their one-hot
  encoding (no running normalization of integers), Dict / Tuple -> an MLP (16, 16) per part, the
  two summed (Dict) or multiplied (Tuple);
- camera observations: a CNN over the image, alone (Box) or with the joint velocities (Dict, Tuple).

An entry point ``...skrl_ppo_cfg:box_discrete`` returns a fresh dict each time it is called.
"""

from __future__ import annotations

import copy
import os
from functools import partial
from typing import Any

import yaml

from simlab.tasks.direct.cartpole import agents as direct_agents

_DIRECT_AGENTS = os.path.dirname(direct_agents.__file__)

_POLICY = {
    "box": {
        "class": "GaussianMixin",
        "clip_actions": False,
        "clip_log_std": True,
        "min_log_std": -20.0,
        "max_log_std": 2.0,
        "initial_log_std": 0.0,
    },
    "discrete": {"class": "CategoricalMixin", "unnormalized_log_prob": True},
    "multidiscrete": {"class": "MultiCategoricalMixin", "unnormalized_log_prob": True},
}


def _mlp(name: str, source: str, layers: list[int]) -> dict:
    return {"name": name, "input": source, "layers": layers, "activations": "elu"}


def _state_network(observation: str) -> list[dict]:
    if observation == "box":
        return [_mlp("net", "OBSERVATIONS", [32, 32])]
    if observation in ("discrete", "multidiscrete"):
        return [_mlp("net", "one_hot_encoding(OBSERVATION_SPACE, OBSERVATIONS)", [32, 32])]
    keys = ('["joint-positions"]', '["joint-velocities"]') if observation == "dict" else ("[0]", "[1]")
    merge = "net_pos + net_vel" if observation == "dict" else "net_pos * net_vel"
    return [
        _mlp("net_pos", f"OBSERVATIONS{keys[0]}", [16, 16]),
        _mlp("net_vel", f"OBSERVATIONS{keys[1]}", [16, 16]),
        {"name": "net", "input": merge, "layers": [], "activations": []},
    ]


_CONVS = [
    {"conv2d": {"out_channels": 32, "kernel_size": 8, "stride": 4, "padding": 0}},
    {"conv2d": {"out_channels": 64, "kernel_size": 4, "stride": 2, "padding": 0}},
    {"conv2d": {"out_channels": 64, "kernel_size": 3, "stride": 1, "padding": 0}},
    "flatten",
]


def _camera_network(observation: str) -> list[dict]:
    if observation == "box":  # the image alone: the direct camera cartpole's CNN
        image = "permute(OBSERVATIONS, (0, 3, 1, 2))"  # (N, H, W, C) images -> torch's (N, C, H, W)
        return [
            {"name": "features_extractor", "input": image, "layers": _CONVS, "activations": "relu"},
            _mlp("net", "features_extractor", [512]),
        ]
    # the image squeezed to 16 features, beside the joint velocities (Dict) or their 8 features (Tuple)
    image, velocities = ('["camera"]', '["joint-velocities"]') if observation == "dict" else ("[0]", "[1]")
    layers = [*_CONVS, {"linear": 512}, {"linear": 16}]
    extractor = {
        "name": "features_extractor",
        "input": f"permute(OBSERVATIONS{image}, (0, 3, 1, 2))",
        "layers": layers,
        "activations": ["relu", "relu", "relu", None, "tanh", "tanh"],
    }
    if observation == "dict":
        return [extractor, _mlp("net", f"concatenate([features_extractor, OBSERVATIONS{velocities}])", [32, 32])]
    return [
        extractor,
        _mlp("proprioception", f"OBSERVATIONS{velocities}", [16, 8]),
        _mlp("net", "concatenate([features_extractor, proprioception])", [32, 32]),
    ]


def skrl_cfg(observation: str, action: str, camera: bool = False) -> dict[str, Any]:
    """The skrl config of the showcase task with these spaces (lower-case names, e.g. "dict", "discrete")."""
    base = "skrl_camera_ppo_cfg.yaml" if camera else "skrl_ppo_cfg.yaml"
    with open(os.path.join(_DIRECT_AGENTS, base)) as f:
        cfg = yaml.safe_load(f)
    network = _camera_network(observation) if camera else _state_network(observation)
    cfg["models"]["policy"] = {**copy.deepcopy(_POLICY[action]), "network": network, "output": "ACTIONS"}
    value = {"class": "DeterministicMixin", "clip_actions": False, "network": copy.deepcopy(network), "output": "ONE"}
    cfg["models"]["value"] = value
    if observation in ("discrete", "multidiscrete"):
        cfg["agent"]["observation_preprocessor"] = None  # integers are one-hot encoded, not normalized
    task = "cartpole_camera_direct" if camera else "cartpole_direct"
    cfg["agent"]["experiment"]["directory"] = f"{task}_{observation}_{action}"
    return cfg


box_box = partial(skrl_cfg, "box", "box")
box_discrete = partial(skrl_cfg, "box", "discrete")
box_multidiscrete = partial(skrl_cfg, "box", "multidiscrete")
discrete_box = partial(skrl_cfg, "discrete", "box")
discrete_discrete = partial(skrl_cfg, "discrete", "discrete")
discrete_multidiscrete = partial(skrl_cfg, "discrete", "multidiscrete")
multidiscrete_box = partial(skrl_cfg, "multidiscrete", "box")
multidiscrete_discrete = partial(skrl_cfg, "multidiscrete", "discrete")
multidiscrete_multidiscrete = partial(skrl_cfg, "multidiscrete", "multidiscrete")
dict_box = partial(skrl_cfg, "dict", "box")
dict_discrete = partial(skrl_cfg, "dict", "discrete")
dict_multidiscrete = partial(skrl_cfg, "dict", "multidiscrete")
tuple_box = partial(skrl_cfg, "tuple", "box")
tuple_discrete = partial(skrl_cfg, "tuple", "discrete")
tuple_multidiscrete = partial(skrl_cfg, "tuple", "multidiscrete")

camera_box_box = partial(skrl_cfg, "box", "box", camera=True)
camera_box_discrete = partial(skrl_cfg, "box", "discrete", camera=True)
camera_box_multidiscrete = partial(skrl_cfg, "box", "multidiscrete", camera=True)
camera_dict_box = partial(skrl_cfg, "dict", "box", camera=True)
camera_dict_discrete = partial(skrl_cfg, "dict", "discrete", camera=True)
camera_dict_multidiscrete = partial(skrl_cfg, "dict", "multidiscrete", camera=True)
camera_tuple_box = partial(skrl_cfg, "tuple", "box", camera=True)
camera_tuple_discrete = partial(skrl_cfg, "tuple", "discrete", camera=True)
camera_tuple_multidiscrete = partial(skrl_cfg, "tuple", "multidiscrete", camera=True)
