"""Env-level benchmarks: env step with random actions, with policy inference, and rsl_rl training.

Each measurement builds the registered task at the given env count, so the figures include
everything the task does per step (action processing, decimated physics, MDP terms, resets,
observations). The raw-physics figure is measured on the same compiled model and backend in
alternating rounds, so ``ratio = physics steps/s through the env / raw physics steps/s``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence

import gymnasium as gym
import torch

import simlab.sim as sim_utils

from .timing import gpu_memory_mb, interleaved, reset_gpu_memory_peak, synchronize, warp_memory_mb

DEFAULT_TASKS = ["simlab/Cartpole-v0", "simlab/Cartpole-Direct-v0", "simlab/Ant-Direct-v0", "simlab/Humanoid-Direct-v0"]


def make_env(task: str, num_envs: int, device: str, cuda_graph: bool = True, overrides: Sequence[str] = ()):
    """The task's env at ``num_envs``, with ``overrides`` (``env.*`` ones, as ``simlab train`` takes them:
    ``env.sim.mujoco.njmax=96``) applied to its config: an A/B of a setting in one benchmark."""
    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils import parse_env_cfg
    from simlab.tasks.utils.hydra import apply_overrides

    sim_utils.SimulationContext.clear_instance()
    cfg = parse_env_cfg(task, device=device, num_envs=num_envs)
    cfg.sim.use_cuda_graph = cuda_graph
    apply_overrides(cfg, None, overrides)
    return gym.make(task, cfg=cfg).unwrapped


def _graph_state(env) -> str:
    """'on' when the env step replays as a CUDA graph, 'off' where graphs are not used (the CPU, or
    turned off), else how it runs ('eager (why)' or 'warming up')."""
    if env.step_is_graphed:
        return "on"
    return "off" if not (env.sim.can_capture_steps and env.cfg.sim.use_cuda_graph) else env.step_mode


def _random_actions(env) -> torch.Tensor:
    if hasattr(env, "possible_agents"):  # a multi-agent env: every agent's actions side by side
        dim = int(sum(env.action_spaces[a].shape[0] for a in env.possible_agents))
        return torch.rand(env.num_envs, dim, device=env.device) * 2 - 1
    space = env.single_action_space
    dim = int(sum(s.shape[0] for s in space.values())) if isinstance(space, gym.spaces.Dict) else space.shape[0]
    return torch.rand(env.num_envs, dim, device=env.device) * 2 - 1


def _step_fn(env, policy=None):
    multi_agent = hasattr(env, "possible_agents")
    obs = {"obs": None}

    def step() -> None:
        if policy is not None and obs["obs"] is not None:
            with torch.inference_mode():
                actions = policy(obs["obs"])
        else:
            actions = _random_actions(env)
        if multi_agent:
            sizes = [env.action_spaces[a].shape[0] for a in env.possible_agents]
            actions = dict(zip(env.possible_agents, torch.split(actions, sizes, dim=-1)))
        result = env.step(actions)
        if not multi_agent:
            obs["obs"] = result[0]["policy"]

    return step


def _raw_fn(env):
    physics = env.sim.physics
    ctrl = physics.data("ctrl")

    def raw() -> None:
        ctrl.copy_(torch.rand_like(ctrl) * 2 - 1)
        physics.step(1, forward=False)  # mj_step alone

    return raw


def _mlp_policy(obs_dim: int, act_dim: int) -> torch.nn.Module:
    """rsl_rl's default actor for the state tasks: an MLP of three ELU layers."""
    return torch.nn.Sequential(
        torch.nn.Linear(obs_dim, 256),
        torch.nn.ELU(),
        torch.nn.Linear(256, 128),
        torch.nn.ELU(),
        torch.nn.Linear(128, 64),
        torch.nn.ELU(),
        torch.nn.Linear(64, act_dim),
    )


class _ChannelsFirst(torch.nn.Module):
    def forward(self, images: torch.Tensor) -> torch.Tensor:
        return images.permute(0, 3, 1, 2)


def _image_policy(obs_shape: tuple[int, int, int], act_dim: int) -> torch.nn.Module:
    """The camera tasks' actor (their rl_games / skrl configs): three convolutions, then 512 ELU units."""
    height, width, channels = obs_shape
    features = torch.nn.Sequential(
        _ChannelsFirst(),
        torch.nn.Conv2d(channels, 32, 8, stride=4),
        torch.nn.ReLU(),
        torch.nn.Conv2d(32, 64, 4, stride=2),
        torch.nn.ReLU(),
        torch.nn.Conv2d(64, 64, 3, stride=1),
        torch.nn.ReLU(),
        torch.nn.Flatten(),
    )
    with torch.no_grad():
        size = features(torch.zeros(1, height, width, channels)).shape[1]
    return torch.nn.Sequential(features, torch.nn.Linear(size, 512), torch.nn.ELU(), torch.nn.Linear(512, act_dim))


def _cameras(env) -> list:
    from simlab.sensors import Camera

    return [sensor for sensor in env.scene.sensors.values() if isinstance(sensor, Camera)]


def _render_fn(cameras):
    """One render of every camera (what a step does when its observations read the images)."""

    def render() -> None:
        for camera in cameras:
            camera.update(0.0, force_recompute=True)
            camera.data  # noqa: B018 - reading the data renders

    return render


def _renders_per_step(cameras, step) -> int | None:
    """How many times one env step renders the cameras (2 when the step also computes final observations)."""
    if not cameras:
        return None
    before = int(cameras[0].frame[0])
    step()
    return int(cameras[0].frame[0]) - before


def _plus(value: float | None, extra: float) -> float | None:
    return None if value is None else value + extra


