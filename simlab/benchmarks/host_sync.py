"""What the env step's host read costs in rsl_rl training: the episode-log flag read every step
against the flags read once per iteration (``ManagerBasedRLEnv.log_refresh_on_device``).

    simlab bench ops sync --device cuda:0 --num_envs 4096 --iterations 20 --rounds 3

One env and one rsl_rl runner, built as ``simlab bench train`` builds them (the agent config's
PPO update and act: on CUDA simlab's fast update and act graph). Rounds alternate the two
settings; each times ``--iterations`` whole iterations (rollout and update, the device synchronised
before and after) and prints env steps/s. Learning does not depend on the setting (logging only;
tests/test_startup_and_rollout_syncs.py checks the weights and the logged values).
"""

from __future__ import annotations

import argparse
import statistics
import time

from simlab.benchmarks.env_suites import make_env
from simlab.benchmarks.timing import synchronize
from simlab.cli.libraries.rsl_rl import make_runner
from simlab.tasks.utils import load_cfg_from_registry


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="simlab bench ops sync", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--task", default="simlab/Cartpole-v0", help="a manager-based task")
    parser.add_argument("--device", default="cuda:0")
    parser.add_argument("--num_envs", type=int, default=4096)
    parser.add_argument("--iterations", type=int, default=20, help="timed iterations per round and setting")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)

    env = make_env(args.task, args.num_envs, args.device)
    if not hasattr(env, "log_refresh_on_device"):
        raise SystemExit(f"{args.task} is not a manager-based task: its step reads no log flag")
    agent_cfg = load_cfg_from_registry(args.task, "rsl_rl_cfg_entry_point")
    agent_cfg.device = str(env.device)
    runner = make_runner(env, agent_cfg, log_dir=None)
    print(
        f"{args.task} on {env.device}, {args.num_envs} envs; PPO update: {runner.update_kind}; act: {runner.act_kind}"
    )
    runner.learn(num_learning_iterations=2)  # warm-up: graph captures, allocator
    settings = {"flag read every step": False, "flags read per iteration": True}
    rates: dict[str, list[float]] = {name: [] for name in settings}
    steps = agent_cfg.num_steps_per_env * args.num_envs * args.iterations
    for r in range(args.rounds):
        for name, on_device in settings.items():
            env.log_refresh_on_device = on_device
            synchronize(args.device)
            start = time.perf_counter()
            runner.learn(num_learning_iterations=args.iterations)
            synchronize(args.device)
            rates[name].append(steps / (time.perf_counter() - start))
            print(f"round {r + 1} {name:>24}: {rates[name][-1]:,.0f} env steps/s", flush=True)
    medians = {name: statistics.median(values) for name, values in rates.items()}
    for name, value in medians.items():
        print(f"median {name:>24}: {value:,.0f} env steps/s")
    ratio = medians["flags read per iteration"] / medians["flag read every step"]
    print(f"per iteration / every step: {ratio:.3f}")
    env.close()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
