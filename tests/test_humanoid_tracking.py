"""G1 motion tracking: the task steps; the motion command starts envs in the clip's state and keeps its
targets on the robot; adaptive sampling favours where the policy fails; the shipped clips (a walk, a
turn in place, a wave and a whole-body twist) are physically trackable: soles on the ground without
sliding, the centre of mass over the soles that touch, no self-penetration, joints within range."""

from __future__ import annotations

import os
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np
import pytest
import torch
from test_graph_contract import emulated_cuda_graph  # noqa: F401 (a fixture)

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.robots.unitree import ASSETS_DIR
from simlab.tasks.manager_based.tracking.config.g1.flat_env_cfg import MOTIONS_DIR
from simlab.tasks.manager_based.tracking.motion_clip import MotionClip, model_joint_names
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry, parse_env_cfg

N = 4
CLIPS = sorted(Path(MOTIONS_DIR).glob("*.npz"))
G1_29DOF_MJCF = f"{ASSETS_DIR}/unitree_g1_29dof.xml"
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


def test_each_shipped_clip_has_its_own_task_id():
    """One policy per clip: the family's id tracks the walk, the others their clip, train and play alike."""
    for clip, name in (("", "g1_walk"), ("-Turn", "g1_turn"), ("-Wave", "g1_wave"), ("-Twist", "g1_twist")):
        for suffix in ("", "-Play"):
            cfg = parse_env_cfg(f"simlab/Tracking-Flat-G1{clip}{suffix}-v0", device="cpu", num_envs=N)
            assert os.path.basename(cfg.commands.motion.motion_file) == f"{name}.npz"
            assert criterion_for(f"simlab/Tracking-Flat-G1{clip}{suffix}-v0") is not None


def test_staying_alive_pays_at_the_agents_initial_action_noise():
    """PPO's first actions are the policy's mean plus noise of init_std, so consecutive actions differ by
    2 J init_std^2 squared on average, which action_rate_l2 charges every step. Where that costs more than
    tracking earns, a step alive loses reward and PPO learns to end its episodes early (mjlab's 1.0:
    episodes of 34 steps fell to 13 in 30 CPU iterations). A robot started in the clip's state earned
    2.0-2.8 per second of the tracking terms' 5 at most in those runs: the noise may cost at most 40 %."""
    task = "simlab/Tracking-Flat-G1-v0"
    cfg = parse_env_cfg(task, device="cpu", num_envs=1)
    agent = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    std = agent.actor.distribution_cfg.init_std
    joints = 29
    cost = -cfg.rewards.action_rate_l2.weight * 2 * joints * std**2  # per second: weight x value, dt cancels
    pay = sum(term.weight for name, term in vars(cfg.rewards).items() if name.startswith("motion_"))
    assert pay == pytest.approx(5.0)
    assert cost < 0.4 * pay, f"init_std {std}: the first actions' changes cost {cost:.2f}/s of {pay:.2f}/s"


def test_criterion_judges_the_clip_played_from_its_start():
    """bench solve plays the training task for the verdict: with the criterion's overrides it is the
    clip's play (the -Play task's settings), not training's pushes and sampled starts."""
    from simlab.tasks.utils.hydra import apply_overrides

    criterion = criterion_for("simlab/Tracking-Flat-G1-v0")
    cfg = parse_env_cfg("simlab/Tracking-Flat-G1-v0", device="cpu", num_envs=N)
    play = parse_env_cfg("simlab/Tracking-Flat-G1-Play-v0", device="cpu", num_envs=N)
    assert cfg.events.push_robot is not None and cfg.commands.motion.adaptive_sampling
    apply_overrides(cfg, None, list(criterion.play_overrides))
    assert cfg.events.push_robot is None and not cfg.observations.policy.enable_corruption
    motion, played = cfg.commands.motion, play.commands.motion
    assert not motion.adaptive_sampling and motion.joint_position_range == played.joint_position_range
    for ranges in (motion.pose_range, motion.velocity_range):
        assert all(low == high == 0.0 for low, high in ranges.values())
    cfg.seed = 0
    env = gym.make("simlab/Tracking-Flat-G1-v0", cfg=cfg).unwrapped
    try:
        env.reset()
        term = env.command_manager.get_term("motion")
        assert term.time_steps.tolist() == [0] * N
        torch.testing.assert_close(env.scene["robot"].data.joint_pos, term.joint_pos)
    finally:
        env.close()


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


def test_task_step_copies_nothing_from_the_host_and_reads_nothing_back():
    """No tensor of the step (clip restarts and resets included) is made from host data: on the GPU
    each is a copy from pageable memory, which a CUDA graph capture refuses ("Cannot copy between CPU
    and CUDA tensors during CUDA graph capture"), and the step then runs eagerly at about half speed."""
    from simlab.benchmarks import step_ops

    counter = step_ops.count("simlab/Tracking-Flat-G1-v0", num_envs=N, steps=3, engine="mujoco")
    assert sum(counter.host_copies.values()) == 0, dict(counter.host_copies)
    assert sum(counter.read_backs.values()) == 0, dict(counter.read_backs)
    assert counter.torch_ops["commands/motion"] > 0 and counter.torch_ops["terminations/ee_body_pos"] > 0


