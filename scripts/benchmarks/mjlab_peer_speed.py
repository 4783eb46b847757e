"""Peer figures: env steps/s of one mjlab task with random actions, on the GPU.

Run in its own process with mjlab on the path (it brings its own MuJoCo), e.g.
    python scripts/benchmarks/mjlab_peer_speed.py Mjlab-Velocity-Flat-Unitree-Go1 4096,16384
The task keeps mjlab's own dt and decimation; the printed line says which they were.
"""

import sys
import time

import mjlab.tasks  # noqa: F401  (registers mjlab's tasks)
import torch
from mjlab.envs import ManagerBasedRlEnv
from mjlab.tasks.registry import load_env_cfg

task, counts = sys.argv[1], [int(n) for n in sys.argv[2].split(",")]
steps = int(sys.argv[3]) if len(sys.argv) > 3 else 100
for num_envs in counts:
    cfg = load_env_cfg(task)
    cfg.scene.num_envs = num_envs
    start = time.perf_counter()
    env = ManagerBasedRlEnv(cfg, device="cuda:0")
    env.reset()
    build_s = time.perf_counter() - start
    action = torch.zeros(num_envs, env.action_manager.total_action_dim, device="cuda:0")
    for _ in range(20):  # warm-up: kernel compilation and graph capture
        env.step(torch.randn_like(action))
    torch.cuda.synchronize()
    start = time.perf_counter()
    for _ in range(steps):
        env.step(torch.randn_like(action))
    torch.cuda.synchronize()
    elapsed = time.perf_counter() - start
    print(
        f"mjlab {task} num_envs={num_envs}: {steps * num_envs / elapsed / 1e6:.3f} M env steps/s, "
        f"{elapsed / steps * 1e3:.2f} ms per env step (dt {cfg.sim.mujoco.timestep}, decimation "
        f"{cfg.decimation}), GPU memory peak {torch.cuda.max_memory_allocated() / 2**20:.0f} MiB (torch), "
        f"build {build_s:.1f} s",
        flush=True,
    )
    del env
    torch.cuda.empty_cache()
    torch.cuda.reset_peak_memory_stats()
