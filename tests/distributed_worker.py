"""One torchrun process of the distributed tests: ``simlab train`` plus what the test compares afterwards.

    python -m torch.distributed.run --nproc_per_node=2 tests/distributed_worker.py OUT_DIR train ... --distributed

Writes ``OUT_DIR/rank<R>.pt`` with the policy's final weights and the observations of the first env
step. ``SIMLAB_TEST_RANK1_NUM_ENVS`` gives rank 1 another ``--num_envs``; ``SIMLAB_TEST_CRASH_RANK``
makes that rank fail once its env is built.
"""

from __future__ import annotations

import os
import sys

import gymnasium as gym
import torch

import simlab.cli.train as train_module
from simlab.cli.distributed import end_torchrun_worker
from simlab.cli.main import main

RANK = int(os.environ["RANK"])
out_dir, argv = sys.argv[1], sys.argv[2:]
captured: dict = {}


class _FirstStep(gym.Wrapper):
    def step(self, action):
        result = super().step(action)
        obs = result[0]  # {"policy": ...}, or one entry per agent
        captured.setdefault("first_obs", torch.cat([obs[k].reshape(obs[k].shape[0], -1) for k in sorted(obs)], -1))
        return result


def make_env(*args, **kwargs):
    env = _FirstStep(original_make_env(*args, **kwargs))
    if os.environ.get("SIMLAB_TEST_CRASH_RANK") == str(RANK):
        raise RuntimeError(f"test crash on rank {RANK}")
    return env


original_make_env = train_module.make_env
train_module.make_env = make_env

library = argv[argv.index("--library") + 1]
adapter = __import__(f"simlab.cli.libraries.{library}", fromlist=["make_runner"])
original_make_runner = getattr(adapter, "make_runner", None)


def make_runner(*args, **kwargs):
    captured["runner"] = original_make_runner(*args, **kwargs)
    return captured["runner"]


if library == "rl_games":  # the agent is made inside training: keep it when rl_games' factory makes it
    original_runner = adapter._runner

    def _runner(*args, **kwargs):
        runner, wrapped = original_runner(*args, **kwargs)
        create = runner.algo_factory.create

        def create_and_keep(*create_args, **create_kwargs):
            captured["agent"] = create(*create_args, **create_kwargs)
            return captured["agent"]

        runner.algo_factory.create = create_and_keep
        return runner, wrapped

    adapter._runner = _runner
else:
    adapter.make_runner = make_runner

if RANK == 1 and os.environ.get("SIMLAB_TEST_RANK1_NUM_ENVS"):
    argv[argv.index("--num_envs") + 1] = os.environ["SIMLAB_TEST_RANK1_NUM_ENVS"]

code = main(argv)
if code == 0:
    runner = captured.get("runner")
    if library == "rl_games":
        policies = {"model": captured["agent"].model}
    elif library == "rsl_rl":
        policies = {"policy": runner.alg.get_policy()}
    else:  # skrl: PPO's policy, or IPPO / MAPPO's one per agent
        policies = getattr(runner.agent, "policies", None) or {"policy": runner.agent.policy}
    weights = {}
    for name, module in policies.items():
        # rl_games keeps each rank's own observation statistics (its multi_gpu mode averages gradients only)
        tensors = module.named_parameters() if library == "rl_games" else module.state_dict().items()
        weights.update({f"{name}.{k}": v.detach().cpu().clone() for k, v in tensors})
    torch.save({"weights": weights, "first_obs": captured["first_obs"]}, os.path.join(out_dir, f"rank{RANK}.pt"))
# as `simlab train` itself ends a torchrun worker (main(argv) leaves that to its caller): without the
# interpreter's teardown, in which a finished gloo rank sometimes aborted on 2 cores (seen in CI)
end_torchrun_worker(code)
sys.exit(code)
