"""Actuator networks (Isaac Lab's ``ActuatorNetMLP`` and ``ActuatorNetLSTM``): a learned map from the
joint's position error and velocity to torque, clipped by the DC motor's torque-speed limits.

Isaac Lab loads these networks as TorchScript files (``torch.jit.load``), which is code from a file.
simlab defines the two architectures here and reads only their weights, a state dict loaded with
``torch.load(weights_only=True)``:

* :class:`ActuatorMLP`: linear layers with a softsign between them (``nn.Sequential`` keys ``0.weight``,
  ``0.bias``, ``2.weight``, ...); the layer sizes are read from the weights;
* :class:`ActuatorLSTM`: an ``nn.LSTM`` on ``(position error, velocity)`` (``lstm.*`` keys) and a linear
  output layer (``output.*``); layers and hidden size are read from the weights.

A TorchScript file, or a pickle holding more than tensors, is refused with one line unless the
config sets ``trust_network_file=True``: then it loads as Isaac Lab loads it. To use a TorchScript
network you trust without that, save its weights once: ``torch.save(torch.jit.load(path).state_dict(),
"net.pt")`` (an MLP must be a plain ``Sequential`` of linear and softsign layers).

simlab ships two small networks of its own in ``simlab/actuators/nets`` (``scripts/tools/
fit_actuator_nets.py`` made them; docs/actuators.md says what they were fitted to and how well), and
Isaac Lab's Nucleus paths of its actuator networks name them (:data:`ISAACLAB_ACTUATOR_NETS`).
"""

from __future__ import annotations

import os
import pickle
from typing import TYPE_CHECKING, Literal

import torch
from torch import nn

from simlab.utils.assets import retrieve_file_path
from simlab.utils.env_mask import PerEnvState, env_mask
from simlab.utils.errors import ConfigError, UntrustedFileError
from simlab.utils.trust import is_torchscript
from simlab.utils.types import ArticulationActions

from .actuator_pd import DCMotor

if TYPE_CHECKING:
    from .actuator_cfg import ActuatorNetLSTMCfg, ActuatorNetMLPCfg

NETS_DIR = os.path.join(os.path.dirname(__file__), "nets")
"""simlab's own actuator networks (weights only)."""

ISAACLAB_ACTUATOR_NETS: dict[str, str] = {
    "ActuatorNets/Unitree/unitree_go1.pt": "unitree_go1_mlp.pt",
    "ActuatorNets/ANYbotics/anydrive_3_lstm_jit.pt": "anydrive_3_lstm.pt",
}
"""Isaac Lab's actuator networks (their path under ``ISAACLAB_NUCLEUS_DIR``) and the file in
:data:`NETS_DIR` that stands for each: simlab's network of the same inputs and outputs, fitted to a DC
motor with a delay (not the measured drive Isaac Lab's network learned)."""


class ActuatorMLP(nn.Sequential):
    """Linear layers with a softsign between consecutive ones; ``sizes`` = (inputs, hidden..., 1)."""

    def __init__(self, sizes: list[int]):
        layers: list[nn.Module] = []
        for i, (fan_in, fan_out) in enumerate(zip(sizes[:-1], sizes[1:])):
            if i:
                layers.append(nn.Softsign())
            layers.append(nn.Linear(fan_in, fan_out))
        super().__init__(*layers)

    @classmethod
    def sizes_of(cls, state: dict[str, torch.Tensor]) -> list[int]:
        weights = sorted((int(k.split(".")[0]), v) for k, v in state.items() if k.endswith(".weight"))
        return [weights[0][1].shape[1]] + [w.shape[0] for _, w in weights] if weights else []


class ActuatorLSTM(nn.Module):
    """An LSTM on ``(position error, velocity)`` per joint and step, and a linear layer to torque.

    ``forward(x, (h, c))`` with ``x`` of shape ``(batch, 1, 2)`` returns ``(torque (batch, 1), (h, c))``,
    the interface of Isaac Lab's TorchScript networks.
    """

    def __init__(self, hidden_size: int, num_layers: int = 1):
        super().__init__()
        self.lstm = nn.LSTM(2, hidden_size, num_layers, batch_first=True)
        self.output = nn.Linear(hidden_size, 1)

    def forward(self, x: torch.Tensor, state: tuple[torch.Tensor, torch.Tensor]):
        out, state = self.lstm(x, state)
        return self.output(out[:, -1]), state

    @classmethod
    def shape_of(cls, state: dict[str, torch.Tensor]) -> tuple[int, int]:
        """(hidden size, layers) of the weights."""
        layers = sum(1 for k in state if k.startswith("lstm.weight_hh_l"))
        hidden = state["lstm.weight_hh_l0"].shape[1] if "lstm.weight_hh_l0" in state else 0
        return hidden, layers


