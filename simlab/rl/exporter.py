"""Export a policy network (observations -> actions) to TorchScript and ONNX.

Every library's trained actor is first turned into a plain ``nn.Module`` mapping a batch of
flat observations ``(N, obs_dim)`` to deterministic actions ``(N, action_dim)`` (normalization
included); these functions then write it out. Both files take the input named ``obs`` with a
dynamic batch dimension and give ``actions``.
"""

from __future__ import annotations

import contextlib
import copy
import io
import logging
import os
import warnings

import torch
import torch.nn as nn

from simlab.utils.io import atomic_path

__all__ = ["export_policy_as_jit", "export_policy_as_onnx", "PolicyWithNormalizer"]


class PolicyWithNormalizer(nn.Module):
    """``policy(normalizer(obs))``: one module to export, normalization baked in."""

    def __init__(self, policy: nn.Module, normalizer: nn.Module | None = None):
        super().__init__()
        self.normalizer = copy.deepcopy(normalizer) if normalizer is not None else nn.Identity()
        self.policy = copy.deepcopy(policy)

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        return self.policy(self.normalizer(obs))


def _prepare(policy: nn.Module, normalizer: nn.Module | None) -> nn.Module:
    module = PolicyWithNormalizer(policy, normalizer) if normalizer is not None else copy.deepcopy(policy)
    return module.to("cpu").eval()


def export_policy_as_jit(
    policy: nn.Module,
    path: str,
    filename: str = "policy.pt",
    normalizer: nn.Module | None = None,
    obs_dim: int | tuple[int, ...] | None = None,
) -> str:
    """Write ``policy`` (with an optional observation ``normalizer``) as TorchScript; return the file path.

    The module is scripted; if it cannot be scripted (library models often use Python-only code),
    it is traced with a zero observation of size ``obs_dim``.
    """
    module = _prepare(policy, normalizer)
    os.makedirs(path, exist_ok=True)
    file = os.path.join(path, filename)
    try:
        with warnings.catch_warnings():  # TorchScript is deprecated in torch 2.10+, yet still the deployable format
            warnings.simplefilter("ignore", DeprecationWarning)
            scripted = torch.jit.script(module)
    except Exception as e:  # noqa: BLE001 - any scripting failure falls back to tracing
        if obs_dim is None:
            raise RuntimeError(f"Cannot script {type(policy).__name__} ({e}); pass obs_dim to trace it.") from e
        with torch.no_grad(), warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            scripted = torch.jit.trace(module, torch.zeros(1, *_shape(obs_dim)), check_trace=False)
    with atomic_path(file) as tmp:  # a crash mid-write keeps the previous export
        scripted.save(tmp)
    return file


def export_policy_as_onnx(
    policy: nn.Module,
    path: str,
    obs_dim: int | tuple[int, ...],
    filename: str = "policy.onnx",
    normalizer: nn.Module | None = None,
    verbose: bool = False,
    metadata: dict[str, str] | None = None,
) -> str:
    """Write ``policy`` (with an optional ``normalizer``) as ONNX (opset 18, dynamic batch); return the path.

    ``metadata`` (``{key: string}``, e.g. :func:`simlab.rl.deploy_metadata.deploy_metadata`) is
    stored as the model's ``metadata_props``.
    """
    module = _prepare(policy, normalizer)
    os.makedirs(path, exist_ok=True)
    file = os.path.join(path, filename)
    batch = torch.export.Dim("batch", min=1)
    # the exporter reports each stage on stdout; keep the console for training output
    sink = contextlib.nullcontext() if verbose else contextlib.redirect_stdout(io.StringIO())
    onnx_log = logging.getLogger("torch.onnx")
    level = onnx_log.level
    if not verbose:
        onnx_log.setLevel(logging.ERROR)  # e.g. "torchvision is not installed" notes
    with sink, torch.no_grad(), warnings.catch_warnings(), atomic_path(file, suffix=".onnx") as tmp:
        if not verbose:
            warnings.simplefilter("ignore", FutureWarning)
            # skrl's shared models keep their last output on self for the value call: the export keeps
            # the computation, and torch's note on the attribute only worried users of every skrl play
            warnings.filterwarnings("ignore", "The tensor attribute .* was assigned during export", UserWarning)
        torch.onnx.export(
            module,
            (torch.zeros(2, *_shape(obs_dim)),),
            tmp,
            input_names=["obs"],
            output_names=["actions"],
            dynamic_shapes=({0: batch},),
            opset_version=18,
            external_data=False,
            verbose=verbose,
        )
        if metadata:
            _set_metadata(tmp, metadata)
    onnx_log.setLevel(level)
    return file


def _set_metadata(file: str, metadata: dict[str, str]) -> None:
    import onnx

    model = onnx.load(file)
    onnx.helper.set_model_props(model, {str(k): str(v) for k, v in metadata.items()})
    onnx.save(model, file)


def _shape(obs_dim: int | tuple[int, ...]) -> tuple[int, ...]:
    """One observation's shape: a flat size, or an image's (H, W, C)."""
    return (obs_dim,) if isinstance(obs_dim, int) else tuple(obs_dim)
