"""Behaviour cloning's policy (simlab's stand-in for Isaac Lab's robomimic BC, which simlab does not
depend on): an MLP from a task's policy observation terms to its actions, its agent config and its file.

A task registers :class:`BCAgentCfg` as ``bc_cfg_entry_point`` (Isaac Lab's stack task registers
``robomimic_bc_cfg_entry_point``); ``scripts/imitation_learning/bc.py train`` fits the policy to
recorded demonstrations with its settings, and ``simlab play --library bc`` plays the file, which
holds tensors, strings and numbers only: :func:`load_bc_policy` reads it as weights only.
"""

from __future__ import annotations

import os

import torch
import torch.nn as nn

from simlab.utils import configclass

__all__ = ["BCAgentCfg", "BCPolicy", "load_bc_policy", "save_bc_policy"]


@configclass
class BCAgentCfg:
    """How a task's BC policy is trained (``bc.py train``'s defaults) and where its runs go."""

    experiment_name: str = "bc"
    obs_terms: list[str] = ["eef_pos", "eef_quat", "gripper_pos", "object"]
    """The policy observation terms fed to the MLP, in order (Isaac Lab's robomimic configs of stack)."""
    hidden: list[int] = [256, 256, 256]
    relative: int = 3
    """Leading actions predicted as offsets from the leading observation columns (:class:`BCPolicy`)."""
    epochs: int = 150
    batch_size: int = 512
    lr: float = 1e-3
    seed: int = 0


class BCPolicy(nn.Module):
    """``mlp((obs - mean) / std)``: the observation terms, concatenated in ``terms`` order, to actions.

    With ``relative`` = k, the first k actions are offsets from the first k observation columns (an
    IK-Abs target from the end effector's position, ``eef_pos`` first): going to a cube is then close
    to its end-effector-to-cube vector, which the observations hold, and an error shrinks near it.
    """

    def __init__(self, terms: list[str], obs_dim: int, action_dim: int, hidden: list[int], relative: int = 0):
        super().__init__()
        self.terms, self.hidden, self.relative = list(terms), list(hidden), relative
        self.register_buffer("obs_mean", torch.zeros(obs_dim))
        self.register_buffer("obs_std", torch.ones(obs_dim))
        self.register_buffer("action_mean", torch.zeros(action_dim))
        self.register_buffer("action_std", torch.ones(action_dim))
        layers: list[nn.Module] = []
        for width_in, width_out in zip([obs_dim, *hidden], hidden):
            layers += [nn.Linear(width_in, width_out), nn.ELU()]
        self.mlp = nn.Sequential(*layers, nn.Linear(hidden[-1] if hidden else obs_dim, action_dim))

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        actions = self.normalized(obs) * self.action_std + self.action_mean
        return torch.cat([actions[:, : self.relative] + obs[:, : self.relative], actions[:, self.relative :]], dim=-1)

    def normalized(self, obs: torch.Tensor) -> torch.Tensor:
        """The actions in units of the demonstrations' spread (what the loss compares)."""
        return self.mlp((obs - self.obs_mean) / self.obs_std)

    def flat_obs(self, policy_obs: dict[str, torch.Tensor]) -> torch.Tensor:
        """The MLP's input from the env's ``policy`` observation group (a dict of terms)."""
        return torch.cat([policy_obs[t].reshape(policy_obs[t].shape[0], -1) for t in self.terms], dim=-1)

    def act(self, policy_obs: dict[str, torch.Tensor]) -> torch.Tensor:
        """Actions from the env's ``policy`` observation group."""
        return self(self.flat_obs(policy_obs))


def save_bc_policy(policy: BCPolicy, path: str, task: str | None, epochs: int | None = None) -> None:
    """``torch.save`` the weights, the terms and sizes that rebuild the policy, its task and its epochs."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    sizes = [policy.obs_mean.shape[0], policy.mlp[-1].out_features]
    saved = {"state_dict": policy.state_dict(), "terms": policy.terms, "relative": policy.relative}
    torch.save({**saved, "hidden": policy.hidden, "sizes": sizes, "task": task, "epochs": epochs}, path)


_FILE_KEYS = ("state_dict", "terms", "relative", "hidden", "sizes")
"""What :func:`save_bc_policy` writes that :func:`load_bc_policy` rebuilds the policy from."""


def load_bc_policy(path: str, trust: bool = False) -> tuple[BCPolicy, str | None]:
    """The policy in ``path`` and its task; weights only unless ``trust`` (a file from elsewhere runs no code).
    A file that is missing, unreadable or not such a policy raises a one-line :class:`CheckpointError`."""
    from simlab.utils.errors import CheckpointError, UntrustedFileError, describe
    from simlab.utils.trust import torch_load

    if not os.path.isfile(path):
        raise CheckpointError(f"The BC policy '{path}' does not exist (looked at '{os.path.abspath(path)}').")
    written_by = "scripts/imitation_learning/bc.py train writes one"
    try:
        saved = torch_load(path, map_location="cpu", trust=trust)
    except UntrustedFileError:
        raise
    except Exception as e:  # noqa: BLE001 - corrupt bytes make torch and pickle raise anything
        raise CheckpointError(f"Cannot read the BC policy '{path}' ({describe(e)}); {written_by}.") from None
    missing = [key for key in _FILE_KEYS if not isinstance(saved, dict) or key not in saved]
    if missing:
        raise CheckpointError(f"'{path}' is not a BC policy: it lacks {missing} ({written_by}).")
    try:
        policy = BCPolicy(saved["terms"], *saved["sizes"], saved["hidden"], saved["relative"])
        policy.load_state_dict(saved["state_dict"])
    except (RuntimeError, TypeError, ValueError) as e:  # sizes and weights that do not fit each other
        raise CheckpointError(f"Cannot read the BC policy '{path}' ({describe(e)}); {written_by}.") from None
    return policy.eval(), saved.get("task")
