"""How much work one rsl_rl PPO update and one rollout step dispatch: torch ops counted per call.

    simlab bench ops update --task simlab/Cartpole-v0 --device cpu [--update rsl_rl]

On the GPU each dispatched op is a kernel launch (or a host read-back, counted apart), so these
counts bound how fast an iteration can run when the host, not the GPU, is the limit. The runner
is built as ``simlab train`` builds it.
"""

from __future__ import annotations

import argparse
import collections
import tempfile

import gymnasium as gym
import torch
from torch.utils._python_dispatch import TorchDispatchMode

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.cli.libraries.rsl_rl import install_progress_logger, make_runner
from simlab.tasks.utils import load_cfg_from_registry, parse_env_cfg

READ_BACKS = ("aten._local_scalar_dense", "aten.nonzero")


class OpCounter(TorchDispatchMode):
    """Counts the torch ops dispatched inside the ``with`` block."""

    def __init__(self):
        super().__init__()
        self.ops: collections.Counter[str] = collections.Counter()

    def __torch_dispatch__(self, func, types, args=(), kwargs=None):
        self.ops[str(func)] += 1
        return func(*args, **(kwargs or {}))

    @property
    def total(self) -> int:
        return sum(self.ops.values())

    @property
    def read_backs(self) -> int:
        return sum(n for name, n in self.ops.items() if name.startswith(READ_BACKS))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="simlab bench ops update", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--task", default="simlab/Cartpole-v0")
    parser.add_argument("--num_envs", type=int, default=256)
    parser.add_argument("--device", default="cpu")
    parser.add_argument(
        "--update",
        choices=("fast", "rsl_rl"),
        default="fast",
        help="simlab's fast PPO update (and on CUDA the rollout's policy and step as CUDA graphs) or rsl_rl's own",
    )
    args = parser.parse_args(argv)

    env = gym.make(args.task, cfg=parse_env_cfg(args.task, device=args.device, num_envs=args.num_envs))
    agent_cfg = load_cfg_from_registry(args.task, "rsl_rl_cfg_entry_point")
    agent_cfg.device = args.device
    agent_cfg.fast_update = args.update == "fast"
    agent_cfg.graph_act = None if args.update == "fast" else False  # fast: the rollout's policy graphed on CUDA
    runner = make_runner(env, agent_cfg, log_dir=None)
    # simlab train's logger (it keeps finished episodes on the device), writing to a throw-away folder
    install_progress_logger(runner, tempfile.mkdtemp(prefix="update_ops_"))
    runner.learn(num_learning_iterations=1)  # warm-up: lazy state, first graph capture
    alg, obs = runner.alg, runner.env.get_observations()

    rollout = OpCounter()
    with torch.inference_mode():
        for _ in range(agent_cfg.num_steps_per_env):
            with rollout:
                obs, rewards, dones, extras = runner.env.step(alg.act(obs))
                alg.process_env_step(obs, rewards, dones, extras)
                runner.logger.process_env_step(rewards, dones, extras)
        alg.compute_returns(obs)
    update = OpCounter()
    with update:
        alg.update()

    mini_batches = agent_cfg.algorithm.num_learning_epochs * agent_cfg.algorithm.num_mini_batches
    steps = agent_cfg.num_steps_per_env
    print(f"{args.task} on {args.device}, rsl_rl {agent_cfg.algorithm.class_name}, {args.update} update:")
    print(
        f"  rollout step (policy, env step, storage, logging): {rollout.total / steps:.0f} ops, "
        f"{rollout.read_backs / steps:.1f} host read-backs"
    )
    print(
        f"  PPO update: {update.total} ops in {mini_batches} mini-batches ({update.total / mini_batches:.0f} each), "
        f"{update.read_backs / mini_batches:.0f} host read-backs each"
    )
    for name, count in update.ops.most_common(8):
        print(f"    {count:6d}  {name}")
    env.close()


if __name__ == "__main__":
    main()
