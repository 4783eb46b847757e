"""Where one rollout step of ``simlab train``'s rsl_rl loop dispatches its torch ops, by source.

    python scripts/benchmarks/rollout_step_ops.py --device cpu --num_envs 64 [--rollout rsl_rl] [--ops]
    python scripts/benchmarks/rollout_step_ops.py --device cuda:0 --num_envs 4096 [--rollout rsl_rl]

A rollout step is rsl_rl's ``OnPolicyRunner.learn`` body: ``alg.act``, ``env.step`` (simlab's
rsl_rl wrapper around the env), ``alg.process_env_step`` (rsl_rl's reward bootstrap and storage
add) and the logger's ``process_env_step`` (simlab's ``_ProgressLogger``). Each op is counted
under the innermost of these that dispatched it; the env's own step (one CUDA-graph replay on the
GPU, eager on the CPU) is counted apart so that the rest, the runner's glue, shows. Host time per
source is the wall time of its calls (at a few envs on the CPU it is mostly Python and dispatch);
on CUDA a second timed run waits for the GPU before and after each labelled call, so that its
time includes its GPU work (that loop runs slower than the unsynchronised one; the sum of its
column is the step's time when nothing overlaps). ``--rollout fast`` is simlab's
rollout step (``agent.fast_rollout``), ``rsl_rl`` rsl_rl's ``process_env_step`` and the logger's own.
"""

from __future__ import annotations

import argparse
import collections
import functools
import tempfile
import time

import gymnasium as gym
import torch
from torch.utils._python_dispatch import TorchDispatchMode

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.cli.libraries.rsl_rl import install_progress_logger, make_runner, use_fast_rollout
from simlab.tasks.utils import load_cfg_from_registry, parse_env_cfg

READ_BACKS = ("aten._local_scalar_dense", "aten.nonzero")


