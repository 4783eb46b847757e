"""What train, play, random and zero share: configs from the registry + flags + overrides, and the env."""

from __future__ import annotations

import argparse
import math
import os
import warnings
from typing import Any

import gymnasium as gym

from simlab.rl.utils import is_multi_agent
from simlab.tasks.utils import apply_overrides, load_cfg_from_registry
from simlab.utils.errors import ConfigError
from simlab.viewer.choice import check_viewer_flags

__all__ = [
    "ONE_VIDEO_INTERVAL",
    "LIBRARIES",
    "agent_entry_point",
    "check_at_least",
    "check_flags",
    "check_mini_batches",
    "check_training_settings",
    "load_configs",
    "make_env",
    "resolve_seed",
]

ONE_VIDEO_INTERVAL = 10**12  # a --video_interval no run reaches: one video, from the first step (play)
VIDEO_FPS = 30  # frames per simulated second of the recorded videos, at most

LIBRARIES = ("rsl_rl", "skrl", "sb3", "rl_games", "bc")  # bc: play a behaviour-cloned policy (simlab.rl.bc)
SKRL_ALGORITHMS = ("PPO", "AMP", "IPPO", "MAPPO")


def agent_entry_point(library: str, algorithm: str | None) -> str:
    """The registry key of the agent config for ``library`` (and skrl's ``algorithm``)."""
    if library not in LIBRARIES:
        raise ConfigError(f"Unknown library '{library}'. Choose one of {list(LIBRARIES)}.")
    algo = (algorithm or "PPO").upper()
    if library == "skrl":
        if algo not in SKRL_ALGORITHMS:
            raise ConfigError(f"--algorithm '{algorithm}' is not one of skrl's {list(SKRL_ALGORITHMS)}.")
        return "skrl_cfg_entry_point" if algo == "PPO" else f"skrl_{algo.lower()}_cfg_entry_point"
    if algo != "PPO":
        raise ConfigError(f"--algorithm {algorithm} is for skrl only; {library} trains PPO.")
    return f"{library}_cfg_entry_point"


def check_flags(args: argparse.Namespace) -> None:
    """Refuse flag values that would run nothing or cut videos short, before anything is built or written."""

    def at_least_one(flag: str) -> None:
        value = getattr(args, flag, None)
        if value is not None and value < 1:
            raise ConfigError(f"--{flag} must be at least 1, got {value}.")

    for flag in ("num_envs", "max_iterations", "steps"):
        at_least_one(flag)
    if hasattr(args, "viewer_port"):
        check_viewer_flags(args.viewer, args.viewer_port, args.viewer_host, args.headless)
    seconds = getattr(args, "seconds", None)
    if seconds is not None and args.steps is not None:
        raise ConfigError("--seconds and --steps both set how long to play: give one of them.")
    if seconds is not None and not seconds > 0:
        raise ConfigError(f"--seconds must be > 0 (simulated seconds), got {seconds}.")
    if getattr(args, "video", False):
        at_least_one("video_length")
        at_least_one("video_interval")
        if args.command == "train" and args.video_length > args.video_interval:
            raise ConfigError(
                f"--video_length {args.video_length} is longer than --video_interval {args.video_interval}: "
                "each recording would be cut off by the next one. Use a video_length <= video_interval."
            )


def check_training_settings(args: argparse.Namespace, counts: dict[str, Any], rates: dict[str, Any]) -> None:
    """When training, refuse agent settings an override can break before the library trips on them deep
    inside (or trains nothing): ``counts`` (rollout steps, epochs, mini-batches, iterations) must be whole
    numbers >= 1, ``rates`` (learning rates) finite numbers >= 0. Both map an override key to its value
    (None: the config has no such setting; a rate given as text, an SB3 schedule, is the library's)."""
    if not hasattr(args, "max_iterations"):
        return
    for key, value in counts.items():
        whole = isinstance(value, (int, float)) and not isinstance(value, bool) and float(value).is_integer()
        if value is not None and not (whole and value >= 1):
            raise ConfigError(f"{key} must be a whole number >= 1 to train, got {value!r}.")
    for key, value in rates.items():
        if isinstance(value, (int, float)) and not (math.isfinite(value) and value >= 0):
            raise ConfigError(f"{key} must be a finite number >= 0, got {value!r}.")


