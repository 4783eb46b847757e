"""Step one task's model on both backends from the same state with the same controls.

    python scripts/benchmarks/compare_backends.py --task simlab/Humanoid-Direct-v0 --warp_device cpu

MuJoCo C (mjbatch) against MuJoCo Warp (``--warp_device cuda:0``, or its CPU device without a GPU;
needs ``pip install "simlab[gpu]"``). Prints the root height of a few worlds and the largest qpos
difference every 20 steps: identical until contacts begin, then the usual chaotic drift.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.sim.backends.cpu import CpuBackend
from simlab.sim.backends.cuda import CudaBackend
from simlab.tasks.utils import parse_env_cfg


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--task", default="simlab/Humanoid-Direct-v0")
    parser.add_argument("--num_envs", type=int, default=8)
    parser.add_argument("--steps", type=int, default=240)
    parser.add_argument("--ctrl_scale", type=float, default=40.0, help="random controls in +-scale")
    parser.add_argument("--warp_device", default="cuda:0")
    args = parser.parse_args()

    cfg = parse_env_cfg(args.task, device="cpu", num_envs=1)
    env = gym.make(args.task, cfg=cfg).unwrapped
    model, opts = env.sim.model, cfg.sim.mujoco
    n = args.num_envs
    backends = {
        "mujoco": CpuBackend(model, n),
        "warp": CudaBackend(model, n, device=args.warp_device, nconmax=opts.nconmax, njmax=opts.njmax),
    }
    for backend in backends.values():
        backend.reset()
    torch.manual_seed(0)
    for i in range(args.steps):
        ctrl = (torch.rand(n, model.nu) * 2 - 1) * args.ctrl_scale
        for backend in backends.values():
            backend.data("ctrl").copy_(ctrl.to(backend.device))
            backend.step(1)
        if i % 20 == 19:
            q = {name: b.data("qpos").cpu() for name, b in backends.items()}
            heights = "  ".join(f"{name} {q[name][:4, 2].numpy().round(3)}" for name in q)
            print(f"step {i + 1:4d}  root z: {heights}  max |dqpos| {float((q['mujoco'] - q['warp']).abs().max()):.2e}")
    env.close()


if __name__ == "__main__":
    main()