def bench_env(
    task: str,
    num_envs: int,
    device: str,
    steps: int,
    with_policy: bool = False,
    cuda_graph: bool = True,
    overrides: Sequence[str] = (),
) -> dict:
    reset_gpu_memory_peak(device)
    env = make_env(task, num_envs, device, cuda_graph, overrides)
    env.reset()
    policy = None
    if with_policy:
        obs_shape = env.single_observation_space["policy"].shape
        act_dim = _random_actions(env).shape[1]
        policy = (_image_policy(obs_shape, act_dim) if len(obs_shape) == 3 else _mlp_policy(obs_shape[0], act_dim)).to(
            env.device
        )
    step, raw = _step_fn(env, policy), _raw_fn(env)
    variants = {"env": step, "raw": raw}
    cameras = _cameras(env)
    if cameras:
        variants["render"] = _render_fn(cameras)
    decimation = env.cfg.decimation
    for fn in variants.values():
        for _ in range(10):
            fn()
    renders_per_step = _renders_per_step(cameras, step)
    # raw steps one physics step per call; run it `decimation` times per env step's worth.
    seconds = interleaved(variants, steps, device)
    env_rate = num_envs / seconds["env"]
    raw_rate = num_envs / seconds["raw"]
    camera_bytes = sum(camera.device_memory_bytes() for camera in cameras)
    row = {
        "task": task,
        "device": str(env.device),
        "num_envs": num_envs,
        "env_steps_per_s": env_rate,
        "physics_steps_per_s": env_rate * decimation,
        "env_ms_per_step": seconds["env"] * 1e3,
        "raw_physics_steps_per_s": raw_rate,
        "ratio": env_rate * decimation / raw_rate,
        # the physics of one env step alone (its `decimation` raw steps), and the rest of the step's share
        "physics_ms_per_env_step": seconds["raw"] * decimation * 1e3,
        "outside_physics_share": 1.0 - seconds["raw"] * decimation / seconds["env"],
        "gpu_memory_mb": _plus(gpu_memory_mb(env.device, env.sim.physics), camera_bytes / 2**20),
        "warp_memory_mb": warp_memory_mb(env.device, env.sim.physics),
        "render_ms": seconds["render"] * 1e3 if cameras else None,
        "renders_per_step": renders_per_step,
        "render_share": renders_per_step * seconds["render"] / seconds["env"] if cameras else None,
        "policy": with_policy,
        "cuda_graph": _graph_state(env),
        "overrides": " ".join(overrides),
    }
    # last: it changes the env, and its second graph would count in the memory figures; a failure there
    # keeps the row's other figures (and says why)
    try:
        outside = _seconds_without_physics(env, step, steps, device)
    except Exception as err:  # noqa: BLE001 - any failure: the row without this figure
        row["outside_timed_error"] = f"{type(err).__name__}: {err}".splitlines()[0]
        print(
            f"[simlab bench] {task}: the step without its physics failed: {row['outside_timed_error']}", file=sys.stderr
        )
    else:
        row["outside_ms_per_step"] = outside * 1e3
        row["outside_physics_share_timed"] = outside / seconds["env"]
    env.close()
    return row


def _seconds_without_physics(env, step, steps: int, device: str) -> float:
    """Seconds per env step with the physics steps left out: MuJoCo's (or MuJoCo Warp's) step does not
    run, everything else in the step does (resets by mask, the kinematics pass the observations read),
    the graph captured again without it. The time outside the physics, measured directly: the env step
    less a raw physics loop also counts any difference between the two physics loads (the raw loop's
    random ctrl drives contacts and solver iterations otherwise than the task's actions)."""
    physics = env.sim.physics
    physics._step = lambda nstep, forward: None
    env._stepper.recapture()
    for _ in range(10):
        step()
    return interleaved({"outside": step}, steps, device)["outside"]


def bench_train(
    task: str,
    num_envs: int,
    device: str,
    iterations: int,
    cuda_graph: bool = True,
    fast_update: bool | None = None,
) -> dict:
    """Wall time of rsl_rl PPO iterations (rollout + update), after one warm-up iteration.

    ``fast_update``: False runs rsl_rl's own update and act, True simlab's fast update (and the act
    graph on CUDA), None the agent config's choice."""
    from simlab.cli.libraries.rsl_rl import make_runner
    from simlab.tasks.utils import load_cfg_from_registry

    reset_gpu_memory_peak(device)
    env = make_env(task, num_envs, device, cuda_graph)
    agent_cfg = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    agent_cfg.device = str(env.device)
    if fast_update is not None:  # rsl_rl's own code (False) or simlab's fast paths (True; the act graph on CUDA)
        agent_cfg.fast_update = fast_update
        agent_cfg.graph_act = None if fast_update else False
    runner = make_runner(env, agent_cfg, log_dir=None)  # as `simlab train` builds it, without logging
    if hasattr(env, "log_refresh_on_device"):  # as `simlab train` steps it: no log flag read per step
        env.log_refresh_on_device = True
    runner.learn(num_learning_iterations=1)
    synchronize(device)
    start = time.perf_counter()
    runner.learn(num_learning_iterations=iterations)
    synchronize(device)
    seconds = (time.perf_counter() - start) / iterations
    steps_per_iteration = agent_cfg.num_steps_per_env * num_envs
    row = {
        "task": task,
        "device": str(env.device),
        "num_envs": num_envs,
        "iterations": iterations,
        "seconds_per_iteration": seconds,
        "env_steps_per_s": steps_per_iteration / seconds,
        "gpu_memory_mb": gpu_memory_mb(env.device, env.sim.physics),
        "warp_memory_mb": warp_memory_mb(env.device, env.sim.physics),
        "cuda_graph": _graph_state(env),
        "ppo_update": runner.update_kind,
        "rollout_policy": runner.act_kind,
    }
    env.close()
    return row