def check_mini_batches(args: argparse.Namespace, key: str, mini_batches: Any, samples: int, rollout: str) -> None:
    """When training, refuse more mini-batches than a rollout holds samples: each would be empty and the
    library would train on nothing (rsl_rl's losses turn NaN, skrl's updates fail). ``rollout`` says how
    the ``samples`` arise (``"8 envs x 16 steps"``)."""
    if not hasattr(args, "max_iterations") or not isinstance(mini_batches, (int, float)) or mini_batches <= samples:
        return
    raise ConfigError(
        f"{key}={mini_batches:g} leaves the mini-batches empty: a rollout holds {samples} samples ({rollout}). "
        f"Use at most {key}={samples}, or more envs or rollout steps."
    )


def check_at_least(args: argparse.Namespace, key: str, value: Any, least: int, why: str) -> None:
    """When training, refuse a ``value`` of ``key`` below ``least``, saying ``why`` the library needs that many."""
    if hasattr(args, "max_iterations") and isinstance(value, (int, float)) and value < least:
        raise ConfigError(f"{key}={value:g} is too small: {why}. Use at least {least}.")


def resolve_seed(seed: int | None) -> int | None:
    """-1 draws a random seed; None keeps the config's."""
    from simlab.utils.seed import set_seed

    if seed is None:
        return None
    return set_seed(seed) if seed == -1 else seed


def _default_to_amp(args: argparse.Namespace) -> None:
    """skrl without ``--algorithm`` on a task that registers only an AMP agent (the AMP humanoids) trains AMP."""
    if args.library != "skrl" or getattr(args, "algorithm", None) or getattr(args, "agent", None):
        return
    try:
        kwargs = gym.spec(args.task).kwargs
    except gym.error.Error:
        return  # load_cfg_from_registry names the unknown task
    if "skrl_cfg_entry_point" not in kwargs and "skrl_amp_cfg_entry_point" in kwargs:
        print(f"[simlab] {args.task} registers skrl's AMP agent only: --algorithm AMP")
        args.algorithm = "AMP"


def _algorithm_of_agent_cfg(args: argparse.Namespace, agent_cfg: Any) -> None:
    """skrl with ``--agent`` and no ``--algorithm`` learns with the algorithm its config names: an IPPO or
    MAPPO config needs the two-agent env (not PPO's single-agent view), an AMP config the motion data."""
    if getattr(args, "library", None) != "skrl" or not getattr(args, "agent", None) or not isinstance(agent_cfg, dict):
        return
    named = str((agent_cfg.get("agent") or {}).get("class", "")).upper()
    if named not in SKRL_ALGORITHMS:
        return
    given = getattr(args, "algorithm", None)
    if given is None:
        args.algorithm = named
    elif given.upper() != named:
        raise ConfigError(
            f"--agent {args.agent} is a skrl {named} config, but --algorithm {given} was given: "
            f"give --algorithm {named}, or leave --algorithm out."
        )


def _library_entry_point(args: argparse.Namespace, presets: list[str]) -> str:
    """The agent entry point of ``--library`` / ``--algorithm``; a task without one is refused naming the
    flags that the task has agents for (the registry's entry-point keys mean nothing on the command line)."""
    from simlab.tasks.utils.parse_cfg import registry_kwargs

    entry_point = agent_entry_point(args.library, args.algorithm)
    kwargs = registry_kwargs(args.task, presets)
    if entry_point in kwargs:
        return entry_point
    flags = []
    for key in sorted(k for k in kwargs if k.endswith("_cfg_entry_point") and k != "env_cfg_entry_point"):
        name = key.removesuffix("_cfg_entry_point")
        if name in LIBRARIES:
            flags.append(f"--library {name}")
        elif name.startswith("skrl_") and name[5:].upper() in SKRL_ALGORITHMS:
            flags.append(f"--library skrl --algorithm {name[5:].upper()}")
        else:  # another config of a library (rsl_rl_with_symmetry)
            flags.append(f"--agent {key}")
    given = f"--library {args.library}" + (f" --algorithm {args.algorithm}" if args.algorithm else "")
    raise ConfigError(f"{args.task} has no agent config for {given}; it has: {', '.join(flags) or 'none'}.")


