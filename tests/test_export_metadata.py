"""Exported ONNX policies carry what a robot-side runner needs (simlab.rl.deploy_metadata).

Each test reads the metadata back from the ONNX file alone and rebuilds from it what the env does:
the joint target of each named joint from an action, and the layout of the policy's input.
"""

from __future__ import annotations

import glob
import json
import os

import gymnasium as gym
import numpy as np
import pytest
import torch

import simlab
import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.cli.main import build_parser, main
from simlab.cli.play import run_play
from simlab.rl.deploy_metadata import deploy_metadata, read_deploy_metadata
from simlab.tasks.utils.parse_cfg import parse_env_cfg

ort = pytest.importorskip("onnxruntime")
onnx = pytest.importorskip("onnx")

CARTPOLE = "simlab/Cartpole-v0"
GO2 = "simlab/Velocity-Flat-Unitree-Go2-v0"
G1 = "simlab/Velocity-Flat-G1-v0"
# what each action-term type sets, and where the articulation keeps it
TARGETS = {"position": "joint_pos_target", "velocity": "joint_vel_target", "effort": "joint_effort_target"}


def _targets_from_metadata(meta: dict, actions: np.ndarray) -> dict[str, np.ndarray]:
    """Joint name -> the target the env sets for ``actions`` (N, A), from the metadata alone."""
    scale, offset = np.array(meta["action_scale"]), np.array(meta["action_offset"])
    target = offset + scale * actions
    for k, clip in enumerate(meta["action_clip"]):
        if clip is not None:
            low, high = (-np.inf if c is None else c for c in clip)
            target[:, k] = np.clip(target[:, k], low, high)
    return {name: target[:, k] for k, name in enumerate(meta["joint_names"])}


def _make_env(task: str, num_envs: int = 3):
    return gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=num_envs))


def _check_action_mapping(env, meta: dict) -> None:
    """Random actions through the env's action manager give the targets the metadata predicts."""
    base = env.unwrapped
    actions = torch.rand(base.num_envs, meta["action_size"], generator=torch.Generator().manual_seed(1)) * 4 - 2
    base.action_manager.process_action(actions)
    base.action_manager.apply_action()
    expected = _targets_from_metadata(meta, actions.numpy())
    for term in meta["action_terms"]:
        robot = base.scene[term["asset_name"]]
        applied = getattr(robot.data, TARGETS[term["target"]])
        for name in term["joint_names"]:
            got = applied[:, robot.joint_names.index(name)].numpy()
            np.testing.assert_allclose(got, expected[name], rtol=1e-6, atol=1e-6, err_msg=name)


def _check_layout(meta: dict, onnx_file: str) -> None:
    """The observation terms tile the policy's input exactly; the time steps agree."""
    (graph_input,) = onnx.load(onnx_file).graph.input
    input_size = graph_input.type.tensor_type.shape.dim[1].dim_value
    terms = meta["observation_terms"]
    assert [t["name"] for t in terms] == meta["observation_names"]
    assert sum(int(np.prod(t["shape"])) for t in terms) == meta["observation_size"] == input_size
    assert [t["slice"][0] for t in terms] == [0] + [t["slice"][1] for t in terms[:-1]]
    assert meta["step_dt"] == pytest.approx(meta["physics_dt"] * meta["decimation"])
    assert meta["simlab_version"] == simlab.__version__
    assert meta["env_type"] == "manager_based"


def test_cartpole_play_export_carries_metadata(tmp_path):
    """``simlab play`` exports with metadata; the ONNX model gives the actions play stepped with."""
    small = ["--task", CARTPOLE, "--num_envs", "4", "--headless", "--device", "cpu", "--log_root", str(tmp_path)]
    assert main(["train", *small, "--max_iterations", "1"]) == 0
    args, rest = build_parser().parse_known_args(["play", *small, "--use_last_checkpoint", "--steps", "4"])
    seen: list[tuple[np.ndarray, np.ndarray]] = []  # (observation, the action the policy gave for it)
    last: dict = {}

    def record(env, obs, actions):
        if "obs" in last:
            seen.append((last["obs"], actions.detach().cpu().numpy()))
        last["obs"] = obs["policy"].detach().cpu().numpy().copy()

    result = run_play(args, rest, on_step=record)
    (onnx_file,) = [f for f in result["exported"] if f.endswith(".onnx")]
    meta = read_deploy_metadata(onnx_file)
    assert meta["task"] == CARTPOLE and meta["joint_names"] == ["slider_to_cart"]
    assert meta["action_terms"][0]["type"] == "JointEffortAction" and meta["action_scale"] == [100.0]
    _check_layout(meta, onnx_file)

    session = ort.InferenceSession(onnx_file)
    assert len(seen) == 3
    for obs, actions in seen:
        (onnx_actions,) = session.run(["actions"], {"obs": obs.astype(np.float32)})
        np.testing.assert_allclose(onnx_actions, actions, atol=1e-5)

    env = _make_env(CARTPOLE)
    try:
        _check_action_mapping(env, meta)
    finally:
        env.close()
    assert glob.glob(os.path.join(tmp_path, "rsl_rl", "*", "*", "exported", "policy.onnx"))


