"""A frozen low-level policy as an action term (Isaac Lab's ``PreTrainedPolicyAction``).

The high-level action is the low-level policy's velocity command ``(v_x, v_y, w_z)``. Every
``low_level_decimation`` physics steps the term computes the low-level observations (the velocity
task's own observation group, its ``velocity_commands`` term reading the high-level action and its
``actions`` term the low-level policy's last output), runs the policy and hands its output (joint
position targets) to the low-level action term, which applies it at every physics step.

Isaac Lab loads the policy as a TorchScript file (``torch.jit.load``), which is code from a file.
simlab reads only weights (``torch.load(weights_only=True)``) and builds the policy's network here: an
MLP, from the layer shapes of the weights and ``policy_activation``. A file may be a shipped simlab
policy (``simlab/pretrained/<task>/rsl_rl/policy.pt``), an rsl_rl checkpoint (``model_*.pt``) or a plain
state dict of the actor's layers. A TorchScript file, or a pickle holding more than tensors, is refused
in one line unless the config sets ``trust_policy_file=True`` (as the actuator networks do).

Isaac Lab's Nucleus path of its blind ANYmal-C policy names simlab's shipped ANYmal-C flat-ground
velocity policy (``simlab.pretrained.isaaclab_policies.ISAACLAB_POLICIES``), trained with the same
observations (48 values, no height scan) and actions.
"""

from __future__ import annotations

import copy
import pickle
from typing import TYPE_CHECKING

import torch
from torch import nn

from simlab.managers import ActionTerm, ObservationManager
from simlab.pretrained.isaaclab_policies import (
    ISAACLAB_POLICIES,
    MLPPolicy,
    actor_state,
    isaaclab_policy,
    shipped_policy_file,
)
from simlab.pretrained.weights import FORMAT as STORED_POLICY_FORMAT
from simlab.pretrained.weights import unpack_policy
from simlab.utils.assets import retrieve_file_path
from simlab.utils.env_mask import PerEnvState, env_mask
from simlab.utils.errors import ConfigError, UntrustedFileError
from simlab.utils.trust import is_torchscript

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

    from .pre_trained_policy_action_cfg import PreTrainedPolicyActionCfg


def resolve_policy_file(path: str) -> str:
    """The local file of ``policy_path``: simlab's shipped policy for an Isaac Lab Nucleus path of one."""
    if "://" in str(path):
        isaac_path = isaaclab_policy(path)
        if isaac_path is not None:
            return shipped_policy_file(isaac_path)
        known = ", ".join(ISAACLAB_POLICIES)
        raise ConfigError(
            f"policy_path '{path}' is a remote (Nucleus) file simlab cannot read; simlab has its own policies for"
            f" Isaac Lab's {known} (under ISAACLAB_NUCLEUS_DIR); give a local file of weights otherwise."
        )
    try:
        return retrieve_file_path(path)
    except FileNotFoundError as e:
        raise ConfigError(f"policy_path: {e}") from None


def load_policy(cfg: PreTrainedPolicyActionCfg, device: str | torch.device) -> nn.Module:
    """The policy of ``cfg.policy_path`` on ``device``, in eval mode and without gradients."""
    path = resolve_policy_file(cfg.policy_path)
    what = f"policy_path '{cfg.policy_path}'"
    trust = bool(cfg.trust_policy_file)
    hint = "set trust_policy_file=True if you trust the file (loading it may run code)"
    if is_torchscript(path):
        if not trust:
            raise UntrustedFileError(
                f"Refused to load {what}: it is a TorchScript file (code); simlab loads weights only: save its"
                f" weights with torch.save(torch.jit.load(file).state_dict(), 'policy.pt'), or {hint}."
            )
        policy = torch.jit.load(path, map_location=device)
    else:
        try:
            loaded = torch.load(path, map_location="cpu", weights_only=not trust)
        except pickle.UnpicklingError:
            raise UntrustedFileError(f"Refused to load {what}: it holds more than weights; {hint}.") from None
        if isinstance(loaded, nn.Module):  # only reachable with trust
            policy = loaded
        else:
            if isinstance(loaded, dict) and loaded.get("format") == STORED_POLICY_FORMAT:
                loaded = unpack_policy(path)[1]
            policy = MLPPolicy(actor_state(loaded, what), cfg.policy_activation, what)
    policy = policy.to(device).eval()
    for p in policy.parameters():
        p.requires_grad_(False)
    return policy


