"""Behaviour cloning adapter: play a :class:`~simlab.rl.bc.BCPolicy` file (``simlab play --library bc``).

A BC policy is fitted to demonstrations, not trained in the env, so ``simlab train --library bc`` is
refused with the command that fits one. The played module reads the whole ``policy`` group,
concatenated in the group's term order as rsl_rl's actors read it (what the exported files' deploy
metadata describes), and picks the columns of the terms it was fitted on.
"""

from __future__ import annotations

import argparse
from typing import Any

import gymnasium as gym
import torch
import torch.nn as nn

from simlab.cli.policy import Policy
from simlab.rl.bc import BCAgentCfg, BCPolicy, load_bc_policy
from simlab.utils.errors import CheckpointError, ConfigError

FIT_COMMAND = "python scripts/imitation_learning/bc.py train --dataset_file <demos.hdf5> --out <policy.pt>"


def experiment_name(agent_cfg: BCAgentCfg, task: str) -> str:
    return agent_cfg.experiment_name


def configure(agent_cfg: BCAgentCfg, args: argparse.Namespace, env_cfg: Any) -> None:
    if getattr(args, "command", None) == "train":
        raise ConfigError(f"A bc policy is fitted to demonstrations, not trained in the env: {FIT_COMMAND}.")
    if args.seed is not None:
        env_cfg.seed = args.seed


def train(env: gym.Env, agent_cfg: BCAgentCfg, run_dir: str, args: argparse.Namespace, resume: str | None) -> None:
    raise ConfigError(f"A bc policy is fitted to demonstrations, not trained in the env: {FIT_COMMAND}.")


class _TermColumns(nn.Module):
    """``policy(obs[:, columns])``: the BC policy on its terms' columns of the whole policy group."""

    def __init__(self, policy: BCPolicy, columns: torch.Tensor):
        super().__init__()
        self.policy = policy
        self.register_buffer("columns", columns)

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        return self.policy(obs.index_select(1, self.columns))


def load_policy(env: gym.Env, agent_cfg: BCAgentCfg, checkpoint: str, trust: bool = False) -> Policy:
    base = env.unwrapped
    manager = getattr(base, "observation_manager", None)
    if manager is None or "policy" not in manager.active_terms:
        raise ConfigError(
            "A bc policy reads the terms of a manager-based env's 'policy' observation group; this env has none."
        )
    policy, _ = load_bc_policy(checkpoint, trust)
    names, shapes = manager.active_terms["policy"], manager.group_obs_term_dim["policy"]
    spans, size = {}, 0  # each term's first column and width in the concatenated group
    for name, shape in zip(names, shapes):
        width = int(torch.Size(shape).numel())
        spans[name], size = (size, width), size + width
    missing = [t for t in policy.terms if t not in spans]
    if missing:
        raise CheckpointError(f"'{checkpoint}' reads the policy terms {missing}, which this env lacks; it has {names}.")
    columns = torch.cat([torch.arange(start, start + width) for start, width in (spans[t] for t in policy.terms)])
    if len(columns) != len(policy.obs_mean):
        raise CheckpointError(
            f"'{checkpoint}' reads {len(policy.obs_mean)} columns of the terms {policy.terms}; this env's are"
            f" {len(columns)} wide (a policy of another task, or of other env overrides?)."
        )
    module = _TermColumns(policy, columns)

    def inputs(obs: dict) -> dict[str, torch.Tensor]:
        group = obs["policy"]
        if isinstance(group, dict):  # the terms in the group's order (a dict keeps it)
            group = torch.cat([group[n].reshape(group[n].shape[0], -1) for n in names], dim=-1)
        return {"policy": group}

    return Policy({"policy": module}, inputs, {"policy": size}, device=str(base.device))
