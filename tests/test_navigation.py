"""ANYmal-C navigation (Isaac Lab's ``Isaac-Navigation-Flat-Anymal-C-v0``): a velocity command fed to
simlab's shipped flat-ground ANYmal-C policy, frozen, read as weights only."""

from __future__ import annotations

import importlib
import json
import os
import pickle
import sys
from pathlib import Path

import gymnasium as gym
import pytest
import torch
from conftest import rendering_available

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.pretrained import POLICY_FILE, pretrained_run_dir
from simlab.tasks.manager_based.navigation.criterion import goal_tracker
from simlab.tasks.manager_based.navigation.mdp import PreTrainedPolicyActionCfg
from simlab.tasks.manager_based.navigation.mdp.pre_trained_policy_action import load_policy, resolve_policy_file
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.utils.assets import ISAACLAB_NUCLEUS_DIR
from simlab.utils.errors import ConfigError, UntrustedFileError

TASK = "simlab/Navigation-Flat-Anymal-C-v0"
PORTED = Path(__file__).parent / "ported"
SHIPPED = os.path.join(pretrained_run_dir("simlab/Velocity-Flat-Anymal-C-v0", "rsl_rl"), POLICY_FILE)


def make_env(num_envs: int, seed: int = 0, **actions):
    cfg = parse_env_cfg(TASK, device="cpu", num_envs=num_envs)
    cfg.seed = seed
    for name, value in actions.items():
        setattr(cfg.actions.pre_trained_policy_action, name, value)
    return gym.make(TASK, cfg=cfg).unwrapped


def test_isaac_lab_policy_path_names_the_shipped_flat_policy():
    assert resolve_policy_file(f"{ISAACLAB_NUCLEUS_DIR}/Policies/ANYmal-C/Blind/policy.pt") == SHIPPED
    with pytest.raises(ConfigError, match=r"remote \(Nucleus\) file .* Policies/ANYmal-C/Blind") as info:
        resolve_policy_file(f"{ISAACLAB_NUCLEUS_DIR}/Policies/ANYmal-D/HeightScan/policy.pt")
    assert "\n" not in str(info.value)


def test_low_level_observations_are_those_the_shipped_policy_was_trained_with():
    """The velocity task's policy group, in its order, as the shipped run's record lists it."""
    with open(os.path.join(os.path.dirname(SHIPPED), "record.json")) as f:
        trained = json.load(f)["observations"]["policy"]
    assert len(trained) == 7, trained
    env = make_env(2)
    term = env.action_manager.get_term("pre_trained_policy_action")
    manager = term._low_level_obs_manager
    assert manager.active_terms["ll_policy"] == trained
    assert manager.group_obs_dim["ll_policy"] == (48,) == (term.policy.obs_dim,)
    env.close()


def test_task_steps_without_host_reads():
    """Nothing in the step reads back from the device (the low-level policy included), so it can be
    captured as one CUDA graph."""
    from simlab.benchmarks import step_ops

    env = make_env(4)
    assert env.graph_blockers() == []
    env.close()
    counter = step_ops.count(TASK, num_envs=4, steps=2, engine="mujoco")
    assert sum(counter.read_backs.values()) == 0, dict(counter.read_backs)
    assert counter.torch_ops["actions/pre_trained_policy_action"] > 0, "the low-level policy runs in the step"


def _walk(env, command: tuple[float, float, float], steps: int) -> tuple[torch.Tensor, torch.Tensor]:
    """Displacement along each robot's initial heading, and base heights after ``steps`` env steps."""
    env.reset()
    robot = env.scene["robot"]
    start, heading = robot.data.root_pos_w.clone(), robot.data.heading_w.clone()
    actions = torch.tensor(command).repeat(env.num_envs, 1)
    for _ in range(steps):
        _, _, terminated, _, _ = env.step(actions)
        assert not terminated.any(), "no robot falls"
    moved = robot.data.root_pos_w[:, :2] - start[:, :2]
    forward = moved[:, 0] * torch.cos(heading) + moved[:, 1] * torch.sin(heading)
    return forward, robot.data.root_pos_w[:, 2]


