"""Export rsl_rl policies to TorchScript and ONNX (Isaac Lab's ``export_policy_as_jit/onnx`` signatures)."""

from __future__ import annotations

import torch.nn as nn

from simlab.rl import exporter

__all__ = ["export_policy_as_jit", "export_policy_as_onnx", "policy_module"]


def policy_module(policy: nn.Module) -> tuple[nn.Module, int | None]:
    """A deterministic obs -> actions module for an rsl_rl model (its own export form), and its input size."""
    if hasattr(policy, "as_jit"):  # rsl_rl MLPModel: normalizer + MLP + distribution mean
        return policy.as_jit(), getattr(policy, "obs_dim", None)
    return policy, None


def export_policy_as_jit(
    policy: nn.Module, normalizer: nn.Module | None, path: str, filename: str = "policy.pt"
) -> str:
    """Write the actor ``policy`` (an rsl_rl model or any obs -> actions module) as TorchScript."""
    module, obs_dim = policy_module(policy)
    return exporter.export_policy_as_jit(module, path, filename, normalizer=normalizer, obs_dim=obs_dim)


def export_policy_as_onnx(
    policy: nn.Module,
    path: str,
    normalizer: nn.Module | None = None,
    filename: str = "policy.onnx",
    verbose: bool = False,
    obs_dim: int | None = None,
    metadata: dict[str, str] | None = None,
) -> str:
    """Write the actor ``policy`` as ONNX (input ``obs``, output ``actions``, dynamic batch), with
    optional ``metadata`` (:func:`simlab.rl.deploy_metadata.deploy_metadata`)."""
    module, dim = policy_module(policy)
    dim = dim or obs_dim
    if dim is None:
        raise ValueError("export_policy_as_onnx: pass obs_dim, the size of the policy's input.")
    return exporter.export_policy_as_onnx(
        module, path, dim, filename, normalizer=normalizer, verbose=verbose, metadata=metadata
    )
