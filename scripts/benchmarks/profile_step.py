"""Where the time of a GPU env step goes: kernel counts and the physics share of a graphed step.

    python scripts/benchmarks/profile_step.py --task simlab/Cartpole-Direct-v0 --num_envs 4096

Prints, for one eager env step, the number of CUDA kernels launched (MuJoCo Warp's and torch's,
counted with the torch profiler), then the time of a graphed env step next to the time of the
same physics alone (``decimation`` substeps, replayed as a graph).
"""

from __future__ import annotations

import argparse

import torch
from torch.profiler import ProfilerActivity, profile

from simlab.benchmarks.env_suites import _random_actions, make_env
from simlab.benchmarks.timing import time_loop


def count_kernels(env, steps: int = 3) -> dict[str, float]:
    actions = _random_actions(env)
    env.step(actions)
    torch.cuda.synchronize()
    with profile(activities=[ProfilerActivity.CUDA]) as prof:
        for _ in range(steps):
            env.step(actions)
        torch.cuda.synchronize()
    kernels = [e for e in prof.events() if e.device_type == torch.autograd.DeviceType.CUDA]
    warp = [e for e in kernels if "_cuda_kernel_forward" in e.name or "wp_" in e.name]
    return {"kernels_per_step": len(kernels) / steps, "warp_kernels_per_step": len(warp) / steps}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--task", default="simlab/Cartpole-Direct-v0")
    parser.add_argument("--num_envs", type=int, default=4096)
    parser.add_argument("--steps", type=int, default=200)
    args = parser.parse_args()

    eager = make_env(args.task, args.num_envs, "cuda:0", cuda_graph=False)
    eager.reset()
    counts = count_kernels(eager)
    print(
        f"{args.task} @ {args.num_envs}: eager step launches {counts['kernels_per_step']:.0f} kernels "
        f"({counts['warp_kernels_per_step']:.0f} of them MuJoCo Warp's)"
    )
    eager.close()

    env = make_env(args.task, args.num_envs, "cuda:0", cuda_graph=True)
    env.reset()
    actions = _random_actions(env)
    step_s = time_loop(lambda: env.step(actions), args.steps, "cuda:0")
    graphed = count_kernels(env)
    print(f"a replayed (graphed) step runs {graphed['kernels_per_step']:.0f} kernels as seen by the profiler")
    physics = env.sim.physics
    decimation = env.cfg.decimation

    def physics_only() -> None:
        physics.step(decimation, forward=False)  # what an env step asks of the physics

    physics_only()
    physics_s = time_loop(physics_only, args.steps, "cuda:0")
    forward_s = time_loop(physics.forward, args.steps, "cuda:0")
    print(
        f"graphed env step {step_s * 1e3:.3f} ms (step: {env.step_mode}); "
        f"its physics alone {physics_s * 1e3:.3f} ms ({physics_s / step_s:.0%}); "
        f"the rest (MDP, masked reset, observations, forwards the task reads) "
        f"{max(step_s - physics_s, 0) * 1e3:.3f} ms; "
        f"for scale, one forward {forward_s * 1e3:.3f} ms"
    )


if __name__ == "__main__":
    main()
