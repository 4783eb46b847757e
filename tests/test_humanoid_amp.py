"""The AMP humanoid: motion files, the clip generator, reference-state initialisation, AMP observations,
and ``simlab train/play --library skrl --algorithm AMP`` end to end."""

from __future__ import annotations

import dataclasses
import glob
import math
import os

import gymnasium as gym
import numpy as np
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.cli.main import main
from simlab.tasks.direct.humanoid_amp.motions import MOTIONS_DIR
from simlab.tasks.direct.humanoid_amp.motions.kinematic_clips import CLIPS, make_clip
from simlab.tasks.direct.humanoid_amp.motions.motion_file import MOTION_KEYS, read_motion_file, write_motion_file
from simlab.tasks.direct.humanoid_amp.motions.motion_loader import MotionLoader
from simlab.tasks.utils import load_cfg_from_registry

TASK = "simlab/Humanoid-AMP-Walk-Direct-v0"
# tiny AMP memories: the configs' 200k / 1M-sample memories take seconds and 0.5 GB to allocate
SMALL_MEMORIES = ["agent.motion_dataset.memory_size=1024", "agent.reply_buffer.memory_size=1024"]


def _two_joint_clip(path: str) -> None:
    """Three frames at 10 fps: joint a goes 0, 1, 3; body b turns 0, 90, 90 degrees about z."""
    quarter = [math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)]
    identity = [1.0, 0.0, 0.0, 0.0]
    write_motion_file(
        path,
        fps=10.0,
        dof_names=["a", "b"],
        body_names=["root", "b"],
        dof_positions=[[0.0, 0.0], [1.0, -1.0], [3.0, -3.0]],
        dof_velocities=np.zeros((3, 2)),
        body_positions=np.arange(18, dtype=float).reshape(3, 2, 3),
        body_rotations=[[identity, identity], [identity, quarter], [identity, quarter]],
        body_linear_velocities=np.zeros((3, 2, 3)),
        body_angular_velocities=np.zeros((3, 2, 3)),
    )


def test_a_users_motion_file_loads_and_is_sampled_with_interpolation(tmp_path):
    path = str(tmp_path / "mine.npz")
    _two_joint_clip(path)
    motion = MotionLoader(path, "cpu")
    assert (motion.num_frames, motion.duration, motion.dof_names) == (3, pytest.approx(0.2), ["a", "b"])
    dof_pos, _, body_pos, body_rot, _, _ = motion.sample(4, times=np.array([0.05, 0.15, 0.2, 7.0]))
    # halfway between frames 0 and 1, then 1 and 2; the end and beyond it clamp to the last frame
    np.testing.assert_allclose(dof_pos[:, 0], [0.5, 2.0, 3.0, 3.0], atol=1e-5)
    np.testing.assert_allclose(body_pos[0, 1], [6.0, 7.0, 8.0], atol=1e-5)  # frames: 3 4 5, 9 10 11
    half = [math.cos(math.pi / 8), 0.0, 0.0, math.sin(math.pi / 8)]  # slerp: 45 degrees about z
    np.testing.assert_allclose(body_rot[0, 1], half, atol=1e-5)
    assert motion.get_dof_index(["b", "a"]) == [1, 0]
    with pytest.raises(ValueError, match=r"no joint named \['knee'\]"):
        motion.get_dof_index(["knee"])
    times = motion.sample_times(1000)
    assert float(times.min()) >= 0.0 and float(times.max()) <= motion.duration


def test_bad_motion_files_say_what_is_wrong(tmp_path):
    path = str(tmp_path / "partial.npz")
    np.savez(path, fps=30.0, dof_names=np.array(["a"]))
    with pytest.raises(ValueError, match="lacks") as e:
        MotionLoader(path, "cpu")
    assert all(key in str(e.value) for key in MOTION_KEYS[3:])
    with pytest.raises(ValueError, match=r"dof_velocities has shape \(2, 3\); expected \(2, 1\)"):
        write_motion_file(
            str(tmp_path / "bad.npz"),
            fps=30.0,
            dof_names=["a"],
            body_names=["root"],
            dof_positions=np.zeros((2, 1)),
            dof_velocities=np.zeros((2, 3)),
            body_positions=np.zeros((2, 1, 3)),
            body_rotations=np.zeros((2, 1, 4)),
            body_linear_velocities=np.zeros((2, 1, 3)),
            body_angular_velocities=np.zeros((2, 1, 3)),
        )
    with pytest.raises(FileNotFoundError):
        MotionLoader(str(tmp_path / "missing.npz"), "cpu")