class SourceCounter(TorchDispatchMode):
    """Counts dispatched torch ops and host seconds under the innermost labelled call."""

    def __init__(self):
        super().__init__()
        self.sync = False  # wait for the GPU around each labelled call
        self.ops: dict[str, collections.Counter[str]] = collections.defaultdict(collections.Counter)
        self.seconds: collections.Counter[str] = collections.Counter()
        self.stack = ["outside"]

    def __torch_dispatch__(self, func, types, args=(), kwargs=None):
        self.ops[self.stack[-1]][str(func)] += 1
        return func(*args, **(kwargs or {}))

    def label(self, owner, name: str, source: str) -> None:
        """Count ``owner.name``'s calls under ``source`` (its own time excludes labelled callees)."""
        call = getattr(owner, name)

        @functools.wraps(call)
        def labelled(*args, **kwargs):
            self.stack.append(source)
            if self.sync:
                torch.cuda.synchronize()
            start = time.perf_counter()
            try:
                return call(*args, **kwargs)
            finally:
                if self.sync:
                    torch.cuda.synchronize()
                spent = time.perf_counter() - start
                self.stack.pop()
                self.seconds[source] += spent
                if len(self.stack) > 1:
                    self.seconds[self.stack[-1]] -= spent  # the caller's own time excludes this call

        setattr(owner, name, labelled)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--task", default="simlab/Cartpole-v0")
    parser.add_argument("--num_envs", type=int, default=64)
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--rollout", choices=("fast", "rsl_rl"), default="fast")
    parser.add_argument("--iterations", type=int, default=3, help="timed iterations (after two warm-up ones)")
    parser.add_argument("--ops", action="store_true", help="list each source's ops")
    args = parser.parse_args()

    env = gym.make(args.task, cfg=parse_env_cfg(args.task, device=args.device, num_envs=args.num_envs))
    agent_cfg = load_cfg_from_registry(args.task, "rsl_rl_cfg_entry_point")
    agent_cfg.device = args.device
    agent_cfg.fast_rollout = args.rollout == "fast"
    runner = make_runner(env, agent_cfg, log_dir=None)
    # simlab train's logger, writing to a throw-away folder
    install_progress_logger(runner, tempfile.mkdtemp(prefix="rollout_ops_"))
    kind = use_fast_rollout(runner, agent_cfg.fast_rollout)
    runner.learn(num_learning_iterations=2)  # warm-up: lazy state, first graph captures

    counter = SourceCounter()
    alg, wrapper = runner.alg, runner.env
    counter.label(alg, "act", "policy (alg.act)")
    counter.label(wrapper, "step", "simlab wrapper (env.step)")
    counter.label(wrapper.unwrapped, "step", "the env's own step (excluded)")
    step_owner = "simlab" if args.rollout == "fast" else "rsl_rl"
    counter.label(alg, "process_env_step", f"process_env_step ({step_owner})")
    counter.label(alg.storage, "add_transition", "rsl_rl storage add")
    counter.label(runner.logger, "process_env_step", "simlab logger")
    runner.logger.log = lambda **_: runner.logger._flush_finished()  # no TensorBoard writes in the count
    runner.logger.init_logging_writer = lambda: None  # the warm-up's writer (no git state saved per learn call)
    runner.save = lambda *a, **k: None
    counter.label(alg, "update", "PPO update (per iteration)")
    counter.label(runner.logger, "log", "logger flush (per iteration)")
    counter.label(alg, "compute_returns", "compute returns (per iteration)")
    counter.label(runner, "learn", "runner loop")
    with counter:  # ops (counting slows every op down: times come from the next runs)
        runner.learn(num_learning_iterations=args.iterations)
    counter.seconds.clear()
    start = time.perf_counter()
    runner.learn(num_learning_iterations=args.iterations)
    iteration_seconds = (time.perf_counter() - start) / args.iterations
    host_seconds = dict(counter.seconds)
    synced_seconds = {}
    if torch.device(args.device).type == "cuda":
        counter.seconds.clear()
        counter.sync = True
        runner.learn(num_learning_iterations=args.iterations)
        synced_seconds = dict(counter.seconds)

    steps = args.iterations * agent_cfg.num_steps_per_env
    print(
        f"{args.task}, {args.num_envs} envs on {args.device}; update: {runner.update_kind}; policy: {runner.act_kind}"
    )
    print(f"rollout step: {kind}; an iteration ({agent_cfg.num_steps_per_env} steps): {iteration_seconds:.4f} s")
    synced = " GPU-synced ms" if synced_seconds else ""
    print(f"  per rollout step (per iteration where said):  ops  read-backs   host ms{synced}")
    totals = [0.0, 0.0, 0.0]
    for source in sorted(set(counter.ops) | set(host_seconds), key=lambda s: ("iteration" in s, "excluded" in s, s)):
        ops, per = counter.ops[source], args.iterations if "iteration" in source else steps
        n, reads = sum(ops.values()) / per, sum(c for k, c in ops.items() if k.startswith(READ_BACKS)) / per
        ms = 1e3 * host_seconds.get(source, 0.0) / per
        synced_ms = 1e3 * synced_seconds.get(source, 0.0) / per
        if "iteration" not in source and "excluded" not in source:
            totals = [totals[0] + n, totals[1] + ms, totals[2] + synced_ms]
        synced = f" {synced_ms:13.3f}" if synced_seconds else ""
        print(f"  {source:34s} {n:8.1f} {reads:10.1f} {ms:9.3f}{synced}")
        if args.ops and "iteration" not in source and "excluded" not in source:
            print("      " + ", ".join(f"{name.removeprefix('aten.')} {c / steps:g}" for name, c in ops.most_common()))
    synced = f" {totals[2]:13.3f}" if synced_seconds else ""
    print(f"  {'rollout step without the env step':34s} {totals[0]:8.1f} {'':10s} {totals[1]:9.3f}{synced}")
    env.close()


if __name__ == "__main__":
    main()