def test_task_step_is_captured_in_the_emulated_cuda_graph(emulated_cuda_graph, monkeypatch):  # noqa: F811
    """The env stepper's capture path on the CPU (test_graph_contract.py's emulated graph, which fails a
    capture that reads back or copies from the host, as a GPU does): the step is captured, and a replay
    moves the clip clock on."""
    from simlab.envs.utils.cuda_graph import EnvStepper

    env = make("simlab/Tracking-Flat-G1-v0")
    try:
        physics = env.sim.physics
        # the CPU backend, told to capture as the GPU one does; the replays run torch's ops only, so
        # MuJoCo's clock stands still, which this backend would take for worlds it restarted
        monkeypatch.setattr(physics, "can_capture_steps", True, raising=False)
        monkeypatch.setattr(physics, "forwards_all_worlds", True, raising=False)
        monkeypatch.setattr(physics, "_restarted_by_simulator", lambda: None)
        env.reset()
        stepper = EnvStepper(env, env._step_body, warmup=2)
        actions = torch.zeros(N, 29)
        for _ in range(3):  # warm-up, capture
            stepper(actions)
        assert stepper.is_graphed and stepper.eager_reason is None, stepper.mode
        clock = env.command_manager.get_term("motion").time_steps
        before = clock.clone()
        stepper(actions)
        assert (clock != before).any(), "the replay runs the motion command"
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
    clip = MotionClip.load(CLIPS[0], mjcf=G1_29DOF_MJCF)
    clip.fps = 30.0
    clip.save(tmp_path / "slow.npz")
    cfg = parse_env_cfg("simlab/Tracking-Flat-G1-v0", device="cpu", num_envs=N)
    cfg.commands.motion.motion_file = str(tmp_path / "slow.npz")
    with pytest.raises(ValueError, match=r"runs at 30 fps but the env steps at 50 Hz.*csv_to_npz.py --output_fps 50,"):
        gym.make("simlab/Tracking-Flat-G1-v0", cfg=cfg)


@pytest.mark.parametrize("path", CLIPS, ids=[p.stem for p in CLIPS])
def test_shipped_clip_is_physically_trackable(path):
    """Quasi-static checks of each frame: the soles touch the ground without sinking, those that touch
    do not slide, the centre of mass is over the soles that touch, no two bodies overlap."""
    clip = MotionClip.load(path, mjcf=G1_29DOF_MJCF)
    spec = mujoco.MjSpec.from_file(G1_29DOF_MJCF)
    for geom in spec.geoms:  # every geom collides with every other (MuJoCo skips parent-child pairs)
        geom.contype, geom.conaffinity = 1, 1
    model = spec.compile()
    data = mujoco.MjData(model)
    joints = model_joint_names(model)
    assert clip.joint_names == joints and clip.fps == 50.0 and clip.duration >= 4.0
    cols = [model.jnt_qposadr[model.joint(n).id] for n in joints]
    soles = [model.geom(n).id for n in SOLES]
    previous, deepest = None, 0.0
    for t in range(clip.num_frames):
        data.qpos[:3], data.qpos[3:7] = clip.body_pos_w[t, 0], clip.body_quat_w[t, 0]
        data.qpos[cols] = clip.joint_pos[t]
        mujoco.mj_forward(model, data)
        axis = [data.geom_xmat[g].reshape(3, 3)[:, 2] * model.geom_size[g][1] for g in soles]
        ends = np.array([[data.geom_xpos[g] - a, data.geom_xpos[g] + a] for g, a in zip(soles, axis)])  # (4, 2, 3)
        bottom = ends[..., 2].min(axis=1) - model.geom_size[soles, 0]
        assert bottom.min() > -1e-3 and bottom.min() < 1e-3, f"frame {t}: a sole on the ground, none below it"
        down = bottom < 1e-3
        if previous is not None:
            kept = down & previous[1]
            slide = np.abs(ends[kept] - previous[0][kept]).max() if kept.any() else 0.0
            assert slide < 2e-3, f"frame {t}: a sole on the ground slides {slide:.4f} m"
        previous = (ends, down)
        # the centre of mass over the outline of the soles that touch (their bounding box, in heading frame)
        com = data.subtree_com[1]
        yaw = 2 * np.arctan2(clip.body_quat_w[t, 0, 3], clip.body_quat_w[t, 0, 0])
        heading = np.array([[np.cos(yaw), np.sin(yaw)], [-np.sin(yaw), np.cos(yaw)]])
        points = ends[down].reshape(-1, 3)[:, :2] @ heading.T
        c = heading @ com[:2]
        margin = min(
            c[0] - points[:, 0].min(), points[:, 0].max() - c[0], c[1] - points[:, 1].min(), points[:, 1].max() - c[1]
        )
        assert margin > 0.015, f"frame {t}: the centre of mass is {margin:.3f} m inside the support"
        for contact in data.contact[: data.ncon]:
            deepest = min(deepest, contact.dist)
    assert deepest > -0.005, f"no body sinks into another (deepest {deepest:.3f} m)"
    assert np.abs(clip.joint_vel).max() < 6.0, "joint speeds the motors reach"
    ranges = model.jnt_range[[model.joint(n).id for n in joints]]
    assert ((clip.joint_pos >= ranges[:, 0] - 1e-4) & (clip.joint_pos <= ranges[:, 1] + 1e-4)).all(), (
        "within the joints' ranges"
    )
