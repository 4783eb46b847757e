"""skrl on torch beside skrl on JAX: training throughput in one run, and the hand-over between them.

    python scripts/benchmarks/skrl_frameworks.py --device cuda:0 --num_envs 4096
    python scripts/benchmarks/skrl_frameworks.py --device cpu --num_envs 64 --iterations 5 25 --rounds 1

Each framework trains the task with ``simlab train --library skrl --ml_framework <f>`` in a child
process, twice per round: ``--iterations`` short and long. The throughput is the difference of the
two runs' training times, so start-up, JAX's compilation and the first iterations' warm-up drop
out: env steps/s = (long - short) iterations x rollouts x envs / (long time - short time). Rounds
alternate the frameworks, so a noisy machine shifts both alike; the ratio is JAX over torch.

The hand-over check builds the env once, wraps it with skrl's JAX wrapper (as ``simlab train``
does) and steps it: on a GPU the observations JAX receives should live on the GPU, at the same
address as the torch tensor the env wrote (DLPack, no copy through the host).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

FRAMEWORKS = ("torch", "jax")
TOOK = re.compile(r"\[simlab\] Training took ([0-9.]+) s")


def train_seconds(task: str, framework: str, device: str, num_envs: int, iterations: int, log_root: str) -> float:
    """Training time (s, start-up excluded) that ``simlab train`` reports for one run."""
    cmd = [sys.executable, "-m", "simlab.cli.main", "train", "--task", task, "--library", "skrl",
           "--ml_framework", framework, "--headless", "--device", device, "--num_envs", str(num_envs),
           "--max_iterations", str(iterations), "--seed", "42", "--log_root", log_root]  # fmt: skip
    out = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "TQDM_DISABLE": "1"})
    match = TOOK.search(out.stdout)
    if out.returncode != 0 or match is None:
        sys.exit(f"{' '.join(cmd)} failed (exit {out.returncode}):\n{out.stdout[-2000:]}\n{out.stderr[-3000:]}")
    return float(match.group(1))


def handover(task: str, device: str) -> dict:
    """Step the env through skrl's JAX wrapper once; where do the observations JAX sees live?"""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401  (registers the tasks)
    from simlab.cli.libraries.skrl import _runner_class, _wrap
    from simlab.tasks.utils import parse_env_cfg

    _runner_class("jax")  # the same JAX set-up as `simlab train --ml_framework jax`
    import jax

    env = _wrap(gym.make(task, cfg=parse_env_cfg(task, device=device, num_envs=8)), "jax")
    env.reset()
    actions = jax.numpy.zeros((8, env.action_space.shape[0]), device=env.device)
    observations, reward, *_ = env.step(actions)
    written = env._env.unwrapped.obs_buf["policy"]  # the torch tensor the env wrote this step
    report = {
        "jax_backend": jax.default_backend(),
        "observation_device": str(next(iter(observations.devices()))),
        "reward_device": str(next(iter(reward.devices()))),
        "same_buffer_as_env": observations.unsafe_buffer_pointer() == written.data_ptr(),
    }
    env.close()
    return report


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--task", default="simlab/Cartpole-v0")
    parser.add_argument("--device", default="cuda:0")
    parser.add_argument("--num_envs", type=int, default=4096)
    parser.add_argument("--iterations", type=int, nargs=2, default=[20, 120], metavar=("SHORT", "LONG"))
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--json", default=None, help="Also write the figures here.")
    parser.add_argument("--handover_only", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.handover_only:
        print(json.dumps(handover(args.task, args.device)))
        return 0
    short, long = args.iterations
    if not 0 < short < long:
        parser.error(f"--iterations needs 0 < SHORT < LONG; got {short} {long}.")

    import simlab.tasks  # noqa: F401
    from simlab.tasks.utils import load_cfg_from_registry

    rollouts = load_cfg_from_registry(args.task, "skrl_cfg_entry_point")["agent"]["rollouts"]
    steps = (long - short) * rollouts * args.num_envs
    rates: dict[str, list[float]] = {f: [] for f in FRAMEWORKS}
    with tempfile.TemporaryDirectory() as log_root:
        for round_ in range(args.rounds):
            for framework in FRAMEWORKS if round_ % 2 == 0 else FRAMEWORKS[::-1]:
                t_short = train_seconds(args.task, framework, args.device, args.num_envs, short, log_root)
                t_long = train_seconds(args.task, framework, args.device, args.num_envs, long, log_root)
                rates[framework].append(steps / (t_long - t_short))
                print(f"round {round_ + 1} {framework:5s}: {short} its {t_short:.2f} s, {long} its {t_long:.2f} s "
                      f"-> {rates[framework][-1]:,.0f} env steps/s", flush=True)  # fmt: skip
    check = subprocess.run([sys.executable, __file__, "--handover_only", "--task", args.task, "--device", args.device],
                           capture_output=True, text=True)  # fmt: skip
    failed = {"error": check.stderr[-1500:]}
    hand = json.loads(check.stdout.strip().splitlines()[-1]) if check.returncode == 0 else failed
    best = {f: max(r) for f, r in rates.items()}
    result = {
        "task": args.task, "device": args.device, "num_envs": args.num_envs, "rollouts": rollouts,
        "iterations": [short, long], "env_steps_per_s": rates, "best": best,
        "jax_over_torch": best["jax"] / best["torch"], "handover": hand,
    }  # fmt: skip
    print(f"\nskrl on {args.device}, {args.task}, {args.num_envs} envs (best of {args.rounds} rounds):")
    for framework in FRAMEWORKS:
        print(f"  {framework:5s} {best[framework]:>12,.0f} env steps/s")
    print(f"  jax / torch: {result['jax_over_torch']:.2f}")
    print(f"  hand-over: {hand}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