@pytest.mark.parametrize(("task", "num_joints"), [(GO2, 12), (G1, 23)], ids=["go2", "g1"])
def test_locomotion_metadata_rebuilds_joint_targets(tmp_path, task, num_joints):
    """A locomotion policy: joint position targets = default pose + scale * action, PD gains per joint."""
    from rsl_rl.models import MLPModel
    from tensordict import TensorDict

    from simlab.rl.rsl_rl import export_policy_as_onnx

    env = _make_env(task)
    try:
        obs, _ = env.reset(seed=0)
        policy_obs = obs["policy"]
        actor = MLPModel(
            TensorDict({"policy": policy_obs}, batch_size=[policy_obs.shape[0]]),
            {"actor": ["policy"]},
            "actor",
            env.unwrapped.action_manager.total_action_dim,
            hidden_dims=[32],
            obs_normalization=True,
            distribution_cfg={"class_name": "GaussianDistribution", "init_std": 1.0},
        )
        actor.update_normalization(TensorDict({"policy": policy_obs * 2 + 1}, batch_size=[policy_obs.shape[0]]))
        actor.eval()
        onnx_file = export_policy_as_onnx(actor, str(tmp_path), metadata=deploy_metadata(env, task))
        meta = read_deploy_metadata(onnx_file)
        _check_layout(meta, onnx_file)
        _check_action_mapping(env, meta)

        robot = env.unwrapped.scene["robot"]
        ids = [robot.joint_names.index(n) for n in meta["joint_names"]]
        assert len(ids) == num_joints and meta["action_terms"][0]["type"] == "JointPositionAction"
        default = robot.data.default_joint_pos[0, ids].numpy()
        np.testing.assert_allclose(meta["default_joint_pos"], default)
        np.testing.assert_allclose(meta["action_offset"], default)  # use_default_offset: target = default + scale * a
        np.testing.assert_allclose(meta["joint_stiffness"], robot.data.joint_stiffness[0, ids].numpy())
        np.testing.assert_allclose(meta["joint_damping"], robot.data.joint_damping[0, ids].numpy())
        assert meta["observation_names"][-1] == "actions" and meta["step_dt"] == pytest.approx(0.02)

        (onnx_actions,) = ort.InferenceSession(onnx_file).run(["actions"], {"obs": policy_obs.numpy()})
        with torch.no_grad():
            expected = actor(TensorDict({"policy": policy_obs}, batch_size=[policy_obs.shape[0]])).numpy()
        np.testing.assert_allclose(onnx_actions, expected, atol=1e-5)
    finally:
        env.close()


def test_direct_task_records_robot_and_time_steps():
    env = _make_env("simlab/Cartpole-Direct-v0", num_envs=1)
    try:
        meta = {k: json.loads(v) for k, v in deploy_metadata(env, "simlab/Cartpole-Direct-v0").items()}
    finally:
        env.close()
    assert meta["env_type"] == "direct"
    assert meta["articulations"]["cartpole"]["joint_names"] == ["slider_to_cart", "cart_to_pole"]
    assert meta["action_size"] == 1 and meta["observation_size"] == 4
    assert meta["action_terms"].startswith("unsupported for deploy")
    assert meta["step_dt"] == pytest.approx(meta["physics_dt"] * meta["decimation"])


def test_passive_joints_carry_no_gains():
    """The Shadow hand's coupled distal joints have no actuator: their gains are null (play's export
    stopped on them with a bare StopIteration)."""
    env = _make_env("simlab/Repose-Cube-Shadow-Direct-v0", num_envs=1)
    try:
        meta = {k: json.loads(v) for k, v in deploy_metadata(env, "simlab/Repose-Cube-Shadow-Direct-v0").items()}
    finally:
        env.close()
    (hand,) = [a for a in meta["articulations"].values() if len(a["joint_names"]) == 24]
    passive = [j for j, group in zip(hand["joint_names"], hand["joint_actuator"]) if group is None]
    assert len(passive) == 4, passive  # the four coupled distal joints of the fingers
    for joint in passive:
        k = hand["joint_names"].index(joint)
        assert hand["joint_stiffness"][k] is None and hand["joint_effort_limit"][k] is None
    assert all(s is not None for s, g in zip(hand["joint_stiffness"], hand["joint_actuator"]) if g is not None)


def test_unknown_observation_group():
    env = _make_env(CARTPOLE, num_envs=1)
    try:
        with pytest.raises(ValueError, match="No observation group \\['critic'\\]; the env's groups: \\['policy'\\]"):
            deploy_metadata(env, CARTPOLE, ["critic"])
    finally:
        env.close()
