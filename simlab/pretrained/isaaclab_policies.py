"""Isaac Lab's pre-trained policies on its Nucleus server, as the shipped simlab policies that stand for them.

Isaac Lab's navigation task and its quadruped tutorial read a locomotion policy from
``ISAACLAB_NUCLEUS_DIR/Policies/...`` as TorchScript (``read_file`` and ``torch.jit.load``). simlab cannot
reach Nucleus; for each path in :data:`ISAACLAB_POLICIES` it ships a policy trained with the same
observations and actions, and ``simlab.utils.assets.read_file`` of the path gives TorchScript scripted in
this process from that policy's weights (:func:`torchscript_policy`): no code is read from a file.

The policy's network is rebuilt from its weights alone (:class:`MLPPolicy`): the linear layers from their
shapes, an activation between them, rsl_rl's observation normalizer when the weights hold one.
"""

from __future__ import annotations

import functools
import io
import os

import torch
from torch import nn

from simlab.utils.errors import ConfigError

from . import POLICY_FILE, pretrained_run_dir
from .weights import unpack_policy

ISAACLAB_POLICIES: dict[str, tuple[str, str]] = {
    "Policies/ANYmal-C/Blind/policy.pt": ("simlab/Velocity-Flat-Anymal-C-v0", "rsl_rl"),
    "Policies/ANYmal-C/HeightScan/policy.pt": ("simlab/Velocity-Rough-Anymal-C-v0", "rsl_rl"),
}
"""Isaac Lab's pre-trained locomotion policies (their path under ``ISAACLAB_NUCLEUS_DIR``) and the shipped
simlab policy (task, library) that stands for each: the blind one (48 observations) is the flat-ground
ANYmal-C policy, the height-scan one (48 + 187 scanned heights) the rough-terrain one."""

ACTIVATIONS = {"elu": nn.ELU, "relu": nn.ReLU, "tanh": nn.Tanh, "selu": nn.SELU, "lrelu": nn.LeakyReLU}


def isaaclab_policy(path: str) -> str | None:
    """The key of :data:`ISAACLAB_POLICIES` that a Nucleus ``path`` (any server, any Isaac Sim version) names."""
    return next((key for key in ISAACLAB_POLICIES if str(path).endswith("/IsaacLab/" + key)), None)


def shipped_policy_file(isaac_path: str) -> str:
    """The shipped ``policy.pt`` that stands for ``isaac_path`` (a key of :data:`ISAACLAB_POLICIES`)."""
    task, library = ISAACLAB_POLICIES[isaac_path]
    return os.path.join(pretrained_run_dir(task, library), POLICY_FILE)


@functools.cache
def torchscript_policy(isaac_path: str) -> bytes:
    """The TorchScript file Isaac Lab's code reads (``torch.jit.load``) for ``isaac_path`` (a key of
    :data:`ISAACLAB_POLICIES`): the shipped weights that stand for it, as :class:`MLPPolicy`, scripted here."""
    what = f"simlab's policy for Isaac Lab's {isaac_path}"
    state = actor_state(unpack_policy(shipped_policy_file(isaac_path))[1], what)
    policy = MLPPolicy(state, "elu", what).eval().requires_grad_(False)  # frozen: its actions take no gradient
    buffer = io.BytesIO()
    torch.jit.save(torch.jit.script(policy), buffer)
    return buffer.getvalue()


def actor_state(loaded: object, what: str) -> dict[str, torch.Tensor]:
    """The actor's weights of a loaded file: a stored simlab policy, an rsl_rl checkpoint or a state dict."""
    if isinstance(loaded, dict) and "actor_state_dict" in loaded:  # rsl_rl >= 3 checkpoint
        loaded = loaded["actor_state_dict"]
    elif isinstance(loaded, dict) and "model_state_dict" in loaded:  # rsl_rl 2.x: actor.* keys of the model
        model = loaded["model_state_dict"]
        loaded = {k[len("actor.") :]: v for k, v in model.items() if k.startswith("actor.")}
        loaded.update({k: v for k, v in model.items() if k.startswith("actor_obs_normalizer.")})
    if not isinstance(loaded, dict) or not all(isinstance(v, torch.Tensor) for v in loaded.values()):
        raise ConfigError(f"{what} holds a {type(loaded).__name__}, not the weights of a policy.")
    return loaded


class MLPPolicy(nn.Module):
    """``obs -> action``: an optional observation normalizer (rsl_rl's ``(obs - mean) / (std + 0.01)``)
    and linear layers with ``activation`` between them; the layers come from the weights' shapes."""

    def __init__(self, state: dict[str, torch.Tensor], activation: str, what: str):
        super().__init__()
        if activation not in ACTIVATIONS:
            raise ConfigError(f"policy_activation '{activation}' is unknown; one of {sorted(ACTIVATIONS)}.")
        # the linear layers: '<prefix><index>.weight' with 2-d weights, in index order
        weights = {k[: -len(".weight")]: v for k, v in state.items() if k.endswith(".weight") and v.dim() == 2}
        names = sorted(weights, key=lambda k: int(k.rsplit(".", 1)[-1]) if k.rsplit(".", 1)[-1].isdigit() else -1)
        if not names or any(not n.rsplit(".", 1)[-1].isdigit() for n in names):
            raise ConfigError(f"{what} has no MLP weights (keys like 'mlp.0.weight'); found {sorted(state)[:6]}.")
        layers: list[nn.Module] = []
        for i, name in enumerate(names):
            if i:
                layers.append(ACTIVATIONS[activation]())
            out_dim, in_dim = weights[name].shape
            linear = nn.Linear(in_dim, out_dim)
            linear.weight.data.copy_(weights[name])
            linear.bias.data.copy_(state.get(f"{name}.bias", torch.zeros(out_dim)))
            layers.append(linear)
        self.mlp = nn.Sequential(*layers)
        mean = next((v for k, v in state.items() if k.endswith("normalizer._mean")), None)
        std = next((v for k, v in state.items() if k.endswith("normalizer._std")), None)
        self.register_buffer("obs_mean", mean.reshape(1, -1) if mean is not None else None)
        self.register_buffer("obs_scale", 1.0 / (std.reshape(1, -1) + 0.01) if std is not None else None)

    @property
    def obs_dim(self) -> int:
        return self.mlp[0].in_features

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        if self.obs_mean is not None:
            obs = (obs - self.obs_mean) * self.obs_scale
        return self.mlp(obs)