def resolve_network_file(path: str) -> str:
    """The local file of ``network_file``: simlab's own network for an Isaac Lab Nucleus path of one."""
    if "://" in str(path):  # a Nucleus (or other remote) path: only Isaac Lab's own networks resolve
        for isaac_path, shipped in ISAACLAB_ACTUATOR_NETS.items():
            if str(path).endswith("/" + isaac_path):
                return os.path.join(NETS_DIR, shipped)
        known = ", ".join(ISAACLAB_ACTUATOR_NETS)
        raise ConfigError(
            f"network_file '{path}' is a remote (Nucleus) file simlab cannot read; simlab has its own networks for"
            f" Isaac Lab's {known} (under ISAACLAB_NUCLEUS_DIR); give a local file of weights otherwise."
        )
    try:
        return retrieve_file_path(path)
    except FileNotFoundError as e:
        raise ConfigError(f"network_file: {e}") from None


def load_actuator_network(
    cfg: ActuatorNetMLPCfg | ActuatorNetLSTMCfg, kind: Literal["mlp", "lstm"], device: str | torch.device
) -> nn.Module:
    """The network of ``cfg.network_file`` on ``device``, in eval mode and without gradients."""
    path = resolve_network_file(cfg.network_file)
    what = f"network_file '{cfg.network_file}'"
    trust = bool(getattr(cfg, "trust_network_file", False))
    hint = "set trust_network_file=True if you trust the file (loading it may run code)"
    if is_torchscript(path):
        if not trust:
            raise UntrustedFileError(
                f"Refused to load {what}: it is a TorchScript file (code); simlab loads weights only: save its"
                f" state dict with torch.save(torch.jit.load(file).state_dict(), 'net.pt'), or {hint}."
            )
        network = torch.jit.load(path, map_location=device)
    else:
        try:
            loaded = torch.load(path, map_location=device, weights_only=not trust)
        except pickle.UnpicklingError:
            raise UntrustedFileError(f"Refused to load {what}: it holds more than weights; {hint}.") from None
        network = loaded if isinstance(loaded, nn.Module) else _build(kind, loaded, what)
    network = network.to(device).eval()
    for p in network.parameters():
        p.requires_grad_(False)
    return network


def _build(kind: str, state, what: str) -> nn.Module:
    if not isinstance(state, dict) or not all(isinstance(v, torch.Tensor) for v in state.values()):
        raise ConfigError(f"{what} holds a {type(state).__name__}, not a state dict of tensors.")
    if kind == "mlp":
        sizes = ActuatorMLP.sizes_of(state) if all(k.split(".")[0].isdigit() for k in state) else []
        network, layout = (ActuatorMLP(sizes) if len(sizes) > 1 else None), "an MLP's ('0.weight', '0.bias', ...)"
    else:
        hidden, layers = ActuatorLSTM.shape_of(state)
        network, layout = (ActuatorLSTM(hidden, layers) if hidden else None), "an LSTM's ('lstm.*', 'output.*')"
    try:
        if network is None:
            raise RuntimeError("unknown keys")
        network.load_state_dict(state)
    except RuntimeError:
        keys = ", ".join(list(state)[:4])
        raise ConfigError(f"{what}: its weights ({keys}, ...) are not {layout}, the layout simlab reads.") from None
    return network


