"""Fit simlab's shipped actuator networks to a DC motor with a delay (about a minute on the CPU).

    python scripts/tools/fit_actuator_nets.py                # into simlab/actuators/nets
    python scripts/tools/fit_actuator_nets.py --out /tmp/nets --nets unitree_go1_mlp

What each network imitates, the *reference actuator*: simlab's ``DCMotor`` (PD law, torque-speed
limits, read at the current speed) with a latency of ``d`` physics steps, in one of two places:

* ``delayed="state"``: the drive acts on the joint state ``d`` steps old (sensing latency),
  ``tau_k = clip_dc(kp e_{k-d} - kd qd_{k-d}; qd_k)``, ``e = q* - q``;
* ``delayed="target"``: the targets arrive ``d`` steps late and the drive's own loop reads the current
  state (Isaac Lab's ``DelayedPDActuator``), ``tau_k = clip_dc(kp (q*_{k-d} - q_k) - kd qd_k; qd_k)``.
  The network sees only ``e`` and ``qd``; ``q*_{k-d} - q_k = e_{k-d} - dt (qd_k + ... + qd_{k-d+1})``
  exactly, as MuJoCo advances a joint by ``q_k = q_{k-1} + dt qd_k`` each step.

A state latency puts the delay inside the position loop: a stiff drive on a light joint then
oscillates (kp 200, kd 11 on the ANYdrive's 0.05-0.1 kg m^2 swinging knee: a growing 20 Hz
oscillation for a 2-step delay, which the torque limits turn into a limit cycle). A target latency
leaves the loop as stable as the undelayed motor.

The joint signals are smooth random processes (each sequence has its own time scale, 20-300 ms, and
amplitude), so that the nets see slow and fast, small and saturating motions. With ``held_targets``
(both nets), the position errors also jump every 4 physics steps, as a policy's targets do at
the locomotion tasks' decimation: without them the LSTM was off by 7.4 N m RMS (13 %) on ANYmal-D's
trajectories under actions of standard deviation 1, 2.5 N m with them; the MLP's damping about rest
was 0.39 instead of 0.5 N m s/rad (its gradient there): a hung Go1's legs still swung at 0.04 rad/s
after 2 s, 7 times its reference's speed.

* ``unitree_go1_mlp.pt``: :class:`ActuatorMLP` 6-32-32-1 with Isaac Lab's ``GO1_ACTUATOR_CFG`` inputs
  (``input_idx`` [0, 1, 2], ``pos_scale`` -1, ``vel_scale`` 1, ``torque_scale`` 1); reference:
  simlab's ``GO1_DC_ACTUATOR_CFG`` (kp 25, kd 0.5, 23.7 N m, 30 rad/s), state delayed 2 steps (its
  soft loop stays stable);
* ``anydrive_3_lstm.pt``: :class:`ActuatorLSTM`, one layer of 16; reference: simlab's
  ``ANYDRIVE_3_STIFF_ACTUATOR_CFG`` (kp 200, kd 11, which holds ANYmal up; 120 N m saturation, 80 N m
  limit, 7.5 rad/s), targets delayed 2 steps.

The delays are physics steps: 10 ms at the locomotion tasks' 5 ms step. The script prints each
net's error on held-out sequences (RMS and the 99.9th percentile, in N m).
"""

from __future__ import annotations

import argparse
import math
import os
import time
from dataclasses import dataclass
from typing import Literal

import torch

from simlab.actuators import DCMotorCfg
from simlab.actuators.actuator_net import NETS_DIR, ActuatorLSTM, ActuatorMLP

DT = 0.005  # physics step the signals are sampled at [s]
TAU_MIN, TAU_MAX = 0.02, 0.3  # time scales of the signals [s]: a joint moves smoothly at 5 ms steps
HOLD = 4  # physics steps a policy holds its targets (the locomotion tasks' decimation)


@dataclass
class Reference:
    kp: float
    kd: float
    saturation: float
    effort_limit: float
    velocity_limit: float
    delay: int
    delayed: Literal["state", "target"]  # where the latency is (module docstring)
    held_targets: bool  # errors also jump as a policy's held targets do (module docstring)
    error_scale: float  # typical position error [rad] of the training signals
    speed_scale: float  # typical joint speed [rad/s]