def load_configs(args: argparse.Namespace, overrides: list[str], with_agent: bool = True) -> tuple[Any, Any]:
    """The env and agent configs of ``args.task``: registry defaults, then overrides, then flags.

    As in Isaac Lab's scripts, a flag that is given (``--num_envs``, ``--device``, ``--seed``)
    wins over the same setting in an override.
    """
    from simlab.tasks.utils.parse_cfg import split_presets
    from simlab.tasks.utils.presets import select_presets
    from simlab.utils.device import resolve_device

    # Isaac Lab 3.0's presets= (simlab.cli.isaaclab3): the task's registered variants pick its entry
    # points, the other names the alternatives of the PresetCfg slots inside its configs
    registered, in_config, table = split_presets(args.task, getattr(args, "presets", None) or ())
    env_cfg = load_cfg_from_registry(args.task, "env_cfg_entry_point", registered)
    agent_cfg = None
    if with_agent:
        _default_to_amp(args)
        entry_point = getattr(args, "agent", None) or _library_entry_point(args, registered)
        agent_cfg = load_cfg_from_registry(args.task, entry_point, registered)
        _algorithm_of_agent_cfg(args, agent_cfg)
    env_cfg, agent_cfg, overrides = select_presets(
        env_cfg, agent_cfg, in_config, getattr(args, "physics", None), overrides, table, args.task
    )
    apply_overrides(env_cfg, agent_cfg, overrides)
    if with_agent:
        _check_policy_group(env_cfg, agent_cfg)
    if getattr(args, "num_envs", None) is not None:
        if args.num_envs < 1:
            raise ConfigError(f"--num_envs must be at least 1, got {args.num_envs}.")
        env_cfg.scene.num_envs = args.num_envs
    if getattr(args, "engine", None) is not None:  # physics= (simlab.cli.isaaclab3)
        env_cfg.sim.engine = args.engine
    if getattr(args, "device", None) is not None:
        env_cfg.sim.device = resolve_device(args.device)
    else:
        env_cfg.sim.device = resolve_device(env_cfg.sim.device)
    envs_set = getattr(args, "num_envs", None) is not None or any(
        text.split("=", 1)[0].lstrip("+~") == "env.scene.num_envs" for text in overrides
    )
    cpu_envs = getattr(env_cfg.scene, "num_envs_cpu", None)
    if cpu_envs is not None and env_cfg.sim.device == "cpu" and not envs_set:
        env_cfg.scene.num_envs = cpu_envs  # the task's CPU default (docs/performance.md, "Time to policy")
    return env_cfg, agent_cfg


def _check_policy_group(env_cfg: Any, agent_cfg: Any) -> None:
    """Refuse a manager-based env whose "policy" observation group an override removed: every learner
    reads it (rsl_rl unless its ``obs_groups`` name other groups), and would fail deep inside."""
    if not hasattr(env_cfg, "observations"):
        return  # a direct env: its policy observations are its own code's
    if getattr(env_cfg.observations, "policy", None) is not None:
        return
    obs_groups = getattr(agent_cfg, "obs_groups", None)
    if obs_groups and all("policy" not in groups for groups in obs_groups.values()):
        return  # rsl_rl reads the groups its obs_groups name
    raise ConfigError(
        "env.observations.policy is None: the learner reads the 'policy' observation group. "
        "Remove single terms instead (env.observations.policy.<term>=null)."
    )


