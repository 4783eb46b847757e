"""Env step time with the contact sensor reading the forces of the physics step just taken (now)
against forwarding the worlds first at every substep (before), in alternating rounds, on the CPU
(a graphed GPU step would keep replaying whichever variant it captured first).

    PYTHONPATH=$PWD python scripts/benchmarks/contact_sensor_forward.py \\
        --task simlab/Velocity-Flat-Unitree-Go2-v0 --num_envs 64
"""

from __future__ import annotations

import argparse
import statistics
import time

import gymnasium as gym
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.sensors import ContactSensor
from simlab.tasks.utils.parse_cfg import parse_env_cfg


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="simlab/Velocity-Flat-Unitree-Go2-v0")
    parser.add_argument("--num_envs", type=int, default=64)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--steps", type=int, default=20)
    args = parser.parse_args()

    env = gym.make(args.task, cfg=parse_env_cfg(args.task, device="cpu", num_envs=args.num_envs))
    env.reset()
    unwrapped = env.unwrapped
    actions = torch.zeros(args.num_envs, unwrapped.action_manager.total_action_dim, device=unwrapped.device)
    in_step_forces = ContactSensor.update

    def forward_first(self, dt, force_recompute=False):
        self._sim.physics.ensure_forward()
        in_step_forces(self, dt, force_recompute)

    times: dict[str, list[float]] = {"forward per substep (before)": [], "in-step forces (now)": []}
    for _ in range(args.rounds):
        for name, update in zip(times, (forward_first, in_step_forces), strict=True):
            ContactSensor.update = update
            for _ in range(3):
                env.step(actions)
            start = time.perf_counter()
            for _ in range(args.steps):
                env.step(actions)
            times[name].append((time.perf_counter() - start) / args.steps * 1e3)
    ContactSensor.update = in_step_forces
    print(f"{args.task}, {args.num_envs} envs on cpu: ms per env step")
    for name, ms in times.items():
        print(f"  {name:30s} {statistics.median(ms):7.2f} (rounds {[round(t, 2) for t in ms]})")
    env.close()


if __name__ == "__main__":
    main()