REFERENCES = {
    "unitree_go1_mlp": Reference(25.0, 0.5, 23.7, 23.7, 30.0, 2, "state", True, error_scale=0.4, speed_scale=10.0),
    "anydrive_3_lstm": Reference(200.0, 11.0, 120.0, 80.0, 7.5, 2, "target", True, error_scale=0.15, speed_scale=3.0),
}


def signals(num: int, steps: int, scale: float, gen: torch.Generator) -> torch.Tensor:
    """(num, steps) smooth random signals: AR(1) processes with a per-sequence time scale and an
    amplitude of 0.1-3 x ``scale`` per sequence (time scales TAU_MIN-TAU_MAX), plus a little white noise."""
    tau = torch.exp(torch.empty(num, 1).uniform_(math.log(TAU_MIN), math.log(TAU_MAX), generator=gen))
    a = torch.exp(-DT / tau)
    amp = scale * torch.exp(torch.empty(num, 1).uniform_(math.log(0.1), math.log(3.0), generator=gen))
    noise = torch.randn(num, steps, generator=gen)
    x = torch.empty(num, steps)
    x[:, 0] = noise[:, 0]
    for k in range(1, steps):
        x[:, k] = a[:, 0] * x[:, k - 1] + torch.sqrt(1 - a[:, 0] ** 2) * noise[:, k]
    return amp * x + 0.01 * scale * torch.randn(num, steps, generator=gen)


def reference_torque(ref: Reference, error: torch.Tensor, speed: torch.Tensor) -> torch.Tensor:
    """The reference actuator's torque for (num, steps) signals; the first ``delay`` steps repeat the
    first sample (as a delay buffer does after a reset)."""
    d = ref.delay
    old_e, old_qd = delayed(error, d), delayed(speed, d)
    if ref.delayed == "target":  # the late target against the current state: q*_{k-d} - q_k
        old_e = old_e - DT * sum((delayed(speed, j) for j in range(d)), torch.zeros_like(speed))
        old_qd = speed
    cfg = DCMotorCfg(
        joint_names_expr=[".*"],
        stiffness=ref.kp,
        damping=ref.kd,
        saturation_effort=ref.saturation,
        effort_limit=ref.effort_limit,
        velocity_limit=ref.velocity_limit,
    )
    motor = cfg.class_type(cfg, ["joint"], [0], error.numel(), "cpu")
    motor._joint_vel.copy_(speed.reshape(-1, 1))  # the limits are read at the current speed
    return motor._clip_effort((ref.kp * old_e - ref.kd * old_qd).reshape(-1, 1)).reshape(error.shape)


def delayed(signal: torch.Tensor, d: int) -> torch.Tensor:
    """(num, steps) ``signal`` ``d`` steps late, its first sample repeated before the start."""
    return torch.cat([signal[:, :1].expand(-1, d), signal[:, :-d]], dim=1) if d else signal


def data(ref: Reference, num: int, steps: int, seed: int) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    gen = torch.Generator().manual_seed(seed)
    error, speed = signals(num, steps, ref.error_scale, gen), signals(num, steps, ref.speed_scale, gen)
    if ref.held_targets:
        error = error + held(num, steps, ref.error_scale, gen)
    return error, speed, reference_torque(ref, error, speed)


def held(num: int, steps: int, scale: float, gen: torch.Generator) -> torch.Tensor:
    """(num, steps) targets as a policy sends them: a random value every HOLD steps (from a random
    phase), held in between; an amplitude of 0-3 x ``scale`` per sequence, none for a quarter of them."""
    jumps = torch.randn(num, steps // HOLD + 2, generator=gen)
    phase = torch.randint(0, HOLD, (num, 1), generator=gen)
    index = (torch.arange(steps).view(1, -1) + phase) // HOLD
    amp = scale * 3 * torch.rand(num, 1, generator=gen) * (torch.rand(num, 1, generator=gen) > 0.25)
    return amp * torch.gather(jumps, 1, index)


def mlp_inputs(error: torch.Tensor, speed: torch.Tensor) -> torch.Tensor:
    """GO1_ACTUATOR_CFG's inputs at steps 2..: -e_k, -e_{k-1}, -e_{k-2}, qd_k, qd_{k-1}, qd_{k-2}."""
    steps = error.shape[1]
    pos = [-error[:, 2 - i : steps - i] for i in range(3)]
    vel = [speed[:, 2 - i : steps - i] for i in range(3)]
    return torch.stack(pos + vel, dim=-1).reshape(-1, 6)


def fit_mlp(ref: Reference, seed: int) -> tuple[torch.nn.Module, dict[str, float]]:
    error, speed, torque = data(ref, 2048, 200, seed)
    x, y = mlp_inputs(error, speed), torque[:, 2:].reshape(-1, 1)
    torch.manual_seed(seed)
    net = ActuatorMLP([6, 32, 32, 1])
    opt = torch.optim.Adam(net.parameters(), lr=3e-3)
    iterations = 4000
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, iterations)
    for _ in range(iterations):
        batch = torch.randint(0, len(x), (2048,))
        loss = torch.nn.functional.mse_loss(net(x[batch]), y[batch])
        opt.zero_grad()
        loss.backward()
        opt.step()
        sched.step()
    error, speed, torque = data(ref, 256, 200, seed + 1)
    with torch.no_grad():
        residual = net(mlp_inputs(error, speed)).reshape(-1) - torque[:, 2:].reshape(-1)
    return net, _stats(residual, torque)


