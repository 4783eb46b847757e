"""The one file a shipped policy is stored as: ``policy.pt``, the weights play loads and nothing else.

A shipped policy is played, never trained on, so its file keeps only what the library's loader
reads for play (rsl_rl's ``actor_state_dict``, a distilled student's ``student_state_dict``; skrl's
``policy`` and its observation normalizer;
Stable-Baselines3's policy network, its settings and its VecNormalize statistics; a behaviour-cloned
policy's weights and the sizes that rebuild it, :mod:`simlab.rl.bc`; rl_games' ``model``, the
value network included: play loads it whole), with its weight
matrices stored smaller than float32, in one of two forms (``MATRICES``):

- ``int8_rows``: int8 with one float32 scale per row (symmetric, the row's largest magnitude maps
  to 127), a quarter of float32's bytes;
- ``float16``: half of float32's bytes, for a policy whose int8 replay misses its criterion.

``scripts/make_pretrained.py`` ships the first form whose replay still meets the task's criterion,
written by :func:`save_policy` (its zip entries deflated).
Vectors (biases, action noise, normalizer statistics) stay float32, rsl_rl's ``(1, N)`` normalizer
statistics too: one int8 scale across features of unlike magnitudes rounds the small ones to 0 (the
Franka reach with IK-Abs replayed at 1.10 of its tolerance so, a failure; with them float32 and the
weights int8 rows, 0.98, as float16). The stored file holds only tensors, dicts, numbers and strings,
so ``torch.load(weights_only=True)`` reads it.

:func:`unpack_policy` turns it back into the library's own checkpoint (float32), which play writes
into the user's log folder and loads as any checkpoint; exports (ONNX, TorchScript) are made there.
:func:`read_checkpoint` and :func:`write_checkpoint` turn a library's checkpoint file into such a dict
and back: a torch file for rsl_rl, skrl, rl_games and bc; for SB3 its ``.zip`` and the ``.npz`` statistics beside it.

SB3's zip keeps its settings as JSON, with its spaces, schedules and policy class pickled in it. The
stored form keeps the JSON settings, the spaces' pickles (read back by simlab's restricted unpickler,
which knows only gymnasium's spaces and numpy) and of the other pickled items their names only: play
takes them from the task's config (:mod:`simlab.cli.libraries.sb3`), so no pickled code is shipped.
"""

from __future__ import annotations

import io
import json
import os
import re
import zipfile
from typing import Any

import numpy as np
import torch

__all__ = [
    "FORMAT", "MATRICES", "PLAY_KEYS", "pack_policy", "read_checkpoint", "save_policy", "unpack_policy",
    "write_checkpoint",
]  # fmt: skip

FORMAT = "simlab-policy-1"
MATRICES = ("int8_rows", "float16")  # smallest first
# what play loads of a library's checkpoint (the critic, value and discriminator and the optimizers'
# moments are left out): rsl_rl's load_cfg={"actor": True}; skrl's policy and its observation normalizer
PLAY_KEYS = {
    "rsl_rl": ("actor_state_dict", "iter", "infos"),
    "skrl": ("policy", "observation_preprocessor"),
    # SB3's policy (PPO.load needs its value head too) and the optimizer's settings (no moments)
    "sb3": ("policy", "policy.optimizer", "data", "vecnormalize", "version"),
    # a behaviour-cloned policy (simlab.rl.bc): its weights and what rebuilds the network
    "bc": ("state_dict", "terms", "relative", "hidden", "sizes", "task", "epochs"),
    # rl_games' model (actor, value network, their normalizers: its player loads it whole) and the epochs done
    "rl_games": ("model", "epoch"),
}
# items of SB3's data that the training rebuilds (the last observations, episode buffers): not kept
_SB3_REBUILT = ("_last_obs", "_last_episode_starts", "_last_original_obs", "ep_info_buffer", "ep_success_buffer")
_SB3_SPACES = ("observation_space", "action_space")
# kept when the checkpoint has them: skrl writes its normalizer only when the agent config sets one; a
# BC file written before bc.py saved its epochs has none
OPTIONAL_KEYS = ("observation_preprocessor", "epochs")
# a packed matrix is {"__packed__": <one of MATRICES>, "values": ..., ("scale": per-row float32)}


def _is_matrix(value: Any) -> bool:
    """A float tensor with two or more dimensions longer than 1: a (1, N) row is a vector."""
    return torch.is_tensor(value) and value.is_floating_point() and sum(size > 1 for size in value.shape) >= 2


def _pack(value: Any, matrices: str) -> Any:
    if isinstance(value, dict):
        return {key: _pack(item, matrices) for key, item in value.items()}
    if _is_matrix(value):
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
    if library == "rsl_rl" and "student_state_dict" in checkpoint:  # a distilled student: play loads it alone
        keys = ("student_state_dict", *keys[1:])
    if library == "skrl" and _per_agent(checkpoint):  # IPPO / MAPPO: each agent's policy under its name
        state = {agent: _play_state(part, keys, matrices) for agent, part in checkpoint.items()}
    else:
        state = _play_state(checkpoint, keys, matrices)
    return {"format": FORMAT, "matrices": matrices, "checkpoint": name, "state": state}


def _per_agent(checkpoint: dict[str, Any]) -> bool:
    """skrl's multi-agent checkpoints hold one checkpoint per agent, keyed by the agent's name."""
    return (
        "policy" not in checkpoint
        and bool(checkpoint)
        and all(isinstance(part, dict) and "policy" in part for part in checkpoint.values())
    )


