"""Training throughput on one process against ``--distributed`` on N (issue 10's scaling table).

    python scripts/benchmarks/distributed_scaling.py --tasks simlab/Cartpole-v0 simlab/Humanoid-Direct-v0 \\
        --num_envs 4096 --max_iterations 300 --nproc 2            # one GPU, then two (one process each)
    python scripts/benchmarks/distributed_scaling.py --device cpu --num_envs 8 --max_iterations 3  # a CPU check

Each run is ``simlab train --library rsl_rl`` in a child process (``--distributed --nproc_per_node N``
for the N-process runs) with ``--num_envs`` worlds per process. From rank 0's TensorBoard log it reads
rsl_rl's ``Perf/total_fps`` (env steps/s over all ranks; the first ``--warmup`` iterations are left out)
and the last ``Train/mean_reward``; the wall time is the training time simlab prints.
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import re
import subprocess
import sys
import tempfile


def _scalars(run_dir: str, tag: str) -> list[float]:
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    events = EventAccumulator(run_dir, size_guidance={"scalars": 0})
    events.Reload()
    return [s.value for s in events.Scalars(tag)] if tag in events.Tags()["scalars"] else []


def run_once(task: str, nproc: int, args: argparse.Namespace, log_root: str) -> dict:
    cmd = [sys.executable, "-m", "simlab", "train", "--task", task, "--library", "rsl_rl", "--headless"]
    cmd += ["--num_envs", str(args.num_envs), "--max_iterations", str(args.max_iterations), "--log_root", log_root]
    if args.device:
        cmd += ["--device", args.device]
    if nproc > 1:
        cmd += ["--distributed", "--nproc_per_node", str(nproc)]
    env = dict(os.environ, NCCL_NVLS_ENABLE="0")
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
    took = re.search(r"Training took ([\d.]+) s", done.stdout)
    (run_dir,) = glob.glob(os.path.join(log_root, "rsl_rl", "*", "*"))
    fps = _scalars(run_dir, "Perf/total_fps")[args.warmup :]
    rewards = _scalars(run_dir, "Train/mean_reward")
    return {
        "task": task,
        "processes": nproc,
        "envs_per_process": args.num_envs,
        "env_steps_per_s": sum(fps) / len(fps) if fps else float("nan"),
        "final_mean_reward": rewards[-1] if rewards else float("nan"),
        "training_s": float(took.group(1)) if took else float("nan"),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tasks", nargs="+", default=["simlab/Cartpole-v0", "simlab/Humanoid-Direct-v0"])
    parser.add_argument("--num_envs", type=int, default=4096, help="Worlds per process.")
    parser.add_argument("--max_iterations", type=int, default=100)
    parser.add_argument("--nproc", type=int, default=2, help="Processes of the distributed run.")
    parser.add_argument("--device", default=None, help="cpu, or the GPU by default.")
    parser.add_argument("--warmup", type=int, default=2, help="Iterations left out of the throughput.")
    parser.add_argument("--json", default=None, help="Write the rows to this JSON file.")
    args = parser.parse_args()

    rows = []
    for task in args.tasks:
        for nproc in (1, args.nproc):
            with tempfile.TemporaryDirectory() as log_root:
                rows.append(run_once(task, nproc, args, log_root))
            print(json.dumps(rows[-1]), flush=True)
    print(f"\n{'task':32} {'procs':>5} {'env steps/s':>14} {'speed-up':>8} {'final reward':>12} {'train s':>8}")
    for row in rows:
        single = next(r for r in rows if r["task"] == row["task"] and r["processes"] == 1)
        print(
            f"{row['task']:32} {row['processes']:5d} {row['env_steps_per_s']:14,.0f} "
            f"{row['env_steps_per_s'] / single['env_steps_per_s']:8.2f} {row['final_mean_reward']:12.2f} "
            f"{row['training_s']:8.1f}"
        )
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
