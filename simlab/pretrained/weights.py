"""The one file a shipped policy is stored as: ``policy.pt``, the weights play loads and nothing else.

A shipped policy is played, never trained on, so its file keeps only what the library's loader
reads for play (rsl_rl's ``actor_state_dict``; skrl's ``policy`` and its observation normalizer),
with its weight matrices stored smaller than float32, in one of two forms (``MATRICES``):

- ``int8_rows``: int8 with one float32 scale per row (symmetric, the row's largest magnitude maps
  to 127), a quarter of float32's bytes;
- ``float16``: half of float32's bytes, for policies whose task needs finer actions (measured on
  the Franka reach with IK-Abs: float32 0.982 of its tolerance, float16 0.982, int8 rows 1.13, a
  failure).

``scripts/make_pretrained.py`` ships the first form whose replay still meets the task's criterion.
Vectors (biases, action noise, normalizer statistics) stay float32. The stored file holds only
tensors, dicts, numbers and strings, so ``torch.load(weights_only=True)`` reads it.

:func:`unpack_policy` turns it back into the library's own checkpoint (float32), which play writes
into the user's log folder and loads as any checkpoint; exports (ONNX, TorchScript) are made there.
"""

from __future__ import annotations

from typing import Any

import torch

__all__ = ["FORMAT", "MATRICES", "PLAY_KEYS", "pack_policy", "unpack_policy"]

FORMAT = "simlab-policy-1"
MATRICES = ("int8_rows", "float16")  # smallest first
# what play loads of a library's checkpoint (the critic, value and discriminator and the optimizers'
# moments are left out): rsl_rl's load_cfg={"actor": True}; skrl's policy and its observation normalizer
PLAY_KEYS = {
    "rsl_rl": ("actor_state_dict", "iter", "infos"),
    "skrl": ("policy", "observation_preprocessor"),
}
# a packed matrix is {"__packed__": <one of MATRICES>, "values": ..., ("scale": per-row float32)}


def _pack(value: Any, matrices: str) -> Any:
    if isinstance(value, dict):
        return {key: _pack(item, matrices) for key, item in value.items()}
    if torch.is_tensor(value) and value.is_floating_point() and value.dim() >= 2:
        matrix = value.detach().float().cpu()
        if matrices == "float16":
            return {"__packed__": matrices, "values": matrix.half()}
        rows = matrix.reshape(value.shape[0], -1)
        scale = rows.abs().amax(dim=1, keepdim=True) / 127.0
        scale = torch.where(scale > 0, scale, torch.ones_like(scale))  # a zero row stays zero
        values = torch.round(rows / scale).clamp(-127, 127).to(torch.int8).reshape(value.shape)
        return {"__packed__": matrices, "values": values, "scale": scale.reshape(-1)}
    if torch.is_tensor(value):
        return value.detach().cpu().clone()  # clone: a view would save its whole storage
    return value


def _unpack(value: Any) -> Any:
    if isinstance(value, dict) and value.get("__packed__") == "float16":
        return value["values"].float()
    if isinstance(value, dict) and value.get("__packed__") == "int8_rows":
        values = value["values"]
        scale = value["scale"].reshape(-1, *([1] * (values.dim() - 1)))
        return values.float() * scale
    if isinstance(value, dict):
        return {key: _unpack(item) for key, item in value.items()}
    return value


def pack_policy(checkpoint: dict[str, Any], library: str, name: str, matrices: str = MATRICES[0]) -> dict[str, Any]:
    """The stored form of a ``library`` checkpoint: what play loads of it, its matrices as ``matrices``
    (one of :data:`MATRICES`), and ``name``, the checkpoint's path in its run folder (``model_149.pt``,
    ``checkpoints/agent_1.pt``)."""
    if matrices not in MATRICES:
        raise ValueError(f"Unknown matrix form {matrices!r}; one of {list(MATRICES)}.")
    if library not in PLAY_KEYS:
        raise ValueError(f"Cannot store a {library} policy; the libraries with stored policies: {sorted(PLAY_KEYS)}.")
    keys = PLAY_KEYS[library]
    missing = [key for key in keys if key not in checkpoint]
    if missing:
        raise KeyError(f"The checkpoint has no {missing} (it has {sorted(checkpoint)}); play needs {list(keys)}.")
    state = {key: _pack(checkpoint[key], matrices) for key in keys}
    return {"format": FORMAT, "matrices": matrices, "checkpoint": name, "state": state}


def unpack_policy(path: str) -> tuple[str, dict[str, Any]]:
    """Read a stored ``policy.pt``: the checkpoint's path in its run folder and the library checkpoint
    (float32 weights) to write there."""
    stored = torch.load(path, map_location="cpu", weights_only=True)
    if not isinstance(stored, dict) or stored.get("format") != FORMAT:
        found = stored.get("format") if isinstance(stored, dict) else type(stored).__name__
        raise ValueError(f"'{path}' is not a stored simlab policy (format {found!r}; expected {FORMAT!r}).")
    return stored["checkpoint"], _unpack(stored["state"])