def _play_state(checkpoint: dict[str, Any], keys: tuple[str, ...], matrices: str) -> dict[str, Any]:
    missing = [key for key in keys if key not in checkpoint and key not in OPTIONAL_KEYS]
    if missing:
        raise KeyError(f"The checkpoint has no {missing} (it has {sorted(checkpoint)}); play needs {list(keys)}.")
    return {key: _pack(checkpoint[key], matrices) for key in keys if key in checkpoint}


def save_policy(stored: dict[str, Any], path: str) -> None:
    """Write ``stored`` (:func:`pack_policy`'s form) as ``torch.save`` does, its archive's entries
    deflate-compressed (level 9): about a tenth smaller for int8 weights, more for float16 ones.
    ``torch.load`` reads it as it is (not with ``mmap=True``, which needs stored entries); the
    entries and their order are torch's."""
    saved = io.BytesIO()
    torch.save(stored, saved)
    with zipfile.ZipFile(saved) as source, zipfile.ZipFile(path, "w") as target:
        for entry in source.infolist():
            # a fresh entry (fixed 1980 date): the same weights give the same bytes
            target.writestr(zipfile.ZipInfo(entry.filename), source.read(entry), zipfile.ZIP_DEFLATED, 9)


def unpack_policy(path: str) -> tuple[str, dict[str, Any]]:
    """Read a stored ``policy.pt``: the checkpoint's path in its run folder and the library checkpoint
    (float32 weights) to write there."""
    stored = torch.load(path, map_location="cpu", weights_only=True)
    if not isinstance(stored, dict) or stored.get("format") != FORMAT:
        found = stored.get("format") if isinstance(stored, dict) else type(stored).__name__
        raise ValueError(f"'{path}' is not a stored simlab policy (format {found!r}; expected {FORMAT!r}).")
    return stored["checkpoint"], _unpack(stored["state"])


def _sb3_statistics_path(checkpoint: str) -> str:
    # the name simlab's SB3 adapter gives VecNormalize's statistics (simlab.cli.libraries.sb3)
    folder, name = os.path.split(checkpoint)
    steps = re.match(r"model_(\d+)_steps\.zip$", name)
    return os.path.join(folder, f"model_vecnormalize_{steps.group(1)}_steps.npz" if steps else "model_vecnormalize.npz")


def _sb3_data(data: dict[str, Any]) -> dict[str, Any]:
    """SB3's settings less the rebuilt buffers, the spaces' pickles kept, other pickles' payloads dropped."""
    kept = {}
    for key, item in data.items():
        if key in _SB3_REBUILT:
            continue
        if isinstance(item, dict) and ":serialized:" in item and key not in _SB3_SPACES:
            item = {**item, ":serialized:": ""}  # play replaces it from the task's config
        kept[key] = item
    return kept


def _read_sb3(path: str) -> dict[str, Any]:
    def load(name: str) -> Any:
        return torch.load(io.BytesIO(archive.read(name)), map_location="cpu", weights_only=True)

    with zipfile.ZipFile(path) as archive:
        data = json.loads(archive.read("data"))
        policy, optimizer = load("policy.pth"), load("policy.optimizer.pth")
        version = archive.read("_stable_baselines3_version").decode()
    statistics: dict[str, Any] = {}
    if os.path.isfile(_sb3_statistics_path(path)):
        with np.load(_sb3_statistics_path(path), allow_pickle=False) as arrays:
            statistics = {key: torch.from_numpy(arrays[key]) for key in arrays.files}
    return {
        "policy": policy,
        "policy.optimizer": {"state": {}, "param_groups": optimizer["param_groups"]},
        "data": _sb3_data(data),
        "vecnormalize": statistics,
        "version": version,
    }


def _write_sb3(checkpoint: dict[str, Any], path: str) -> None:
    def tensor_file(value: Any) -> bytes:
        buffer = io.BytesIO()
        torch.save(value, buffer)
        return buffer.getvalue()

    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("data", json.dumps(checkpoint["data"], indent=4))
        archive.writestr("policy.pth", tensor_file(checkpoint["policy"]))
        archive.writestr("policy.optimizer.pth", tensor_file(checkpoint["policy.optimizer"]))
        archive.writestr("pytorch_variables.pth", tensor_file({}))
        archive.writestr("_stable_baselines3_version", checkpoint["version"])
    if checkpoint["vecnormalize"]:
        with open(_sb3_statistics_path(path), "wb") as f:
            np.savez(f, **{key: value.numpy() for key, value in checkpoint["vecnormalize"].items()})


def read_checkpoint(path: str, library: str) -> dict[str, Any]:
    """A ``library`` checkpoint file as a dict of tensors, numbers and strings (weights only; for SB3
    its zip's policy, optimizer settings and JSON settings, and the VecNormalize statistics beside it)."""
    if library == "sb3":
        return _read_sb3(path)
    from simlab.utils.trust import torch_load

    return torch_load(path, map_location="cpu")  # weights only: a run's file is data


def write_checkpoint(checkpoint: dict[str, Any], path: str, library: str) -> None:
    """Write ``checkpoint`` (:func:`read_checkpoint`'s form) as the ``library``'s checkpoint file at ``path``."""
    if library == "sb3":
        _write_sb3(checkpoint, path)
    else:
        torch.save(checkpoint, path)