def test_frozen_low_level_policy_walks_the_commanded_velocity():
    """0.5 m/s forward for 4 s (20 env steps of 0.2 s): about 2 m (measured 2.01-2.08 m on 8 envs);
    told to stand, the robots stay put."""
    env = make_env(8)
    forward, height = _walk(env, (0.5, 0.0, 0.0), steps=20)
    assert (forward > 1.6).all() and (forward < 2.4).all(), forward
    assert (height > 0.45).all(), height
    standing, _ = _walk(env, (0.0, 0.0, 0.0), steps=10)
    assert standing.abs().max() < 0.3, standing
    env.close()


def _play(env, controller, steps: int) -> dict[str, int]:
    hook, counts = goal_tracker()
    obs, _ = env.reset()
    for _ in range(steps):
        actions = controller(obs["policy"][:, 6:10])
        obs, _, _, _, _ = env.step(actions)
        hook(env, obs, actions)
    return counts


def test_a_scripted_controller_reaches_the_goal_pose():
    """Velocity commands proportional to the goal in the base frame (and to the heading error) bring
    the robots to the goal pose within the 8 s episode (measured: 16 of 16 envs within 4 cm and 0.04 rad);
    a zero command does not (the registered criterion judges both)."""

    def towards_goal(command: torch.Tensor) -> torch.Tensor:
        return torch.cat([command[:, :2].clamp(-1, 1), command[:, 3:].clamp(-1, 1)], dim=1)

    env = make_env(8)
    steps = env.max_episode_length + 1
    reached = _play(env, towards_goal, steps)
    assert reached["episodes"] == 8 and reached["success"] >= 7, reached
    standing = _play(env, lambda command: torch.zeros(command.shape[0], 3), steps)
    assert standing["episodes"] == 8 and standing["success"] <= 1, standing
    env.close()


def test_a_policy_of_other_inputs_is_refused_in_one_line(tmp_path):
    path = tmp_path / "policy.pt"
    torch.save({"0.weight": torch.zeros(12, 50), "0.bias": torch.zeros(12)}, path)
    with pytest.raises(ConfigError, match="give 48 values, but the policy .* reads 50") as info:
        make_env(2, policy_path=str(path))
    assert "\n" not in str(info.value)


def test_a_low_level_decimation_that_does_not_divide_the_env_step_is_refused():
    with pytest.raises(ConfigError, match="low_level_decimation=3 must be a positive divisor of the env's decimation"):
        make_env(2, low_level_decimation=3)


def _cfg(path, **kwargs) -> PreTrainedPolicyActionCfg:
    return PreTrainedPolicyActionCfg(asset_name="robot", policy_path=str(path), **kwargs)


def test_a_torchscript_policy_is_refused_and_never_loaded(tmp_path, monkeypatch):
    path = tmp_path / "policy.pt"
    torch.jit.save(torch.jit.script(torch.nn.Linear(48, 12)), str(path))
    loads = []
    original = torch.jit.load
    monkeypatch.setattr(torch.jit, "load", lambda *a, **k: loads.append(a) or original(*a, **k))
    with pytest.raises(UntrustedFileError, match="TorchScript file .*trust_policy_file=True") as info:
        load_policy(_cfg(path), "cpu")
    assert "\n" not in str(info.value) and loads == []
    # trusted, it loads as Isaac Lab loads it
    trusted = load_policy(_cfg(path, trust_policy_file=True), "cpu")
    assert loads and trusted(torch.zeros(1, 48)).shape == (1, 12)


class _Payload:
    def __init__(self, marker: str):
        self.marker = marker

    def __reduce__(self):
        return (open, (self.marker, "w"))  # unpickling it would create the marker file