def fit_lstm(ref: Reference, seed: int) -> tuple[torch.nn.Module, dict[str, float]]:
    error, speed, torque = data(ref, 2048, 64, seed)
    torch.manual_seed(seed)
    net = ActuatorLSTM(hidden_size=16, num_layers=1)
    _scale_output(net.output, ref)
    opt = torch.optim.Adam(net.parameters(), lr=3e-2)
    iterations = 3000
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, iterations)
    warm = ref.delay  # the first steps hold the sample before the signal: not learnable, not scored
    for _ in range(iterations):
        batch = torch.randint(0, len(error), (256,))
        pred = _run_lstm(net, error[batch], speed[batch])
        loss = torch.nn.functional.mse_loss(pred[:, warm:], torque[batch, warm:])
        opt.zero_grad()
        loss.backward()
        opt.step()
        sched.step()
    error, speed, torque = data(ref, 256, 400, seed + 1)
    with torch.no_grad():
        residual = (_run_lstm(net, error, speed) - torque)[:, warm:].reshape(-1)
    return net, _stats(residual, torque)


def _scale_output(layer: torch.nn.Linear, ref: Reference) -> None:
    """Start the LSTM's output layer at the torque's scale: Adam's steps (about the learning rate
    each) would take thousands of iterations to grow its weights to tens of N m per unit of hidden
    state (the MLP, whose hidden layers are not bounded to [-1, 1] by a tanh, fits better without)."""
    with torch.no_grad():
        layer.weight.mul_(ref.effort_limit / 2)


def _run_lstm(net: ActuatorLSTM, error: torch.Tensor, speed: torch.Tensor) -> torch.Tensor:
    """Torque of every step of (num, steps) sequences, from a zero state (as after a reset)."""
    out, _ = net.lstm(torch.stack([error, speed], dim=-1))
    return net.output(out).squeeze(-1)


def _stats(residual: torch.Tensor, torque: torch.Tensor) -> dict[str, float]:
    abs_res = residual.abs()
    return {
        "rms_error": residual.pow(2).mean().sqrt().item(),
        "p999_error": abs_res.quantile(0.999).item() if abs_res.numel() <= 2**24 else float("nan"),
        "rms_torque": torque.pow(2).mean().sqrt().item(),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=NETS_DIR, help="Folder for the nets (default: simlab/actuators/nets).")
    parser.add_argument("--nets", nargs="+", default=list(REFERENCES), choices=list(REFERENCES))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", type=int, default=1, help="CPU threads for torch (1: small nets train fastest).")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    os.makedirs(args.out, exist_ok=True)
    for name in args.nets:
        start = time.perf_counter()
        fit = fit_mlp if name.endswith("_mlp") else fit_lstm
        net, stats = fit(REFERENCES[name], args.seed)
        path = os.path.join(args.out, f"{name}.pt")
        torch.save(net.state_dict(), path)
        print(
            f"{name}.pt ({os.path.getsize(path) / 1024:.1f} KB, {time.perf_counter() - start:.0f} s):"
            f" held-out RMS error {stats['rms_error']:.3f} N m, 99.9th percentile {stats['p999_error']:.3f} N m"
            f" (RMS torque {stats['rms_torque']:.2f} N m)"
        )


if __name__ == "__main__":
    main()