def make_env(args: argparse.Namespace, env_cfg: Any, video_dir: str | None, single_agent: bool) -> gym.Env:
    """``gym.make`` the task (rgb_array rendering with ``--video``), record videos, flatten multi-agent envs."""
    video = bool(getattr(args, "video", False)) and video_dir is not None
    if video:  # the renderer is checked before training starts, not when the first clip is due
        from simlab.envs.utils.viewer import renderer_kind

        warp = env_cfg.sim.device.startswith("cuda") or getattr(env_cfg.sim, "engine", "auto") == "mujoco_warp"
        if renderer_kind(uses_mujoco_warp=warp) == "warp":
            print("[simlab] Videos are rendered with MuJoCo Warp's ray tracer")
        else:
            print(f"[simlab] Videos are rendered with MUJOCO_GL={os.environ.get('MUJOCO_GL')}")
    env = gym.make(args.task, cfg=env_cfg, render_mode="rgb_array" if video else None)
    if single_agent and is_multi_agent(env):
        from simlab.envs import multi_agent_to_single_agent

        env = multi_agent_to_single_agent(env)
    if video:
        interval = int(getattr(args, "video_interval", 2000))
        env = _RecordVideo(
            env,
            video_folder=video_dir,
            step_trigger=lambda step: step % interval == 0,
            video_length=args.video_length,
            name_prefix=_free_video_prefix(video_dir, "rl-video"),
            disable_logger=True,
        )
        every = f"videos every {interval} steps" if interval < ONE_VIDEO_INTERVAL else "video from the first step"
        print(f"[simlab] Recording {args.video_length}-step {every} to {video_dir}")
    return with_viewer(args, env)


def with_viewer(args: argparse.Namespace, env: gym.Env) -> gym.Env:
    """``env`` shown in the live viewer ``--viewer`` asks for (none with ``--headless``); play runs in
    real time, and a velocity task's command is steered from the viewer. A viewer that cannot open
    warns, and the run goes on without it."""
    from simlab.viewer import DEFAULT_HOST, DEFAULT_PORT, ViewerWrapper, open_viewer, resolve_viewer_kind

    kind = resolve_viewer_kind(getattr(args, "viewer", "none"), getattr(args, "headless", True))
    play = getattr(args, "command", None) == "play"
    viewer = open_viewer(
        env.unwrapped,
        kind,
        getattr(args, "viewer_port", DEFAULT_PORT),
        realtime=play,
        host=getattr(args, "viewer_host", DEFAULT_HOST),
        steer=play,
    )
    return env if viewer is None else ViewerWrapper(env, viewer)


def _free_video_prefix(folder: str, base: str) -> str:
    """``base``, or ``base-2``, ``base-3``, ... : a prefix no video in ``folder`` has (so none is overwritten)."""
    names = os.listdir(folder) if os.path.isdir(folder) else []
    prefix, n = base, 1
    while any(name.startswith((f"{prefix}-step-", f"{prefix}-episode-")) for name in names):
        n += 1
        prefix = f"{base}-{n}"
    return prefix


class _RecordVideo(gym.wrappers.RecordVideo):
    """Gymnasium's ``RecordVideo``, at most ``VIDEO_FPS`` frames per simulated second, writing each clip
    atomically into a folder that may already hold clips.

    Gymnasium renders every env step into the clip (``render_fps`` is the step rate, 60 for the
    cartpole); rendering is most of a recording's cost, so only every k-th step is drawn and the clip
    plays at ``render_fps / k``: the same duration with fewer frames. ``video_length`` stays in steps.
    Names never collide (:func:`_free_video_prefix`), so gymnasium's "Overwriting existing videos"
    warning about an existing folder does not apply and is silenced.
    """

    def __init__(self, env: gym.Env, **kwargs: Any):
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*Overwriting existing videos")
            super().__init__(env, **kwargs)
        step_rate = float(self.frames_per_sec)
        self.frame_every = max(1, round(step_rate / VIDEO_FPS))
        self.frames_per_sec = step_rate / self.frame_every
        if self.video_length != float("inf"):
            self.video_length = math.ceil(self.video_length / self.frame_every)  # frames, as gymnasium counts
        self._captures = 0

    def start_recording(self, video_name: str) -> None:
        super().start_recording(video_name)
        self._captures = 0

    def _capture_frame(self) -> None:
        """Gymnasium calls this on each step of a recording: draw every ``frame_every``-th."""
        self._captures += 1
        if (self._captures - 1) % self.frame_every == 0:
            super()._capture_frame()

    def stop_recording(self) -> None:
        name = self._video_name
        temp = f".{name}.{os.getpid()}.tmp"  # moviepy picks the codec from the .mp4 it appends below
        self._video_name = temp
        super().stop_recording()
        written = os.path.join(self.video_folder, f"{temp}.mp4")
        if os.path.isfile(written):
            os.replace(written, os.path.join(self.video_folder, f"{name}.mp4"))
