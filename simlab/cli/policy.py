"""A trained policy in a library-independent form: plain ``nn.Module`` actors, exported as they run.

Each library adapter turns its checkpoint into one ``obs -> actions`` module per agent (observation
normalization and action clipping included) plus a function that picks and flattens the module's
input from the env's observation dict. ``play`` steps the env with exactly these modules, and
:meth:`Policy.export` writes the same modules to TorchScript and ONNX.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field

import torch
import torch.nn as nn

from simlab.rl.exporter import export_policy_as_jit, export_policy_as_onnx

__all__ = ["ClampActions", "Policy"]


class ClampActions(nn.Module):
    """``clamp(policy(obs), low, high)``: the action bounds a library applies before stepping."""

    def __init__(self, policy: nn.Module, low: float, high: float):
        super().__init__()
        self.policy = policy
        self.low, self.high = float(low), float(high)

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        return torch.clamp(self.policy(obs), self.low, self.high)


@dataclass
class Policy:
    """Deterministic actors of a trained agent.

    Attributes:
        modules: ``{"policy": module}`` for one agent, ``{agent: module}`` for multi-agent policies.
        inputs: maps the env's observation (dict of groups or of agents) to each module's flat input.
        obs_dims: each module's input size, or an image input's (H, W, C) (for export).
        device: where the modules run.
        obs_groups: the env's observation groups a single-agent module reads, concatenated in this order.
    """

    modules: dict[str, nn.Module]
    inputs: Callable[[dict], dict[str, torch.Tensor]]
    obs_dims: dict[str, int | tuple[int, ...]]
    device: str = "cpu"
    not_exportable: str | None = None
    """Why the modules cannot be exported (None: they can)."""
    obs_groups: list[str] = field(default_factory=lambda: ["policy"])

    def __post_init__(self):
        for m in self.modules.values():
            m.to(self.device).eval()

    @property
    def multi_agent(self) -> bool:
        return list(self.modules) != ["policy"]

    @torch.inference_mode()
    def __call__(self, obs: dict) -> torch.Tensor | dict[str, torch.Tensor]:
        x = self.inputs(obs)
        actions = {k: m(x[k].to(self.device, torch.float32)) for k, m in self.modules.items()}
        return actions if self.multi_agent else actions["policy"]

    def export(self, folder: str, metadata: dict[str, str] | None = None) -> list[str]:
        """Write ``policy.pt`` (TorchScript) and ``policy.onnx`` (``policy_<agent>.*`` per agent); the
        ONNX files carry ``metadata`` (the deploy metadata, see :mod:`simlab.rl.deploy_metadata`)."""
        if self.not_exportable:
            raise NotImplementedError(self.not_exportable)
        files = []
        for name, module in self.modules.items():
            stem = "policy" if name == "policy" else f"policy_{name}"
            cpu = module.to("cpu")
            files.append(export_policy_as_jit(cpu, folder, f"{stem}.pt", obs_dim=self.obs_dims[name]))
            files.append(export_policy_as_onnx(cpu, folder, self.obs_dims[name], f"{stem}.onnx", metadata=metadata))
            module.to(self.device)
        return [os.path.abspath(f) for f in files]
