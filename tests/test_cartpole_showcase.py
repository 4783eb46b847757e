"""Isaac Lab's cartpole spaces showcase and the manager-based camera cartpole (issue 41.5).

Oracles: the spaces Isaac Lab's configs declare (written out here), the showcase's action and
observation tables (its config docstrings), and Isaac Lab's own task files
(``tests/ported/isaaclab_cartpole_showcase``, ``tests/ported/isaaclab_cartpole_camera_manager``) run
after the import mapping: the same seed and actions give the same observations as simlab's.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from conftest import rendering_available

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs.utils.spaces import deserialize_space, sample_space
from simlab.tasks.direct.cartpole_showcase.cartpole.cartpole_env import cart_force
from simlab.tasks.utils import registered_task_ids
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry, parse_env_cfg
from simlab.utils.errors import ConfigError
from simlab.utils.io import load_yaml

PORTED = Path(__file__).parent / "ported"
REPO = Path(__file__).parent.parent
N = 2
INF = float("inf")

# the spaces Isaac Lab's showcase configs declare
OBSERVATION = {
    "Box": gym.spaces.Box(-INF, INF, shape=(4,)),
    "Discrete": gym.spaces.Discrete(16),
    "MultiDiscrete": gym.spaces.MultiDiscrete([2, 2, 2, 2]),
    "Dict": gym.spaces.Dict(
        {"joint-positions": gym.spaces.Box(-INF, INF, (2,)), "joint-velocities": gym.spaces.Box(-INF, INF, (2,))}
    ),
    "Tuple": gym.spaces.Tuple((gym.spaces.Box(-INF, INF, (2,)), gym.spaces.Box(-INF, INF, (2,)))),
}
IMAGE = gym.spaces.Box(-INF, INF, shape=(100, 100, 3))
CAMERA_OBSERVATION = {
    "Box": IMAGE,
    "Dict": gym.spaces.Dict({"joint-velocities": gym.spaces.Box(-INF, INF, (2,)), "camera": IMAGE}),
    "Tuple": gym.spaces.Tuple((IMAGE, gym.spaces.Box(-INF, INF, (2,)))),
}
ACTION = {
    "Box": gym.spaces.Box(-1.0, 1.0, shape=(1,)),
    "Discrete": gym.spaces.Discrete(3),
    "MultiDiscrete": gym.spaces.MultiDiscrete([3, 2]),
}
STATE_IDS = [f"simlab/Cartpole-Showcase-{o}-{a}-Direct-v0" for o in OBSERVATION for a in ACTION]
CAMERA_IDS = [f"simlab/Cartpole-Camera-Showcase-{o}-{a}-Direct-v0" for o in CAMERA_OBSERVATION for a in ACTION]
needs_rendering = pytest.mark.skipif(not rendering_available(), reason="no OpenGL context for the cameras")


def _to_numpy(obs, index: int):
    """Env ``index``'s part of a batched observation, as a space's sample looks."""
    if isinstance(obs, dict):
        return {k: _to_numpy(v, index) for k, v in obs.items()}
    if isinstance(obs, tuple):
        return tuple(_to_numpy(v, index) for v in obs)
    value = obs[index].cpu().numpy()
    return value.astype(np.int64) if value.dtype.kind == "i" else value


def _ported_camera_cfg():
    sys.path.insert(0, str(PORTED))
    try:
        from isaaclab_cartpole_camera_manager import cartpole_camera_env_cfg
    finally:
        sys.path.remove(str(PORTED))
    return cartpole_camera_env_cfg


def _build_and_step(task: str, steps: int = 3):
    cfg = parse_env_cfg(task, device="cpu", num_envs=N)
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        obs, _ = env.reset(seed=0)
        for _ in range(steps):
            obs, reward, terminated, truncated, _ = env.step(sample_space(env.single_action_space, "cpu", N))
            assert reward.shape == (N,) and torch.isfinite(reward).all()
        return env.single_observation_space["policy"], env.single_action_space, obs["policy"]
    finally:
        env.close()


def test_every_showcase_pair_is_registered_with_skrl_and_the_cartpole_criterion():
    assert set(registered_task_ids("Showcase")) == set(STATE_IDS + CAMERA_IDS)  # Isaac Lab's 24 pairs
    for task in STATE_IDS + CAMERA_IDS:
        assert criterion_for(task).description == criterion_for("simlab/Cartpole-Direct-v0").description
        agent = load_cfg_from_registry(task, "skrl_cfg_entry_point")
        assert agent is not load_cfg_from_registry(task, "skrl_cfg_entry_point")  # a fresh dict per call
        policy = agent["models"]["policy"]["class"]
        kind = task.split("-")[-3]
        assert policy == {"Box": "GaussianMixin", "Discrete": "CategoricalMixin"}.get(kind, "MultiCategoricalMixin")


@pytest.mark.parametrize("task", STATE_IDS)
def test_showcase_spaces_are_isaac_labs_and_observations_lie_in_them(task):
    obs_kind, act_kind = task.split("-")[-4:-2]
    observation_space, action_space, obs = _build_and_step(task)
    assert observation_space == OBSERVATION[obs_kind] and action_space == ACTION[act_kind]
    for i in range(N):
        assert observation_space.contains(_to_numpy(obs, i)), (task, obs)


@needs_rendering
@pytest.mark.parametrize("task", CAMERA_IDS)
def test_camera_showcase_spaces_are_isaac_labs(task):
    obs_kind, act_kind = task.split("-")[-4:-2]
    observation_space, action_space, obs = _build_and_step(task, steps=2)
    assert observation_space == CAMERA_OBSERVATION[obs_kind] and action_space == ACTION[act_kind]
    assert observation_space.contains(_to_numpy(obs, 0))
    image = obs if obs_kind == "Box" else obs["camera"] if obs_kind == "Dict" else obs[0]
    assert image.abs().max() > 0.05  # a picture, not a blank frame


def test_actions_become_the_tabled_cart_forces():
    discrete = torch.tensor([[0], [1], [2]])
    assert cart_force(discrete, ACTION["Discrete"], 100.0).flatten().tolist() == [0.0, -100.0, 100.0]
    # (size: 0 none, 1 half, 2 full; direction: 0 backwards, 1 forwards)
    multi = torch.tensor([[0, 1], [1, 0], [1, 1], [2, 0], [2, 1]])
    assert cart_force(multi, ACTION["MultiDiscrete"], 100.0).flatten().tolist() == [0.0, -50.0, 50.0, -100.0, 100.0]
    box = torch.tensor([[0.25], [-1.0]])
    assert cart_force(box, ACTION["Box"], 100.0).flatten().tolist() == [25.0, -100.0]


@pytest.mark.parametrize(
    ("obs_kind", "expected"), [("Discrete", [10, 5]), ("MultiDiscrete", [[1, 0, 1, 0], [0, 1, 0, 1]])]
)
def test_discrete_observations_are_the_signs_of_the_joint_states(obs_kind, expected):
    """Env 0: pole +0.1 rad, cart -0.5 m, pole +0.3 rad/s, cart -0.2 m/s: signs + - + - (10 = 0b1010);
    env 1 the opposite (5 = 0b0101)."""
    task = f"simlab/Cartpole-Showcase-{obs_kind}-Box-Direct-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=N)).unwrapped
    try:
        env.reset(seed=0)
        robot = env.cartpole
        pole, cart = robot.find_joints("cart_to_pole")[0][0], robot.find_joints("slider_to_cart")[0][0]
        pos, vel = torch.zeros(N, 2), torch.zeros(N, 2)
        pos[:, pole], pos[:, cart], vel[:, pole], vel[:, cart] = 0.1, -0.5, 0.3, -0.2
        pos[1], vel[1] = -pos[0], -vel[0]
        robot.write_joint_state_to_sim(pos, vel)
        assert env._get_observations()["policy"].tolist() == expected
    finally:
        env.close()


@pytest.mark.parametrize("task", STATE_IDS)
def test_isaac_labs_showcase_task_files_run_as_simlabs(task):
    sys.path.insert(0, str(PORTED))
    try:
        from isaaclab_cartpole_showcase import cartpole_env, cartpole_env_cfg
    finally:
        sys.path.remove(str(PORTED))
    obs_kind, act_kind = task.split("-")[-4:-2]
    ours = parse_env_cfg(task, device="cpu", num_envs=N)
    theirs = getattr(cartpole_env_cfg, f"{obs_kind}{act_kind}EnvCfg")()
    theirs.scene.num_envs, theirs.sim.device = N, "cpu"
    envs = [gym.make(task, cfg=ours).unwrapped, cartpole_env.CartpoleShowcaseEnv(theirs)]
    try:
        assert envs[0].single_observation_space == envs[1].single_observation_space
        assert envs[0].single_action_space == envs[1].single_action_space
        torch.manual_seed(0)
        actions = [sample_space(envs[0].single_action_space, "cpu", N) for _ in range(20)]
        observations = []
        for env in envs:
            obs, _ = env.reset(seed=1)
            seen = [obs["policy"]]
            for action in actions:
                seen.append(env.step(action)[0]["policy"])
            observations.append(seen)
        for a, b in zip(*observations):
            for i in range(N):
                assert repr(_to_numpy(a, i)) == repr(_to_numpy(b, i))
    finally:
        for env in envs:
            env.close()


@pytest.mark.parametrize("pair", ["Discrete-MultiDiscrete", "Dict-Box", "Tuple-Discrete"])
def test_skrl_trains_a_showcase_pair_and_the_run_records_its_spaces(tmp_path, pair):
    task = f"simlab/Cartpole-Showcase-{pair}-Direct-v0"
    command = [sys.executable, "-m", "simlab", "train", "--task", task, "--library", "skrl", "--device", "cpu"]
    command += ["--num_envs", "8", "--headless", "--max_iterations", "1", "--log_root", str(tmp_path)]
    done = subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    env_yaml = next(tmp_path.glob("skrl/*/*/params/env.yaml"))
    written = load_yaml(env_yaml)
    obs_kind, act_kind = pair.split("-")
    # Isaac Lab's format: each space a JSON string that reads back as the space
    assert json.loads(written["observation_space"])["space"] == obs_kind
    assert deserialize_space(written["observation_space"]) == OBSERVATION[obs_kind]
    assert deserialize_space(written["action_space"]) == ACTION[act_kind]
    assert any(name.endswith(".pt") for _, _, files in os.walk(tmp_path) for name in files)
    # play: the skrl policy reads the flattened Dict / Tuple / Discrete observation and acts in the action space
    command = [sys.executable, "-m", "simlab", "play", "--task", task, "--library", "skrl", "--device", "cpu"]
    command += ["--num_envs", "4", "--headless", "--log_root", str(tmp_path), "--use_last_checkpoint"]
    done = subprocess.run(
        [*command, "--steps", "20", "--no_export"], cwd=REPO, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]


@needs_rendering
@pytest.mark.parametrize("kind", ["RGB", "Depth"])
def test_manager_based_camera_cartpole_is_registered_and_isaac_labs_config_runs(kind):
    task = f"simlab/Cartpole-{kind}-v0"
    assert criterion_for(task).description == criterion_for("simlab/Cartpole-v0").description
    for key in ("rl_games_cfg_entry_point", "rsl_rl_cfg_entry_point", "skrl_cfg_entry_point"):
        load_cfg_from_registry(task, key)
    space, _, obs = _build_and_step(task, steps=2)
    assert space.shape == (100, 100, 3 if kind == "RGB" else 1) and obs.shape == (N, *space.shape)
    # Isaac Lab's own config (no ground under the cart) builds and steps with the same spaces
    ported = _ported_camera_cfg()
    cfg = getattr(ported, f"Cartpole{kind}CameraEnvCfg")()
    cfg.scene.num_envs, cfg.sim.device = N, "cpu"
    assert cfg.scene.ground is None
    from simlab.envs import ManagerBasedRLEnv

    env = ManagerBasedRLEnv(cfg=cfg)
    try:
        assert env.single_observation_space["policy"] == space
        env.reset(seed=0)
        obs = env.step(torch.zeros(N, 1))[0]["policy"]
        assert obs.shape == (N, *space.shape) and obs.abs().max() > 0.05
    finally:
        env.close()


@needs_rendering
def test_isaac_labs_frozen_encoder_configs_are_refused_in_one_line():
    """The ResNet-18 and Theia-Tiny variants need downloaded weights: Theia (Hugging Face remote code)
    is refused whatever is installed."""
    from simlab.envs import ManagerBasedRLEnv

    ported = _ported_camera_cfg()
    cfg = ported.CartpoleTheiaTinyCameraEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = N, "cpu"
    with pytest.raises(ConfigError, match="Theia model") as error:
        ManagerBasedRLEnv(cfg=cfg)
    assert "\n" not in str(error.value)