class ActuatorNetMLP(DCMotor):
    """Torque from an MLP fed the joint position errors and velocities of the steps ``input_idx``
    back (0: this step), scaled by ``pos_scale`` and ``vel_scale``, output times ``torque_scale``,
    clipped as a DC motor (Hwangbo et al. 2019; Isaac Lab's model). The history is per env and
    joint, zeroed at the env's reset; only the position targets are used."""

    cfg: ActuatorNetMLPCfg

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device, **defaults):
        super().__init__(cfg, joint_names, joint_ids, num_envs, device, **defaults)
        if cfg.input_order not in ("pos_vel", "vel_pos"):
            raise ConfigError(f"ActuatorNetMLPCfg.input_order is 'pos_vel' or 'vel_pos', got {cfg.input_order!r}.")
        input_idx = list(cfg.input_idx)
        if not input_idx or not all(type(i) is int and i >= 0 for i in input_idx):
            raise ConfigError(f"ActuatorNetMLPCfg.input_idx must be history steps (integers >= 0), got {input_idx!r}.")
        self.network = load_actuator_network(cfg, "mlp", device)
        first = next((m for m in self.network.modules() if isinstance(m, nn.Linear)), None)
        if first is not None and first.in_features != 2 * len(input_idx):
            raise ConfigError(
                f"network_file '{cfg.network_file}' takes {first.in_features} inputs; input_idx={input_idx} gives"
                f" {2 * len(input_idx)} (a position error and a velocity per history step)."
            )
        self._input_idx = torch.tensor(input_idx, dtype=torch.long, device=device)
        # Both histories in one buffer, newest step first, (envs, steps, 2, joints), the two kinds in the
        # network's input order: recording a step is one concatenation and one copy, and the inputs are
        # one gather, one reshape and one scale (this runs every physics step). Isaac Lab's two
        # histories are views of it.
        self._pos_first = cfg.input_order == "pos_vel"
        self.state = PerEnvState(num_envs, device)
        self._history = self.state.zeros("history", (max(input_idx) + 1, 2, self.num_joints))
        pos, vel = (0, 1) if self._pos_first else (1, 0)  # the channel of each kind
        self._joint_pos_error_history = self._history[:, :, pos]
        self._joint_vel_history = self._history[:, :, vel]
        scales = (cfg.pos_scale, cfg.vel_scale) if self._pos_first else (cfg.vel_scale, cfg.pos_scale)
        self._input_scale = torch.tensor(scales, device=device).repeat_interleave(len(input_idx))  # (2 K,)

    def reset(self, env_ids) -> None:
        self.state.reset(env_mask(env_ids, self.num_envs, self.device))

    def restart(self, mask: torch.Tensor) -> None:
        super().restart(mask)
        self.state.reset(mask)  # zeros: no draw

    def compute(self, control_action, joint_pos, joint_vel):
        error = control_action.joint_positions - joint_pos
        newest = (error, joint_vel) if self._pos_first else (joint_vel, error)
        flat = self._history.view(self.num_envs, -1)  # each env's steps, newest first
        flat.copy_(torch.cat((*newest, flat[:, : flat.shape[1] - 2 * self.num_joints]), dim=1))
        self._record_speed(joint_vel)  # where the DC motor's limits are read
        # (envs * joints, 2 K): each joint's first kind at the steps input_idx back, then its second kind
        picked = self._history.index_select(1, self._input_idx).permute(0, 3, 2, 1)
        inputs = picked.reshape(self.num_envs * self.num_joints, -1) * self._input_scale
        with torch.no_grad():
            torques = self.network(inputs)
        torch.mul(torques.view(self.num_envs, self.num_joints), self.cfg.torque_scale, out=self.computed_effort)
        self._clip_effort(self.computed_effort, out=self.applied_effort)
        return ArticulationActions(joint_efforts=self.applied_effort, joint_indices=control_action.joint_indices)


class ActuatorNetLSTM(DCMotor):
    """Torque from an LSTM fed each step's joint position error and velocity, clipped as a DC motor
    (Rudin et al. 2022; Isaac Lab's model). The hidden and cell states are per env and joint, zeroed
    at the env's reset; only the position targets are used."""

    cfg: ActuatorNetLSTMCfg

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device, **defaults):
        super().__init__(cfg, joint_names, joint_ids, num_envs, device, **defaults)
        self.network = load_actuator_network(cfg, "lstm", device)
        lstm = self.network.lstm.state_dict()
        num_layers, hidden = len(lstm) // 4, lstm["weight_hh_l0"].shape[1]
        rows = num_envs * self.num_joints
        self.sea_input = torch.zeros(rows, 1, 2, device=device)
        self.sea_hidden_state = torch.zeros(num_layers, rows, hidden, device=device)
        self.sea_cell_state = torch.zeros(num_layers, rows, hidden, device=device)
        per_env = (num_layers, num_envs, self.num_joints, hidden)
        self.sea_hidden_state_per_env = self.sea_hidden_state.view(per_env)
        self.sea_cell_state_per_env = self.sea_cell_state.view(per_env)
        self.state = PerEnvState(num_envs, device)  # env-first views of the states the LSTM reads
        self.state.add("hidden_state", self.sea_hidden_state_per_env.transpose(0, 1))
        self.state.add("cell_state", self.sea_cell_state_per_env.transpose(0, 1))

    def reset(self, env_ids) -> None:
        self.state.reset(env_mask(env_ids, self.num_envs, self.device))

    def restart(self, mask: torch.Tensor) -> None:
        super().restart(mask)
        self.state.reset(mask)  # zeros: no draw

    def compute(self, control_action, joint_pos, joint_vel):
        # (position error, velocity) of each env and joint written in one kernel, rows env-major
        error = control_action.joint_positions - joint_pos
        torch.stack((error, joint_vel), dim=-1, out=self.sea_input.view(self.num_envs, self.num_joints, 2))
        self._record_speed(joint_vel)
        with torch.no_grad():
            torques, (hidden, cell) = self.network(self.sea_input, (self.sea_hidden_state, self.sea_cell_state))
        self.sea_hidden_state.copy_(hidden)
        self.sea_cell_state.copy_(cell)
        self.computed_effort.copy_(torques.view(self.num_envs, self.num_joints))
        self._clip_effort(self.computed_effort, out=self.applied_effort)
        return ArticulationActions(joint_efforts=self.applied_effort, joint_indices=control_action.joint_indices)
