"""Time to a policy: ``simlab train`` from the process start to the first checkpoint that solves the task.

Training is ``simlab train``'s own (:func:`simlab.cli.train.run_train` with rsl_rl); after each
checkpoint the policy is played (``simlab play``'s loader and rollout) on a separate evaluation env
and judged by the criterion the task registers (:mod:`simlab.tasks.utils.criteria`). Training stops
at the first checkpoint that passes. The time to policy is when that checkpoint was written, less the
time spent evaluating the earlier ones: what ``simlab train`` alone would have taken to write it.

The evaluation runs with its own random streams and leaves training's untouched, so a run here
trains as ``simlab train`` with the same seed does; every checkpoint is played from the same
initial states (the seed's).
"""

from __future__ import annotations

import os
import random
import time
from contextlib import contextmanager
from typing import Any

import numpy as np
import torch

from simlab.cli.train import seconds_since_process_start
from simlab.tasks.utils.criteria import criterion_for
from simlab.utils.io import load_yaml
from simlab.utils.startup import cache_report, milestones, phases

SUPPORTED_LIBRARIES = ("rsl_rl",)


@contextmanager
def _own_simulation_and_rng(sim: Any | None, device: str):
    """Make ``sim`` the current SimulationContext and give the block its own random streams.

    simlab keeps one current simulation (Isaac Lab's singleton), and building an env clears the one
    before; the evaluation env lives beside the training env, so each is made current in turn.
    """
    from simlab.sim import SimulationContext

    training_sim = SimulationContext._instance
    SimulationContext._instance = sim
    py_state, np_state = random.getstate(), np.random.get_state()
    devices = [torch.device(device)] if device.startswith("cuda") else []
    try:
        with torch.random.fork_rng(devices=devices):
            yield
    finally:
        random.setstate(py_state)
        np.random.set_state(np_state)
        SimulationContext._instance = training_sim


class CheckpointJudge:
    """The ``on_checkpoint`` hook: plays each new checkpoint and records the timeline of the run."""

    def __init__(
        self,
        task: str,
        library: str,
        device: str,
        eval_envs: int,
        eval_seconds: float,
        seed: int,
        reward_threshold: float | None = None,
        env_overrides: list[str] | None = None,
        agent: str | None = None,
    ):
        self.task, self.library, self.device = task, library, device
        self.agent = agent  # the agent config's registry key (None: the library's default)
        self.env_overrides = list(env_overrides or [])  # the trained env's settings (an image stack, say)
        self.eval_envs, self.eval_seconds, self.seed = eval_envs, eval_seconds, seed
        self.criterion = criterion_for(task, reward_threshold)
        self.evaluations: list[dict[str, Any]] = []
        self.evaluation_seconds = 0.0
        self.solved: dict[str, Any] | None = None
        self._env = self._agent_cfg = self._sim = None

    def _build_eval_env(self) -> None:
        from simlab.cli.libraries import get_library
        from simlab.cli.main import build_parser
        from simlab.cli.session import load_configs, make_env
        from simlab.cli.train import uses_multi_agent_learner

        argv = ["play", "--task", self.task, "--library", self.library, "--headless", "--no_export"]
        argv += ["--num_envs", str(self.eval_envs), "--device", self.device, "--seed", str(self.seed)]
        argv += ["--agent", self.agent] if self.agent else []
        args = build_parser().parse_args(argv)
        env_cfg, agent_cfg = load_configs(args, [*self.env_overrides, *self.criterion.play_overrides])
        get_library(self.library).configure(agent_cfg, args, env_cfg)
        # skrl's IPPO / MAPPO (an --agent config naming one) play the two-agent env, as they trained
        self._env = make_env(args, env_cfg, None, single_agent=not uses_multi_agent_learner(args))
        self._agent_cfg = agent_cfg
        seconds = self.criterion.play_seconds(self.eval_seconds)  # whole episodes where it judges those
        self._steps = max(1, round(seconds / self._env.unwrapped.step_dt))

    def __call__(self, path: str, iteration: int, seconds: dict[str, float]) -> bool:
        if any(e["checkpoint"] == path for e in self.evaluations):  # rsl_rl saves the last one twice
            return False
        saved_at = seconds_since_process_start()
        start = time.perf_counter()
        from simlab.cli.libraries import get_library
        from simlab.cli.play import rollout

        with _own_simulation_and_rng(self._sim, self.device):
            if self._env is None:
                self._build_eval_env()
                from simlab.sim import SimulationContext

                self._sim = SimulationContext._instance
            policy = get_library(self.library).load_policy(self._env, self._agent_cfg, path)
            hook, state = self.criterion.make_hook()
            # every checkpoint starts from the same initial states
            result = rollout(self._env, policy, self._steps, hook, stop_on_interrupt=False, seed=self.seed)
            score, passed = self.criterion.judge(result, state)
        took = time.perf_counter() - start
        entry = {
            "checkpoint": path,
            "iteration": iteration,
            "saved_at_s": saved_at,
            # what `simlab train` alone would have taken: less the evaluations before this one
            "time_to_checkpoint_s": saved_at - self.evaluation_seconds,
            "rollout_s": seconds["rollout"],
            "update_s": seconds["update"],
            "score": score,
            "passed": passed,
            "evaluation_s": took,
        }
        parts = state.get("parts") if isinstance(state, dict) else None  # a criterion's measures behind its score
        if parts:
            entry["parts"] = parts
        self.evaluation_seconds += took
        self.evaluations.append(entry)
        print(
            f"[solve] {os.path.basename(path)} at {entry['time_to_checkpoint_s']:.1f} s: "
            f"score {score:.3f} {'PASS' if passed else 'fail'} (evaluated in {took:.1f} s)"
            + (" [" + ", ".join(f"{name} {value:.3f}" for name, value in parts.items()) + "]" if parts else ""),
            flush=True,
        )
        if passed:
            self.solved = entry
        return passed

    def close(self) -> None:
        if self._env is not None:
            with _own_simulation_and_rng(self._sim, self.device):
                self._env.close()
            self._env = None


