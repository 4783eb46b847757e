"""G1 motion tracking: the task steps; the motion command starts envs in the clip's state and keeps its
targets on the robot; adaptive sampling favours where the policy fails; the shipped clips are
physically trackable (soles planted on the ground, centre of mass over them, no self-penetration)."""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.robots.unitree import ASSETS_DIR
from simlab.tasks.manager_based.tracking.config.g1.flat_env_cfg import MOTIONS_DIR
from simlab.tasks.manager_based.tracking.motion_clip import MotionClip, model_joint_names
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import parse_env_cfg

N = 4
CLIPS = sorted(Path(MOTIONS_DIR).glob("*.npz"))
SOLES = ("left_sole_inner", "left_sole_outer", "right_sole_inner", "right_sole_outer")


def make(task: str):
    cfg = parse_env_cfg(task, device="cpu", num_envs=N)
    cfg.seed = 0
    return gym.make(task, cfg=cfg).unwrapped


def test_task_ids_and_criterion():
    for task in ("simlab/Tracking-Flat-G1-v0", "simlab/Tracking-Flat-G1-Play-v0"):
        assert task in gym.registry
        criterion = criterion_for(task)
        assert "body position error < 10 cm" in criterion.description
    judge = criterion_for("simlab/Tracking-Flat-G1-v0").judge
    assert judge({}, {"error": 0.08 * 100, "samples": 100, "falls": 0}) == (pytest.approx(0.08), True)
    assert not judge({}, {"error": 0.08 * 100, "samples": 100, "falls": 1})[1]
    assert not judge({}, {"error": 0.12 * 100, "samples": 100, "falls": 0})[1]


def test_task_steps_with_finite_observations_and_rewards():
    env = make("simlab/Tracking-Flat-G1-v0")
    try:
        obs, _ = env.reset()
        # policy: clip joints (2 x 29), anchor (3 + 6), base velocities (6), joints (2 x 29), actions (29)
        assert obs["policy"].shape == (N, 58 + 9 + 6 + 58 + 29)
        assert obs["critic"].shape == (N, 58 + 9 + 14 * 9 + 6 + 58 + 29)
        assert env.graph_blockers() == [], "the step (clip ends and restarts included) can be captured as a CUDA graph"
        for _ in range(20):
            obs, reward, *_ = env.step(0.3 * torch.randn(N, 29))
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(obs["critic"]).all()
            assert torch.isfinite(reward).all()
    finally:
        env.close()


def test_envs_start_in_the_clips_state_and_follow_its_clock():
    env = make("simlab/Tracking-Flat-G1-Play-v0")  # from the clip's start, no start noise
    try:
        env.reset()
        motion = env.command_manager.get_term("motion")
        robot = env.scene["robot"]
        assert motion.time_steps.tolist() == [0] * N
        torch.testing.assert_close(robot.data.joint_pos, motion.joint_pos)
        # the simulated bodies are where the clip's forward kinematics put them (same model, same state)
        motion._update_metrics()
        assert motion.metrics["error_body_pos"].max() < 1e-3
        assert motion.metrics["error_anchor_pos"].max() < 1e-3
        for name in ("motion_body_pos", "motion_global_anchor_pos"):
            term = env.reward_manager.get_term_cfg(name)
            torch.testing.assert_close(term.func(env, **term.params), torch.ones(N), atol=1e-3, rtol=0)
        env.step(torch.zeros(N, 29))
        assert motion.time_steps.tolist() == [1] * N
        # at the clip's end the env restarts it, the robot put back in the clip's first state
        motion.time_steps[:] = motion.num_frames - 1
        env.step(torch.zeros(N, 29))
        assert motion.time_steps.tolist() == [0] * N
    finally:
        env.close()


def test_adaptive_sampling_starts_where_the_policy_fails():
    env = make("simlab/Tracking-Flat-G1-v0")
    try:
        env.reset()
        motion = env.command_manager.get_term("motion")
        assert motion.sampling_entropy() == pytest.approx(1.0)
        motion.bin_failed.zero_()
        motion.bin_failed[2] = 10.0  # many recent failures in the third second of the clip
        every_env = torch.ones(N, dtype=torch.bool)
        times = torch.cat([motion._sample_times(every_env) or motion.time_steps.clone() for _ in range(250)])
        bins = times * motion.bin_count // motion.num_frames
        share = (bins == 2).float().mean()
        assert share > 0.9, share
        assert motion.sampling_entropy() < 0.5
    finally:
        env.close()


def test_a_clip_at_another_rate_is_refused(tmp_path):
    clip = MotionClip.load(CLIPS[0])
    clip.fps = 30.0
    clip.save(tmp_path / "slow.npz")
    cfg = parse_env_cfg("simlab/Tracking-Flat-G1-v0", device="cpu", num_envs=N)
    cfg.commands.motion.motion_file = str(tmp_path / "slow.npz")
    with pytest.raises(ValueError, match=r"runs at 30 fps but the env steps at 50 Hz"):
        gym.make("simlab/Tracking-Flat-G1-v0", cfg=cfg)


@pytest.mark.parametrize("path", CLIPS, ids=[p.stem for p in CLIPS])
def test_shipped_clip_is_physically_trackable(path):
    clip = MotionClip.load(path)
    spec = mujoco.MjSpec.from_file(f"{ASSETS_DIR}/unitree_g1_29dof.xml")
    for geom in spec.geoms:  # every geom collides with every other (MuJoCo skips parent-child pairs)
        geom.contype, geom.conaffinity = 1, 1
    model = spec.compile()
    data = mujoco.MjData(model)
    joints = model_joint_names(model)
    assert clip.joint_names == joints and clip.fps == 50.0 and clip.duration >= 4.0
    cols = [model.jnt_qposadr[model.joint(n).id] for n in joints]
    soles = [model.geom(n).id for n in SOLES]
    sole_pos, lowest, com_margin, deepest = [], [], [], 0.0
    for t in range(clip.num_frames):
        data.qpos[:3], data.qpos[3:7] = clip.body_pos_w[t, 0], clip.body_quat_w[t, 0]
        data.qpos[cols] = clip.joint_pos[t]
        mujoco.mj_forward(model, data)
        sole_pos.append(np.array([data.geom_xpos[g] for g in soles]))
        lowest.append(min(data.geom_xpos[g][2] - model.geom_size[g][0] for g in soles))
        # the centre of mass over the rectangle the soles span
        ends = np.array(
            [
                data.geom_xpos[g] + s * model.geom_size[g][1] * data.geom_xmat[g].reshape(3, 3)[:, 2]
                for g in soles
                for s in (-1, 1)
            ]
        )
        com = data.subtree_com[1]
        com_margin.append(
            min(
                com[0] - ends[:, 0].min(),
                ends[:, 0].max() - com[0],
                com[1] - ends[:, 1].min(),
                ends[:, 1].max() - com[1],
            )
        )
        for c in data.contact[: data.ncon]:
            deepest = min(deepest, c.dist)
    sole_pos = np.array(sole_pos)
    assert np.abs(np.array(lowest)).max() < 1e-3, "the soles touch the ground in every frame: no floating, no sinking"
    assert np.abs(sole_pos - sole_pos[0]).max() < 1e-3, "and stay where they are: no sliding"
    assert min(com_margin) > 0.02, "the centre of mass stays over the feet, 2 cm inside their outline"
    assert deepest > -0.005, f"no body sinks into another (deepest {deepest:.3f} m)"
    assert np.abs(clip.joint_vel).max() < 6.0, "joint speeds the motors reach"