class PreTrainedPolicyAction(ActionTerm):
    """The velocity command ``(v_x, v_y, w_z)`` of a frozen low-level locomotion policy."""

    cfg: PreTrainedPolicyActionCfg

    def __init__(self, cfg: PreTrainedPolicyActionCfg, env: ManagerBasedRLEnv) -> None:
        super().__init__(cfg, env)
        self.robot = env.scene[cfg.asset_name]
        if cfg.low_level_decimation < 1 or env.cfg.decimation % cfg.low_level_decimation:
            raise ConfigError(
                f"low_level_decimation={cfg.low_level_decimation} must be a positive divisor of the env's decimation"
                f" ({env.cfg.decimation}), so that every env step runs the low-level policy at the same physics steps."
            )
        self.policy = load_policy(cfg, self.device)
        self._state = PerEnvState(self.num_envs, self.device)
        self._raw_actions = self._state.zeros("raw_actions", (self.action_dim,))
        self._low_level_action_term: ActionTerm = cfg.low_level_actions.class_type(cfg.low_level_actions, env)
        self.low_level_actions = self._state.zeros("low_level_actions", (self._low_level_action_term.action_dim,))

        # the velocity task's observation group, two of its terms fed from here (a copy: the cfg stays as given)
        observations = copy.deepcopy(cfg.low_level_observations)
        for name in ("actions", "velocity_commands"):
            if getattr(observations, name, None) is None:
                raise ConfigError(f"low_level_observations has no '{name}' term; the low-level policy reads it.")
        observations.actions.func = lambda env: self.low_level_actions
        observations.actions.params = {}
        observations.velocity_commands.func = lambda env: self._raw_actions
        observations.velocity_commands.params = {}
        self._low_level_obs_manager = ObservationManager({"ll_policy": observations}, env)
        obs_dim = self._low_level_obs_manager.group_obs_dim["ll_policy"][0]
        expected = getattr(self.policy, "obs_dim", obs_dim)  # a TorchScript policy does not say
        if obs_dim != expected:
            raise ConfigError(
                f"low_level_observations give {obs_dim} values, but the policy of '{cfg.policy_path}' reads {expected};"
                " give the observation group the policy was trained with, in its order."
            )
        self._counter = 0

    @property
    def action_dim(self) -> int:
        return 3

    @property
    def raw_actions(self) -> torch.Tensor:
        return self._raw_actions

    @property
    def processed_actions(self) -> torch.Tensor:
        return self._raw_actions

    def process_actions(self, actions: torch.Tensor) -> None:
        self._raw_actions[:] = actions
        # the low-level policy runs at the first physics step of every env step and every
        # low_level_decimation after it: the same Python path at every step, so a captured step replays it
        self._counter = 0

    def apply_actions(self) -> None:
        if self._counter % self.cfg.low_level_decimation == 0:
            obs = self._low_level_obs_manager.compute_group("ll_policy")
            self.low_level_actions[:] = self.policy(obs)
            self._low_level_action_term.process_actions(self.low_level_actions)
        self._low_level_action_term.apply_actions()
        self._counter += 1

    def reset(self, env_ids=None) -> None:
        """Zero the command and the low-level policy's last action of the envs that restart (ids or a mask)."""
        mask = env_mask(env_ids, self.num_envs, self.device)
        self._state.reset(mask)
        self._low_level_action_term.reset(mask)
        self._low_level_obs_manager.reset(mask)