def time_to_policy(
    task: str,
    library: str = "rsl_rl",
    device: str = "cpu",
    num_envs: int | None = None,
    max_iterations: int | None = None,
    eval_every: int | None = None,
    seed: int = 42,
    eval_envs: int = 64,
    eval_seconds: float = 5.0,
    reward_threshold: float | None = None,
    log_root: str = "logs",
    overrides: list[str] | None = None,
    resume: str | None = None,
    allow_module: list[str] | None = None,
) -> dict[str, Any]:
    """Train ``task`` until a checkpoint solves it (or ``max_iterations``); one result row.

    ``resume``: a checkpoint to train on from (``simlab train --checkpoint``); ``max_iterations``
    then counts the iterations after it, as in ``simlab train``.

    The start-up share is measured from this process's start, so call it once per process for a
    figure that means what it says (``simlab bench solve`` does).
    """
    if library not in SUPPORTED_LIBRARIES:
        raise ValueError(f"simlab bench solve trains with {list(SUPPORTED_LIBRARIES)}; got --library {library}.")
    from simlab.cli.main import allowed_modules, build_parser
    from simlab.cli.train import run_train
    from simlab.tasks.utils.hydra import env_overrides_in
    from simlab.utils.string import callable_modules

    argv = ["train", "--task", task, "--library", library, "--headless", "--device", device]
    argv += ["--seed", str(seed), "--log_root", log_root, "--run_name", "solve"]
    if num_envs is not None:
        argv += ["--num_envs", str(num_envs)]
    if max_iterations is not None:
        argv += ["--max_iterations", str(max_iterations)]
    if resume is not None:
        argv += ["--checkpoint", resume]
    for module in allow_module or []:
        argv += ["--allow_module", module]
    args = build_parser().parse_args(argv)
    overrides = list(overrides or [])
    if eval_every is not None:
        overrides.append(f"agent.save_interval={eval_every}")
    judge = CheckpointJudge(
        task, library, device, eval_envs, eval_seconds, seed, reward_threshold, env_overrides_in(overrides)
    )
    args.on_checkpoint = judge
    try:
        with callable_modules(allowed_modules(args)):  # as `simlab train`: module:name values of simlab's, the task's
            run_dir = run_train(args, overrides)
    finally:
        judge.close()
    if num_envs is None:  # the task's own count, as the run recorded it
        num_envs = load_yaml(os.path.join(run_dir, "params", "env.yaml"))["scene"]["num_envs"]
    wall = seconds_since_process_start()
    last = judge.solved or (judge.evaluations[-1] if judge.evaluations else None)
    if last is None:
        raise RuntimeError(f"Training {task} wrote no checkpoint; nothing was evaluated.")
    # start-up: process start to the first iteration, i.e. the first checkpoint's time less its training
    startup = judge.evaluations[0]["saved_at_s"] - judge.evaluations[0]["rollout_s"] - judge.evaluations[0]["update_s"]
    shares = {
        "startup_s": startup,
        "rollout_s": last["rollout_s"],
        "update_s": last["update_s"],
        "evaluation_s": judge.evaluation_seconds,
    }
    shares["other_s"] = last["saved_at_s"] + last["evaluation_s"] - sum(shares.values())
    measured = sum(shares.values())  # process start to the end of the last evaluation
    verdict = (
        f"solved at iteration {last['iteration']}: {last['time_to_checkpoint_s']:.1f} s to the policy"
        if judge.solved
        else f"not solved in {last['iteration'] + 1} iterations"
    )
    names = {"startup_s": "start-up", "rollout_s": "rollout", "update_s": "update", "evaluation_s": "evaluation"}
    split = ", ".join(f"{names.get(k, 'other')} {v / measured:.0%}" for k, v in shares.items())
    print(f"[solve] {task}: {verdict}; of {measured:.1f} s: {split}", flush=True)
    reached = milestones()  # simlab train's, from this process's start
    print(
        f"[solve] start-up {startup:.1f} s, reached at (s): " + ", ".join(f"{k} {v:.1f}" for k, v in reached.items()),
        flush=True,
    )
    caches = cache_report()
    print(f"[solve] compiled in this process: {_compiled_text(caches)}", flush=True)
    return {
        "task": task,
        "library": library,
        "device": device,
        "num_envs": num_envs,
        "seed": seed,
        "criterion": judge.criterion.description,
        "run_dir": run_dir,
        "solved": judge.solved is not None,
        "iteration": last["iteration"],
        "score": last["score"],
        "time_to_policy_s": last["time_to_checkpoint_s"] if judge.solved else None,
        "wall_s": wall,
        **shares,
        "startup_milestones_s": reached,
        "startup_phases_s": phases(reached),
        "python_modules_compiled": caches["python_modules_compiled"],
        "warp_kernel_modules_compiled": caches.get("warp_kernel_modules_compiled"),
        "caches": caches,
        "evaluations": judge.evaluations,
    }


def _compiled_text(caches: dict[str, Any]) -> str:
    text = f"{caches['python_modules_compiled']} of {caches['python_modules']} Python modules (no cached bytecode)"
    if "warp_kernel_modules_compiled" in caches:
        text += (
            f", {caches['warp_kernel_modules_compiled']} Warp kernel modules (cache {caches['warp_kernel_cache_dir']} "
            f"holds {caches['warp_kernel_modules_cached']})"
        )
    return text