def test_shipped_clips_are_what_the_generator_makes():
    for name, spec in CLIPS.items():
        clip, stats = make_clip(spec)
        shipped = read_motion_file(os.path.join(MOTIONS_DIR, f"humanoid_{name}.npz"))  # body states by FK
        for key in MOTION_KEYS[3:]:
            # body velocities: finite differences of poses from the float32 root and joints (1.2e-5 at most)
            atol = 2e-5 if key.startswith("body_") and key.endswith("velocities") else 1e-5
            np.testing.assert_allclose(shipped[key], clip[key], atol=atol, err_msg=f"{name}: {key}")
        assert shipped["dof_names"].tolist() == clip["dof_names"]
    walk, run = make_clip(CLIPS["walk"])[1], make_clip(CLIPS["run"])[1]
    assert 0.4 < walk["forward_speed_m_s"] < run["forward_speed_m_s"]


def _support_track(clip: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per frame of ``clip``: the whole body's centre of mass, the middle of the lower foot's sole (both
    from MuJoCo's kinematics of the clip's torso pose and joint angles), and whether only one foot is down."""
    import mujoco

    from simlab.tasks.direct.humanoid_amp.motions.kinematic_clips import (
        FOOT_GEOMS,
        HUMANOID_XML,
        _centre_of_mass,
        _sole_middle,
    )

    model = mujoco.MjModel.from_xml_path(HUMANOID_XML)
    data = mujoco.MjData(model)
    torso = clip["body_names"].index("torso")
    dof_adr = [model.jnt_qposadr[model.joint(name).id] for name in clip["dof_names"]]
    com, sole, single = [], [], []
    for f in range(len(clip["dof_positions"])):
        data.qpos[:3], data.qpos[3:7] = clip["body_positions"][f, torso], clip["body_rotations"][f, torso]
        data.qpos[dof_adr] = clip["dof_positions"][f]
        mujoco.mj_kinematics(model, data)
        com.append(_centre_of_mass(model, data))
        soles = [_sole_middle(data, foot) for foot in FOOT_GEOMS]
        sole.append(min(soles, key=lambda p: p[2]))
        single.append(abs(soles[0][2] - soles[1][2]) > 0.05)
    return np.array(com), np.array(sole), np.array(single)


def test_the_balanced_dance_stands_on_its_supporting_foot():
    """A march that stands on one foot for half a second must hold its weight over that foot and not
    slide it (the unbalanced clip slid the stance foot at about 0.9 m/s): else no body can dance it."""
    clip, _ = make_clip(CLIPS["dance"])
    com, sole, single = _support_track(clip)
    assert single.mean() > 0.5  # mostly on one foot
    sideways = np.abs(com[single, 1] - sole[single, 1])
    assert sideways.mean() < 0.02 and sideways.max() < 0.05, (sideways.mean(), sideways.max())
    # the stance sole stays put while it is the stance one (frames where the lower foot does not change)
    same = np.linalg.norm(np.diff(sole[:, :2], axis=0), axis=1) < 0.05
    slide = np.linalg.norm(np.diff(sole[:, :2], axis=0), axis=1)[same] * clip["fps"]
    assert np.median(slide) < 0.02, np.median(slide)
    unbalanced, _ = make_clip(dataclasses.replace(CLIPS["dance"], support=None, lateral_sway=0.04))
    com, sole, single = _support_track(unbalanced)
    assert np.abs(com[single, 1] - sole[single, 1]).max() > 0.05  # what the balance fixes


def _make_env(num_envs: int = 3, **cfg_fields):
    cfg = load_cfg_from_registry(TASK, "env_cfg_entry_point")
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    cfg.seed = 0
    for key, value in cfg_fields.items():
        setattr(cfg, key, value)
    return gym.make(TASK, cfg=cfg)


def test_env_steps_and_amp_observations_match_their_space():
    env = _make_env(3)
    try:
        base = env.unwrapped
        obs, _ = env.reset()
        size = base.amp_observation_space.shape[0]
        assert size == base.cfg.num_amp_observations * base.cfg.amp_observation_space == 134
        assert obs["policy"].shape == (3, base.cfg.observation_space)
        for _ in range(5):
            obs, reward, terminated, truncated, extras = env.step(0.1 * torch.randn(3, 21))
        assert extras["amp_obs"].shape == (3, size) and torch.isfinite(extras["amp_obs"]).all()
        # the newest frame of the history is the state the step ended in (final_obs)
        torch.testing.assert_close(extras["amp_obs"][:, : size // 2], extras["final_obs"]["policy"])
        reference = base.collect_reference_motions(7)
        assert reference.shape == (7, size) and torch.isfinite(reference).all()
        assert torch.equal(reward, torch.ones(3))
        assert base.graph_blockers() == []  # resets by mask: the step can replay as a CUDA graph
    finally:
        env.close()


def test_reference_state_init_puts_the_humanoid_in_the_clips_pose():
    env = _make_env(3, reset_strategy="random-start")
    try:
        base = env.unwrapped
        env.reset()
        motion = base._motion_loader
        robot = base.robot
        first = motion.dof_positions[0, base.motion_dof_indexes]
        torch.testing.assert_close(robot.data.joint_pos, first.expand(3, -1), atol=1e-6, rtol=0)
        torso = motion.get_body_index(["torso"])[0]
        expected_pos = motion.body_positions[0, torso] + base.scene.env_origins
        expected_pos[:, 2] += base.cfg.reference_lift
        torch.testing.assert_close(robot.data.root_pos_w, expected_pos, atol=1e-5, rtol=0)
        torch.testing.assert_close(
            robot.data.root_quat_w, motion.body_rotations[0, torso].expand(3, -1), atol=1e-5, rtol=0
        )
        # the sim's frame (forward kinematics of the written state) is the clip's frame: same key-body
        # positions, velocities and orientation; only the torso height differs, by the lift
        frame = base._get_observations()["policy"]
        reference = base.collect_reference_motions(3, torch.zeros(3))[:, : frame.shape[1]]
        height = 2 * robot.num_joints
        torch.testing.assert_close(frame[:, height] - reference[:, height], torch.full((3,), 0.05), atol=1e-5, rtol=0)
        keep = [i for i in range(frame.shape[1]) if i != height]
        torch.testing.assert_close(frame[:, keep], reference[:, keep], atol=2e-3, rtol=0)
        # the AMP history of a reset env is the clip's: no jump from a stale state into the first transition
        torch.testing.assert_close(
            base.amp_observation_buffer.flatten(1), base.collect_reference_motions(3, torch.zeros(3))
        )
    finally:
        env.close()


def test_random_reference_states_are_the_clip_at_random_times():
    env = _make_env(4, reset_strategy="random")
    try:
        base = env.unwrapped
        env.reset()
        motion = base._motion_loader
        # 0.25 ms apart: a clip recorded from physics moves a joint at up to 30 rad/s
        times = torch.linspace(0, motion.duration, int(motion.duration * 4000) + 1)
        dense = motion.sample(len(times), times=times)[0][:, base.motion_dof_indexes]
        joint_pos = base.robot.data.joint_pos
        nearest = torch.cdist(joint_pos, dense).min(dim=1).values
        assert (nearest < 0.02).all(), nearest  # each env is on the clip...
        assert torch.cdist(joint_pos, joint_pos).fill_diagonal_(1.0).min() > 0.01  # ...at its own time
    finally:
        env.close()


def test_a_motion_for_another_skeleton_is_refused_naming_the_joints(tmp_path):
    path = str(tmp_path / "other.npz")
    _two_joint_clip(path)
    with pytest.raises(ValueError, match="has no joint named.*lower_waist:0"):
        _make_env(2, motion_file=path)


def test_train_and_play_amp_with_skrl(tmp_path):
    logs = ["--log_root", str(tmp_path / "logs")]
    small = [
        "--task",
        TASK,
        "--num_envs",
        "2",
        "--headless",
        "--device",
        "cpu",
        "--library",
        "skrl",
        "--algorithm",
        "AMP",
    ]
    assert main(["train", *small, "--max_iterations", "2", *logs, *SMALL_MEMORIES]) == 0
    (run,) = glob.glob(str(tmp_path / "logs" / "skrl" / "humanoid_amp_walk" / "*"))
    assert os.path.isfile(os.path.join(run, "checkpoints", "agent_32.pt"))  # 2 iterations x 16 rollouts

    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    from simlab.cli.libraries.skrl import STYLE_REWARD_TAG

    events = EventAccumulator(run)
    events.Reload()
    style = [s.value for s in events.Scalars(STYLE_REWARD_TAG)]
    assert len(style) >= 1 and all(math.isfinite(v) and v >= 0 for v in style)
    # without --algorithm, skrl plays the task's only agent: AMP
    assert main(["play", *small[:-2], "--use_last_checkpoint", "--steps", "3", *logs]) == 0
    assert os.path.isfile(os.path.join(run, "checkpoints", "exported", "policy.onnx"))


@pytest.mark.parametrize("motion", ["Walk", "Run", "Dance"])
def test_amp_tasks_register_skrl_amp_configs(motion):
    task = f"simlab/Humanoid-AMP-{motion}-Direct-v0"
    agent = load_cfg_from_registry(task, "skrl_amp_cfg_entry_point")
    assert agent["agent"]["class"] == "AMP" and set(agent["models"]) >= {"policy", "value", "discriminator"}
    assert agent["agent"]["experiment"]["directory"] == f"humanoid_amp_{motion.lower()}"
    env_cfg = load_cfg_from_registry(task, "env_cfg_entry_point")
    # the walk and run imitate clips recorded from Humanoid-v0's policies; the dance the generator's clip
    clips = {"Walk": "humanoid_walk_recorded.npz", "Run": "humanoid_run_recorded.npz", "Dance": "humanoid_dance.npz"}
    clip = clips[motion]
    assert os.path.isfile(env_cfg.motion_file) and os.path.basename(env_cfg.motion_file) == clip


def test_default_reset_starts_the_history_afresh():
    env = _make_env(2, reset_strategy="default")
    try:
        base = env.unwrapped
        env.reset()
        torch.testing.assert_close(base.robot.data.joint_pos, base.robot.data.default_joint_pos)
        _, _, _, _, extras = env.step(torch.zeros(2, 21))
        frames = extras["amp_obs"].view(2, base.cfg.num_amp_observations, -1)
        torch.testing.assert_close(frames[:, 0], frames[:, 1])  # no stale frame from before the reset
        _, _, _, _, extras = env.step(torch.zeros(2, 21))
        frames = extras["amp_obs"].view(2, base.cfg.num_amp_observations, -1)
        assert not torch.allclose(frames[:, 0], frames[:, 1])  # then the frames advance
    finally:
        env.close()


def test_unknown_reset_strategy_is_refused():
    with pytest.raises(
        ValueError, match=r"Unknown reset_strategy 'randon'. Allowed: \['default', 'random', 'random-start'\]"
    ):
        _make_env(1, reset_strategy="randon")


def test_amp_on_jax_is_refused_before_anything_is_built(tmp_path, capsys):
    argv = ["train", "--task", TASK, "--library", "skrl", "--ml_framework", "jax", "--headless"]
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    assert "skrl's AMP agent exists for torch only" in capsys.readouterr().err
    assert not (tmp_path / "logs").exists()


def test_a_kinematic_replay_of_the_clip_gives_the_reference_amp_observations():
    """The env's AMP observation of the clip's states, written step by step into the sim, is what
    ``collect_reference_motions`` (skrl's motion dataset) holds for those times, over the whole
    history window: the discriminator sees one distribution from both sides."""
    env = _make_env(3, reset_strategy="random", reference_lift=0.0)
    try:
        base = env.unwrapped
        env.reset()
        motion, robot, everyone = base._motion_loader, base.robot, torch.ones(3, dtype=torch.bool)
        start = torch.tensor([0.0, 0.5, 1.7])  # the history of env 0 starts at the clip's first frame
        base._motion_loader.sample_times = lambda n, duration=None: start  # RSI at these times
        base._reset_mask(everyone)
        root = base.motion_ref_body_index
        for step in range(5):
            times = start + step * base.step_dt
            if step:
                dof_pos, dof_vel, body_pos, body_rot, body_lin_vel, body_ang_vel = motion.sample(3, times=times)
                robot.write_root_pose_to_sim(
                    torch.cat([body_pos[:, root] + base.scene.env_origins, body_rot[:, root]], -1), everyone
                )
                robot.write_root_velocity_to_sim(
                    torch.cat([body_lin_vel[:, root], body_ang_vel[:, root]], -1), everyone
                )
                joints = base.motion_dof_indexes
                robot.write_joint_state_to_sim(dof_pos[:, joints], dof_vel[:, joints], None, everyone)
                base._advance_amp_history()  # what the step does after its physics
            history = base.amp_observation_buffer.flatten(1)
            torch.testing.assert_close(history, base.collect_reference_motions(3, times), atol=2e-3, rtol=0)
    finally:
        env.close()


@pytest.mark.parametrize("name", list(CLIPS))
def test_every_amp_feature_of_the_shipped_clips_varies(name):
    """A feature the clip holds constant (a torso pinned upright, a frozen joint) is one no simulated
    body matches exactly: the discriminator would call every policy fake by it alone."""
    from simlab.tasks.direct.humanoid_amp.humanoid_amp_env import compute_obs

    motion = MotionLoader(os.path.join(MOTIONS_DIR, f"humanoid_{name}.npz"), "cpu")
    root = motion.get_body_index(["torso"])[0]
    keys = motion.get_body_index(["right_hand", "left_hand", "right_foot", "left_foot"])
    frames = compute_obs(
        motion.dof_positions,
        motion.dof_velocities,
        motion.body_positions[:, root],
        motion.body_rotations[:, root],
        motion.body_linear_velocities[:, root],
        motion.body_angular_velocities[:, root],
        motion.body_positions[:, keys],
    )
    constant = (frames.std(dim=0) < 1e-4).nonzero().flatten().tolist()
    assert constant == [], f"{name}: AMP features {constant} never change"


def test_the_imitation_reward_pays_for_the_clips_poses_and_pace():
    """Off (Isaac Lab's env) the reward is a constant 1; on, each env earns up to 1 for a pose on the
    clip and up to 1 for the clip's forward speed."""
    env = _make_env(3, reset_strategy="random-start", imitation_reward=True)
    try:
        base = env.unwrapped
        env.reset()
        robot = base.robot
        assert base.clip_forward_speed > 0.1  # the walk moves forward
        # reference states are on the clip: the pose term is 1, the pace term the clip's speed at its start
        assert base.clip_pose_squared_error(robot.data.joint_pos).max() < 1e-10
        on_clip = base._get_rewards()
        speed = robot.data.body_lin_vel_w[:, base.ref_body_index, 0]
        pace = torch.exp(-(((speed - base.clip_forward_speed) / base.cfg.speed_sigma) ** 2))
        torch.testing.assert_close(on_clip, 1.0 + pace)
        # the same bodies standing in the zero pose: the pose term falls, the pace term stays
        zero = torch.zeros_like(robot.data.joint_pos)
        robot.write_joint_state_to_sim(zero, robot.data.joint_vel.clone())
        error = base.clip_pose_squared_error(robot.data.joint_pos)
        assert (error > 0.01).all()
        torch.testing.assert_close(base._get_rewards(), torch.exp(-error / base.cfg.pose_sigma**2) + pace)
        base.cfg.imitation_reward = False
        assert torch.equal(base._get_rewards(), torch.ones(3))
    finally:
        env.close()
