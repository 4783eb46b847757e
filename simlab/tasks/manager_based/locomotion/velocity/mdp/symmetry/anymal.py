"""ANYmal's mirror symmetries for data augmentation (Isaac Lab's ``mdp.symmetry.anymal``).

A batch of observations and actions becomes four: as recorded, mirrored left-right (about the base's
x-z plane), front-back (about its y-z plane), and both. The policy observation is the velocity
tasks' layout: base linear velocity, base angular velocity, gravity (3 each), the command (vx, vy,
yaw rate), joint positions, joint velocities and last actions (12 each, Isaac Lab's joint order
LF, LH, RF, RH within HAA, HFE, KFE), then on rough ground the 11 x 17 height scan (y rows, x columns).

Mirroring swaps legs: left-right swaps LF<->RF and LH<->RH and negates the abduction (HAA) angles;
front-back swaps LF<->LH and RF<->RH and negates the flexion (HFE, KFE) angles.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

if TYPE_CHECKING:
    from tensordict import TensorDict

    from simlab.envs import ManagerBasedRLEnv

__all__ = ["compute_symmetric_states"]

# joint index = part * 4 + leg, legs LF, LH, RF, RH
_LEFT_RIGHT_LEGS = [2, 3, 0, 1]
_FRONT_BACK_LEGS = [1, 0, 3, 2]
_JOINTS = {
    "left_right": ([part * 4 + leg for part in range(3) for leg in _LEFT_RIGHT_LEGS], [-1.0] * 4 + [1.0] * 8),
    "front_back": ([part * 4 + leg for part in range(3) for leg in _FRONT_BACK_LEGS], [1.0] * 4 + [-1.0] * 8),
}
# sign flips of (lin vel, ang vel, gravity, command) under each mirror
_BASE_SIGNS = {
    "left_right": [1, -1, 1] + [-1, 1, -1] + [1, -1, 1] + [1, -1, -1],
    "front_back": [-1, 1, 1] + [1, -1, -1] + [-1, 1, 1] + [-1, 1, -1],
}
_SCAN_ROWS, _SCAN_COLS = 11, 17
_SCAN_FLIP_DIM = {"left_right": 1, "front_back": 2}  # flip y rows, or x columns


def _mirror_joints(data: torch.Tensor, mirror: str) -> torch.Tensor:
    order, signs = _JOINTS[mirror]
    return data[..., order] * torch.tensor(signs, device=data.device)


def _mirror_obs(obs: torch.Tensor, mirror: str, has_scan: bool) -> torch.Tensor:
    out = obs.clone()
    out[:, :12] = obs[:, :12] * torch.tensor(_BASE_SIGNS[mirror], device=obs.device, dtype=obs.dtype)
    for start in (12, 24, 36):  # joint positions, velocities, last actions
        out[:, start : start + 12] = _mirror_joints(obs[:, start : start + 12], mirror)
    if has_scan:
        end = 48 + _SCAN_ROWS * _SCAN_COLS
        scan = obs[:, 48:end].reshape(-1, _SCAN_ROWS, _SCAN_COLS)
        out[:, 48:end] = scan.flip(dims=[_SCAN_FLIP_DIM[mirror]]).reshape(-1, _SCAN_ROWS * _SCAN_COLS)
    return out


def _has_height_scan(env, obs_type: str) -> bool:
    terms = env.observation_manager.active_terms
    group = "critic" if obs_type == "critic" and "critic" in terms else "policy"
    return "height_scan" in terms[group]


def _augment_obs(env, obs: torch.Tensor, obs_type: str) -> torch.Tensor:
    has_scan = _has_height_scan(env, obs_type)
    left_right = _mirror_obs(obs, "left_right", has_scan)
    front_back = _mirror_obs(obs, "front_back", has_scan)
    return torch.cat([obs, left_right, front_back, _mirror_obs(left_right, "front_back", has_scan)])


@torch.no_grad()
def compute_symmetric_states(
    env: ManagerBasedRLEnv,
    obs: torch.Tensor | TensorDict | None = None,
    actions: torch.Tensor | None = None,
    obs_type: str = "policy",
) -> tuple[torch.Tensor | TensorDict | None, torch.Tensor | None]:
    """``obs`` and ``actions`` stacked four times: as given, left-right, front-back, and both mirrored.

    ``obs`` is one group's tensor (``obs_type`` names it) or, as rsl_rl passes it, a TensorDict of
    groups ("policy", "critic"), each mirrored by its own layout."""
    obs_aug = actions_aug = None
    if obs is not None:
        if isinstance(obs, torch.Tensor):
            obs_aug = _augment_obs(env.unwrapped, obs, obs_type)
        else:
            groups = {name: _augment_obs(env.unwrapped, obs[name], name) for name in obs.keys()}  # noqa: SIM118 - a TensorDict iterates its rows
            obs_aug = type(obs)(groups, batch_size=[4 * obs.batch_size[0]], device=obs.device)
    if actions is not None:
        left_right = _mirror_joints(actions, "left_right")
        front_back = _mirror_joints(actions, "front_back")
        actions_aug = torch.cat([actions, left_right, front_back, _mirror_joints(left_right, "front_back")])
    return obs_aug, actions_aug