def test_a_pickle_that_runs_code_is_refused_and_never_runs(tmp_path):
    marker = tmp_path / "pwned"
    path = tmp_path / "policy.pt"
    with open(path, "wb") as f:
        pickle.dump({"actor_state_dict": _Payload(str(marker))}, f)
    with pytest.raises(UntrustedFileError, match="more than weights") as info:
        load_policy(_cfg(path), "cpu")
    assert "\n" not in str(info.value)
    assert not marker.exists()


def test_isaac_labs_own_task_file_runs_after_the_import_mapping():
    """Isaac Lab's navigation_env_cfg.py (tests/ported): the same terms as simlab's, and its frozen
    low-level policy walks where the high-level action points."""
    sys.path.insert(0, str(PORTED))
    try:
        module = importlib.import_module("isaaclab_navigation_anymal_c.navigation_env_cfg")
    finally:
        sys.path.remove(str(PORTED))
    cfg = module.NavigationEnvCfg()
    ours = parse_env_cfg(TASK, device="cpu", num_envs=4)
    assert {k: t.weight for k, t in vars(cfg.rewards).items()} == {k: t.weight for k, t in vars(ours.rewards).items()}
    assert cfg.decimation == ours.decimation == 40
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = 4, "cpu", 0
    env = gym.make(TASK, cfg=cfg).unwrapped
    forward, _ = _walk(env, (0.5, 0.0, 0.0), steps=5)
    assert (forward > 0.3).all(), forward
    env.close()


@pytest.mark.parametrize("normalized", [False, True])
def test_the_weights_act_as_rsl_rls_own_actor(tmp_path, normalized):
    """The MLP built from the weights gives rsl_rl's deterministic action for the same state dict
    (the shipped one; with an observation normalizer, random statistics)."""
    rsl_rl_models = pytest.importorskip("rsl_rl.models")
    from tensordict import TensorDict

    from simlab.pretrained.weights import unpack_policy

    obs = torch.randn(5, 48)
    actor = rsl_rl_models.MLPModel(
        TensorDict({"policy": obs}, batch_size=[5]),
        {"actor": ["policy"]},
        "actor",
        12,
        hidden_dims=[128, 128, 128],
        activation="elu",
        obs_normalization=normalized,
        distribution_cfg={"class_name": "GaussianDistribution", "init_std": 1.0, "std_type": "scalar"},
    )
    state = unpack_policy(SHIPPED)[1]["actor_state_dict"]
    if normalized:
        state = {
            **state,
            "obs_normalizer._mean": torch.randn(1, 48),
            "obs_normalizer._var": torch.ones(1, 48),
            "obs_normalizer._std": torch.rand(1, 48) + 0.5,
            "obs_normalizer.count": torch.tensor(100),
        }
    actor.load_state_dict(state)
    path = tmp_path / "model_1.pt"
    torch.save({"actor_state_dict": state, "iter": 1, "infos": None}, path)
    with torch.no_grad():
        expected = actor(TensorDict({"policy": obs}, batch_size=[5]))
    torch.testing.assert_close(load_policy(_cfg(path), "cpu")(obs), expected)


@pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL here")
def test_the_goal_is_drawn_in_renders():
    """The task's ``debug_vis=True`` (Isaac Lab's) draws each goal as a green arrow along its heading."""
    import numpy as np

    cfg = parse_env_cfg(TASK, device="cpu", num_envs=2)
    env = gym.make(TASK, cfg=cfg, render_mode="rgb_array").unwrapped
    env.reset()
    term = env.command_manager.get_term("pose_command")
    term.pos_command_w[:] = env.scene["robot"].data.root_pos_w + torch.tensor([0.0, 0.0, 0.3])  # in view
    drawn = np.asarray(env.render()).astype(np.int32)
    term.set_debug_vis(False)
    plain = np.asarray(env.render()).astype(np.int32)
    env.close()
    changed = np.abs(drawn - plain).sum(-1) > 30
    assert changed.sum() > 50
    green = drawn[changed]
    assert (green[:, 1] > green[:, 0] + 60).mean() > 0.8
