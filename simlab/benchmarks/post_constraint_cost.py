"""Cost of MuJoCo's post-constraint pass in the Shadow hand's env step (the fingertip joint forces).

``simlab/Repose-Cube-Shadow-Direct-v0`` three ways: as registered (nothing reads joint forces); with
the asymmetric critic, whose state holds the fingertips' incoming joint wrenches, and the pass
compiled into the model (simlab's env does this in ``_setup_scene``), so every forward pass runs it;
and with that critic but the pass left out of the model, as Isaac Lab's own env leaves it, so the
backend runs it when the critic reads the wrenches. One env at a time (one simulation per process),
each timed over ``--rounds`` rounds of ``--steps`` steps with random actions.

    simlab bench postconstraint --device cuda:0 --num_envs 8192
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
from unittest import mock

import gymnasium as gym
import torch

import simlab.sim as sim_utils
from simlab.benchmarks.timing import time_loop

TASK = "simlab/Repose-Cube-Shadow-Direct-v0"
VARIANTS = {
    "no joint forces read": (False, True),
    "critic reads them, pass compiled in": (True, True),
    "critic reads them, pass run when read": (True, False),
}
"""name: (the asymmetric critic, the pass compiled into the model)."""


def _make_env(device: str, num_envs: int, critic: bool, compiled_in: bool):
    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils import parse_env_cfg

    sim_utils.SimulationContext.clear_instance()
    cfg = parse_env_cfg(TASK, device=device, num_envs=num_envs)
    cfg.seed = 0
    if critic:
        cfg.asymmetric_obs, cfg.state_space = True, 187  # the OpenAI variant's critic state
    # the env compiles the pass in from _setup_scene: without it, what Isaac Lab's own env does
    skip = contextlib.nullcontext() if compiled_in else mock.patch.object(sim_utils, "compute_body_interaction_forces")
    with skip:
        return gym.make(TASK, cfg=cfg).unwrapped


def _steps_per_second(env, steps: int, rounds: int) -> list[float]:
    generator = torch.Generator(device=env.device).manual_seed(0)
    width = env.single_action_space.shape[-1]

    def step() -> None:
        env.step(2 * torch.rand(env.num_envs, width, generator=generator, device=env.device) - 1)

    for _ in range(10):  # warm-up: the CUDA graph's capture
        step()
    return [env.num_envs / time_loop(step, steps, str(env.device)) for _ in range(rounds)]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="simlab bench postconstraint", description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="cuda:0" if torch.cuda.is_available() else "cpu")
    parser.add_argument("--num_envs", type=int, default=None, help="default: 8192 on the GPU, 64 on the CPU")
    parser.add_argument("--steps", type=int, default=100, help="timed env steps per round")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    num_envs = args.num_envs or (8192 if args.device.startswith("cuda") else 64)
    print(f"{TASK}, {num_envs} envs on {args.device}: env steps/s (median of {args.rounds} rounds)")
    for name, (critic, compiled_in) in VARIANTS.items():
        env = _make_env(args.device, num_envs, critic, compiled_in)
        try:
            env.reset()
            rates = _steps_per_second(env, args.steps, args.rounds)
        finally:
            env.close()
        print(f"  {name:40s} {statistics.median(rates):10.0f}  (rounds {[round(r) for r in rates]})", flush=True)


if __name__ == "__main__":
    main()
