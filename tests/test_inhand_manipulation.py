"""In-hand cube reorientation (simlab.tasks.direct.inhand_manipulation with the Allegro Hand).

The task builds, resets and steps on the CPU with finite values and Isaac Lab's spaces; a cube turned
to its goal earns the bonus, gets a new goal at once and counts as a success, which the episode's end
carries into ``consecutive_successes`` and the solve criterion; the agent configs are Isaac Lab's.
"""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch
from test_graph_contract import emulated_cuda_graph, graphed_allegro_env  # noqa: F401 (a fixture)

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import rotation_distance, unscale
from simlab.tasks.utils import parse_env_cfg

ALLEGRO = "simlab/Repose-Cube-Allegro-Direct-v0"
NUM_ENVS = 4


def make(task: str, num_envs: int = NUM_ENVS):
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    env = gym.make(task, cfg=cfg).unwrapped
    env.reset(seed=0)
    return env


@pytest.fixture(scope="module")
def allegro():
    env = make(ALLEGRO)
    yield env
    env.close()


def hold_actions(env) -> torch.Tensor:
    """Actions whose targets are the joints' current positions (the hand keeps still)."""
    act = env.actuated_dof_indices
    lower, upper = env.hand_dof_lower_limits[:, act], env.hand_dof_upper_limits[:, act]
    return unscale(env.hand.data.joint_pos[:, act], lower, upper)


def test_allegro_direct_steps_with_finite_values_and_resets_by_mask(allegro):
    env = allegro
    assert env.single_observation_space["policy"].shape == (124,)
    assert env.single_action_space.shape == (16,)
    assert env.graph_blockers() == []  # resets and goal redraws select envs by mask: the step can be one graph
    generator = torch.Generator().manual_seed(0)
    for _ in range(20):
        actions = 2 * torch.rand(NUM_ENVS, 16, generator=generator) - 1
        obs, reward, terminated, truncated, extras = env.step(actions)
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    assert "consecutive_successes" in extras["log"]
    # the cube starts on the fingers of the palm-up hand and has not fallen from a few random moves
    assert (env.object_pos - env.in_hand_pos).norm(dim=-1).max() < env.cfg.fall_dist


def test_a_reached_goal_earns_the_bonus_is_redrawn_and_counts_at_the_episode_end(allegro):
    env = allegro
    env.reset(seed=1)
    old_goal = env.goal_rot.clone()
    # env 0's cube turned to its goal, where it rests on the fingers now
    pose = torch.cat((env.object.data.root_pos_w, env.goal_rot), dim=-1)[:1]
    env.object.write_root_pose_to_sim(pose, env_ids=torch.tensor([0]))
    env.object.write_root_velocity_to_sim(torch.zeros(1, 6), env_ids=torch.tensor([0]))
    assert float(rotation_distance(env.object.data.root_quat_w, old_goal)[0]) < 1e-3
    before = float(env.consecutive_successes)
    _, reward, terminated, truncated, _ = env.step(hold_actions(env))
    assert not (terminated | truncated).any()
    assert float(rotation_distance(env.object_rot, old_goal)[0]) < env.cfg.success_tolerance  # still there
    assert float(reward[0]) > env.cfg.reach_goal_bonus  # the bonus, on top of the closeness terms
    assert float(reward[1:].max()) < env.cfg.reach_goal_bonus
    assert env.successes.tolist() == [1.0, 0.0, 0.0, 0.0]
    assert not torch.allclose(env.goal_rot[0], old_goal[0])  # a new goal at once
    torch.testing.assert_close(env.goal_rot[1:], old_goal[1:])  # the others keep theirs
    # env 0's episode ends (time-out): its count goes into the running mean and the criterion's record
    env.episode_length_buf[0] = env.max_episode_length - 1
    _, _, _, truncated, _ = env.step(hold_actions(env))
    assert bool(truncated[0])
    assert float(env.episode_successes[0]) == 1.0 and float(env.successes[0]) == 0.0
    expected = env.cfg.av_factor * 1.0 + (1.0 - env.cfg.av_factor) * before
    assert float(env.consecutive_successes) == pytest.approx(expected)


def test_the_step_s_in_place_reward_is_isaac_lab_s_compute_rewards():
    """The env computes its reward, success counts and running mean in place, reusing the dones'
    distances; Isaac Lab's functional ``compute_rewards`` on the same state gives the same values (some
    envs within the goal's tolerance, some flagged for a redraw, some ending, one fallen)."""
    from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import compute_rewards

    env = make(ALLEGRO)
    cfg = env.cfg
    generator = torch.Generator().manual_seed(3)
    for _ in range(3):
        env.step(hold_actions(env) + 0.1 * (2 * torch.rand(NUM_ENVS, 16, generator=generator) - 1))
    try:
        rot = rotation_distance(env.object_rot, env.goal_rot)
        cfg.success_tolerance = float(rot.sort().values[1]) + 1e-4  # two envs within it
        cfg.fall_dist = float((env.object_pos - env.in_hand_pos).norm(dim=-1).max()) - 1e-6  # one fallen
        terminated, time_out = env._get_dones()
        assert terminated.sum() == 1
        env.reset_buf.copy_(terminated | torch.tensor([True, False, False, False]))
        env.reset_goal_buf.copy_(rot == rot.max())  # flagged, not within the tolerance
        env.successes.copy_(torch.tensor([2.0, 0.0, 1.0, 3.0]))
        env.consecutive_successes.fill_(0.5)
        expected = compute_rewards(
            env.reset_buf, env.reset_goal_buf.clone(), env.successes.clone(), env.consecutive_successes.clone(),
            env.object_pos, env.object_rot, env.in_hand_pos, env.goal_rot, cfg.dist_reward_scale,
            cfg.rot_reward_scale, cfg.rot_eps, env.actions, cfg.action_penalty_scale, cfg.success_tolerance,
            cfg.reach_goal_bonus, cfg.fall_dist, cfg.fall_penalty, cfg.av_factor,
        )  # fmt: skip
        reward = env._get_rewards()
    finally:
        env.close()
    assert expected[1].sum() >= 3  # reached or flagged: the bonus is paid somewhere, not everywhere
    torch.testing.assert_close(reward, expected[0], rtol=1e-6, atol=1e-5)
    assert torch.equal(env.successes, expected[2])
    torch.testing.assert_close(env.consecutive_successes, expected[3], rtol=1e-6, atol=0)
    assert not env.reset_goal_buf.any(), "the reached goals were redrawn at once"


def test_allegro_joint_writes_and_speed_cap_in_column_order():
    """The Allegro Hand's joints (breadth-first names) sit in consecutive qpos/qvel columns in another
    order: masked state writes and the speed cap work over those columns in place; each joint still gets
    its own value and its own limit."""
    env = make(ALLEGRO)
    try:
        hand = env.hand
        assert hand._dof_span is not None and hand._qpos_span is not None  # the case these paths serve
        n, joints = NUM_ENVS, hand.num_joints
        before_pos, before_vel = hand.data.joint_pos.clone(), hand.data.joint_vel.clone()
        pos = 0.01 * torch.arange(joints).repeat(n, 1) + torch.arange(n)[:, None]
        mask = torch.tensor([True, False, True, False])
        hand.write_joint_state_to_sim(pos, 100.0 * pos + 1.0, env_ids=mask)
        assert torch.equal(hand.data.joint_pos[mask], pos[mask])
        assert torch.equal(hand.data.joint_vel[mask], (100.0 * pos + 1.0)[mask])
        assert torch.equal(hand.data.joint_pos[~mask], before_pos[~mask])
        assert torch.equal(hand.data.joint_vel[~mask], before_vel[~mask])
        limits = 0.5 + 0.25 * torch.arange(joints, dtype=torch.float32)  # one per joint
        hand.write_joint_velocity_limit_to_sim(limits.repeat(n, 1))
        velocity = torch.full((n, joints), 1e3)
        velocity[1] = -1e3
        velocity[3, 5] = 0.1  # within its limit: kept
        hand.write_joint_velocity_to_sim(velocity)
        hand.write_data_to_sim()
        expected = torch.maximum(torch.minimum(velocity, limits), -limits)
        assert torch.equal(hand.data.joint_vel, expected)
    finally:
        env.close()


def test_the_action_scale_rounds_as_isaac_lab_s_formula():
    """The targets go to the physics: fewer kernels, the same bits (0.5 t is exact in floating point)."""
    from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import scale

    generator = torch.Generator().manual_seed(0)
    x = 4 * torch.rand(1000, 16, generator=generator) - 2
    lower = -torch.rand(1000, 16, generator=generator)
    upper = torch.rand(1000, 16, generator=generator) + 0.1
    assert torch.equal(scale(x, lower, upper), 0.5 * (x + 1.0) * (upper - lower) + lower)


def test_solve_criterion_counts_the_goals_of_finished_episodes(allegro):
    from simlab.tasks.utils.criteria import criterion_for

    criterion = criterion_for(ALLEGRO)
    assert ">= 5 goal orientations" in criterion.description and criterion.min_seconds > 10.0
    on_step, sums = criterion.make_hook()
    env = allegro
    env.reset_buf[:] = torch.tensor([True, True, False, False])
    env.episode_successes[:] = torch.tensor([6.0, 2.0, 9.0, 9.0])  # envs 2 and 3 are still running
    on_step(env, None, None)
    assert sums == {"successes": 8.0, "episodes": 2}
    assert criterion.judge({}, sums) == (4.0, False)
    sums["successes"] += 3.0
    assert criterion.judge({}, sums) == (5.5, True)


def test_allegro_agent_configs_follow_isaac_lab():
    from simlab.tasks.utils import load_cfg_from_registry

    rsl = load_cfg_from_registry(ALLEGRO, "rsl_rl_cfg_entry_point")
    rsl.to_rsl_rl_dict()  # validates: no MISSING field left
    assert (rsl.num_steps_per_env, rsl.max_iterations, rsl.experiment_name) == (16, 10000, "allegro_hand")
    assert rsl.actor.hidden_dims == [1024, 512, 256, 128] and rsl.algorithm.desired_kl == 0.016
    skrl = load_cfg_from_registry(ALLEGRO, "skrl_cfg_entry_point")
    assert skrl["agent"]["rollouts"] == 16 and skrl["trainer"]["timesteps"] == 80000
    rlg = load_cfg_from_registry(ALLEGRO, "rl_games_cfg_entry_point")
    config = rlg["params"]["config"]
    assert config["minibatch_size"] == 32768 and config["max_epochs"] == 5000 and config["torch_compile"] is False


# -- manager-based: simlab/Repose-Cube-Allegro-v0 ---------------------------------------------------------

ALLEGRO_MANAGER = "simlab/Repose-Cube-Allegro-v0"


@pytest.fixture(scope="module")
def allegro_manager():
    env = make(ALLEGRO_MANAGER)
    yield env
    env.close()


def test_allegro_manager_steps_with_finite_values_and_targets_within_limits(allegro_manager):
    env = allegro_manager
    assert env.single_observation_space["policy"].shape == (72,)
    assert env.single_action_space.shape == (16,)
    assert env.graph_blockers() == []
    robot = env.scene["robot"]
    limits = robot.data.soft_joint_pos_limits
    generator = torch.Generator().manual_seed(0)
    for _ in range(20):
        obs, reward, *_ = env.step(3 * torch.rand(NUM_ENVS, 16, generator=generator) - 1.5)  # beyond [-1, 1] too
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        targets = robot.data.joint_pos_target
        assert ((targets >= limits[..., 0] - 1e-6) & (targets <= limits[..., 1] + 1e-6)).all()


def test_allegro_manager_goal_is_redrawn_on_success_and_counted(allegro_manager):
    env = allegro_manager
    env.reset(seed=2)
    command = env.command_manager.get_term("object_pose")
    cube = env.scene["object"]
    old_goal = command.quat_command_w.clone()
    pose = torch.cat((cube.data.root_pos_w, old_goal), dim=-1)[:1]
    cube.write_root_pose_to_sim(pose, env_ids=torch.tensor([0]))
    cube.write_root_velocity_to_sim(torch.zeros(1, 6), env_ids=torch.tensor([0]))
    robot = env.scene["robot"]
    lower, upper = robot.data.soft_joint_pos_limits[..., 0], robot.data.soft_joint_pos_limits[..., 1]
    hold = unscale(robot.data.joint_pos, lower, upper)  # targets at the joints' positions (alpha 0.95 keeps them)
    _, reward, terminated, truncated, _ = env.step(hold)
    assert not (terminated | truncated).any()
    bonus = 250.0 * env.step_dt  # manager-based rewards are weight * term * dt
    assert float(reward[0]) > bonus and float(reward[1:].max()) < bonus
    assert command.metrics["consecutive_success"].tolist() == [1.0, 0.0, 0.0, 0.0]
    assert not torch.allclose(command.quat_command_w[0], old_goal[0])
    torch.testing.assert_close(command.quat_command_w[1:], old_goal[1:])
    # the episode's end keeps its count for the criterion
    env.episode_length_buf[0] = env.max_episode_length - 1
    _, _, _, truncated, _ = env.step(unscale(robot.data.joint_pos, lower, upper))
    assert bool(truncated[0]) and float(command.episode_successes[0]) == 1.0
    assert float(command.metrics["consecutive_success"][0]) == 0.0


def test_allegro_manager_orientation_error_is_computed_once_per_state_and_goal(allegro_manager, monkeypatch):
    """The bonus and the tracking reward read one angle to the goal per state and goal; a new goal or
    a state write computes it again (Isaac Lab's quat_error_magnitude)."""
    from simlab.tasks.manager_based.manipulation.inhand import mdp
    from simlab.utils.math import quat_error_magnitude

    env = allegro_manager
    env.step(torch.zeros(NUM_ENVS, 16))
    command = env.command_manager.get_term("object_pose")
    cube = env.scene["object"]

    def expected() -> torch.Tensor:
        return quat_error_magnitude(cube.data.root_quat_w, command.quat_command_w)

    first = mdp.track_orientation_inv_l2(env, "object_pose")
    torch.testing.assert_close(first, 1.0 / (expected() + 1e-3))
    calls = []
    monkeypatch.setattr(mdp.rewards.math_utils, "quat_error_magnitude", lambda *a: calls.append(1) or expected())
    mdp.success_bonus(env, "object_pose")
    assert calls == [], "the second term reuses the first one's angle"
    command._resample_command(torch.tensor([True, False, False, False]))  # a new goal for env 0
    torch.testing.assert_close(mdp.track_orientation_inv_l2(env, "object_pose"), 1.0 / (expected() + 1e-3))
    pose = torch.cat((cube.data.root_pos_w, command.quat_command_w), dim=-1)
    cube.write_root_pose_to_sim(pose, env_ids=torch.tensor([True, True, False, False]))  # a state write
    bonus = mdp.success_bonus(env, "object_pose")
    assert len(calls) == 2 and bonus[:2].tolist() == [1.0, 1.0]
    torch.testing.assert_close(bonus, (expected() <= command.cfg.orientation_success_threshold).float())


def test_allegro_manager_play_variant_and_agent_configs():
    from simlab.tasks.utils import load_cfg_from_registry

    play = parse_env_cfg("simlab/Repose-Cube-Allegro-Play-v0", device="cpu")
    assert play.scene.num_envs == 50 and play.terminations.time_out is None
    assert play.observations.policy.enable_corruption is False
    rsl = load_cfg_from_registry(ALLEGRO_MANAGER, "rsl_rl_cfg_entry_point")
    rsl.to_rsl_rl_dict()
    assert (rsl.num_steps_per_env, rsl.max_iterations, rsl.experiment_name) == (24, 5000, "allegro_cube")
    assert rsl.algorithm.gamma == 0.998 and rsl.actor.hidden_dims == [512, 256, 128]
    skrl = load_cfg_from_registry(ALLEGRO_MANAGER, "skrl_cfg_entry_point")
    assert skrl["agent"]["rollouts"] == 24 and skrl["agent"]["mini_batches"] == 12
    rlg = load_cfg_from_registry(ALLEGRO_MANAGER, "rl_games_cfg_entry_point")
    assert rlg["params"]["config"]["horizon_length"] == 24 and rlg["params"]["config"]["minibatch_size"] == 16384
    from simlab.tasks.utils.criteria import criterion_for

    assert criterion_for(ALLEGRO_MANAGER).min_seconds > 20.0


# -- direct Shadow Hand: simlab/Repose-Cube-Shadow-Direct-v0 ------------------------------------------------

SHADOW = "simlab/Repose-Cube-Shadow-Direct-v0"


def test_shadow_direct_steps_with_finite_values_and_coupled_distal_joints():
    env = make(SHADOW)
    try:
        assert env.single_observation_space["policy"].shape == (157,)
        assert env.single_action_space.shape == (20,)
        assert env.graph_blockers() == []
        assert len(env.actuated_dof_indices) == 20 and env.num_fingertips == 5
        names = env.hand.joint_names
        middle = [names.index(f"robot0_{f}J1") for f in ("FF", "MF", "RF", "LF")]
        distal = [names.index(f"robot0_{f}J0") for f in ("FF", "MF", "RF", "LF")]
        generator = torch.Generator().manual_seed(0)
        for _ in range(20):
            obs, reward, *_ = env.step(2 * torch.rand(NUM_ENVS, 20, generator=generator) - 1)
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
            gap = (env.hand.data.joint_pos[:, distal] - env.hand.data.joint_pos[:, middle]).abs().max()
            assert float(gap) < 0.05  # the distal joints follow the middle ones under random actions
        from simlab.tasks.utils import load_cfg_from_registry

        rsl = load_cfg_from_registry(SHADOW, "rsl_rl_cfg_entry_point")
        assert rsl.actor.hidden_dims == [512, 512, 256, 128] and rsl.experiment_name == "shadow_hand"
    finally:
        env.close()


@pytest.mark.slow
@pytest.mark.parametrize("task", [ALLEGRO, SHADOW])
def test_contact_buffers_cover_the_peaks_of_random_play(task):
    """MuJoCo Warp's kernels on Warp's CPU device, the task's own buffers (an overflow raises), short
    episodes so that the rollout crosses resets: twice the peak contacts and constraint rows fit."""
    pytest.importorskip("mujoco_warp")
    from simlab.tasks.utils.contact_buffers import measure_task_buffers

    peaks, diverged, reserved = measure_task_buffers(task, num_envs=4, env_steps=60, headroom=1, episode_length_s=0.5)
    assert diverged == 0
    assert peaks.contacts_per_world > 0  # the cube touches the hand: the count means something
    assert reserved["nconmax"] >= 2 * peaks.contacts_per_world
    assert reserved["njmax"] >= 2 * peaks.constraint_rows


def test_allegro_direct_step_stays_within_its_kernel_budget():
    """The direct Allegro step outside the physics (``simlab bench ops step``, GPU backend counted on
    Warp's CPU device, docs/dexterous.md): 380 torch kernels and two forward passes (212 MuJoCo Warp
    launches) per step before issue 40's cuts, 232 and one (106) after; with the CPU backend this test
    uses, 245 and one forward, then 262 with the NaN check's per-term accumulators and the divergence
    guard's restart clearing the actuator's efforts (by mask, every step); 196 after issue 40.4's cuts
    (fused PD control and speed cap per physics step, the reward and targets in place, fingertip and
    joint quantities computed where the observations read them, one-kernel divergence test per array,
    masked joint writes in column order, unscale in three kernels; what reaches the physics rounds as
    before, so a seeded rollout's states stay bit-identical)."""
    from simlab.benchmarks import step_ops

    env = step_ops.make_env(ALLEGRO, num_envs=4, seed=0, engine="mujoco")
    forwards = []
    original_forward = env.sim.physics.forward
    env.sim.physics.forward = lambda *args, **kwargs: forwards.append(1) or original_forward(*args, **kwargs)
    counter = step_ops.LaunchCounter()
    step_ops.instrument(env, counter)
    env.reset()
    actions = hold_actions(env)
    with torch.inference_mode(), counter:
        env.step(actions)  # warm-up
        forwards.clear()
        env.episode_length_buf[:] = env.max_episode_length - 1  # every env resets in the counted step
        counter.active = True
        _, _, _, truncated, _ = env.step(actions)
        counter.active = False
    env.close()
    assert truncated.all()
    assert len(forwards) == 1, "one forward pass per step: the fingertips' poses the observations read (after resets)"
    outside = sum(n for label, n in counter.torch_ops.items() if label != "physics")
    assert outside <= 196, f"{outside} torch kernels per step outside the physics:\n{step_ops.report(counter, 1, 3)}"


def test_the_graphed_allegro_step_copies_back_one_tensor_per_replay(emulated_cuda_graph):  # noqa: F811
    """What the step binds anew each replay of the captured step copies back (``tensor_slots``): the
    direct task writes its own tensors in place, so only the cube's per-state angular velocity is left
    (11 copies per replay before issue 40.4)."""
    env = graphed_allegro_env()
    rebound = [path for *_, path in env._stepper._slots.written]
    assert env._stepper.write_backs <= 1, rebound
    env.close()


@pytest.mark.parametrize("task", [ALLEGRO, SHADOW, "simlab/Repose-Cube-Shadow-OpenAI-FF-Direct-v0"])
def test_contact_buffers_hold_the_cube_squeezed_by_the_closed_hand(task):
    """The worst case the buffers must hold: the cube at its in-hand position, pressed into the hand by
    every finger closing on it (world 0: every joint at its upper limit; the others at random points
    between the default pose and the upper limits). The worlds run on the CPU backend; after every
    physics step MuJoCo C counts each world's contacts and constraint rows on the task's model. The
    task's per-world nconmax and njmax (what MuJoCo Warp reserves) hold 1.5 times the peaks: MuJoCo
    Warp's collision functions are its own, so a pair may give a few more contacts there."""
    import mujoco

    cfg = parse_env_cfg(task, device="cpu", num_envs=4)
    cfg.seed = 0
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        env.reset(seed=0)
        hand, cube, physics = env.hand, env.object, env.sim.physics
        model, data = env.sim.model, mujoco.MjData(env.sim.model)
        default, upper = hand.data.default_joint_pos, env.hand_dof_upper_limits
        share = torch.rand(4, 1, generator=torch.Generator().manual_seed(0))
        share[0] = 1.0
        targets = default + share * (upper - default)
        pose = torch.cat((env.in_hand_pos + env.scene.env_origins, env.object.data.default_root_state[:, 3:7]), -1)
        cube.write_root_pose_to_sim(pose)
        cube.write_root_velocity_to_sim(torch.zeros(4, 6))
        qpos, qvel = physics.data("qpos"), physics.data("qvel")
        contacts, rows = [0] * 4, [0] * 4
        for _ in range(round(2.0 / env.physics_dt)):  # 2 s
            hand.set_joint_position_target(targets)
            env.scene.write_data_to_sim()
            env.sim.step(render=False)
            for world in range(4):
                data.qpos[:], data.qvel[:] = qpos[world].numpy(), qvel[world].numpy()
                mujoco.mj_forward(model, data)
                contacts[world], rows[world] = max(contacts[world], data.ncon), max(rows[world], data.nefc)
        # the closed hand grips the cube: several of its bodies touch it
        data.qpos[:] = qpos[0].numpy()
        mujoco.mj_forward(model, data)
        cube_body = cube._body_ids[0]
        pairs = [(model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]) for c in data.contact[: data.ncon]]
        touching = {a if b == cube_body else b for a, b in pairs if cube_body in (a, b)}
        assert len(touching) >= 4, [model.body(b).name for b in touching]
        # peaks measured: Allegro 30 / 136 (28 / 128 at kp 3), Shadow 19 / 104, OpenAI-FF 20 / 108
        reserved = cfg.sim.mujoco
        assert reserved.nconmax >= 1.5 * max(contacts), f"contacts per world {contacts}, nconmax {reserved.nconmax}"
        assert reserved.njmax >= 1.5 * max(rows), f"constraint rows per world {rows}, njmax {reserved.njmax}"
    finally:
        env.close()


def test_the_rotation_distances_stay_finite_at_their_edge_cases():
    """Finite physics gives finite rewards: the two in-hand rotation distances (direct: asin of the
    difference's vector part; manager: ``quat_error_magnitude``) at identical, sign-flipped and opposite
    orientations, at |q| slightly above 1 from float error (asin's argument clamped), and at a zero quaternion."""
    from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import compute_rewards
    from simlab.utils.math import quat_error_magnitude

    identity = torch.tensor([1.0, 0.0, 0.0, 0.0])
    half_turn_x = torch.tensor([0.0, 1.0, 0.0, 0.0])
    tilted = torch.nn.functional.normalize(torch.tensor([0.3, 0.9, -0.2, 0.25]), dim=0)
    q1 = torch.stack([identity, tilted, -tilted, half_turn_x * (1 + 1e-6), tilted * (1 + 1e-6), torch.zeros(4)])
    q2 = torch.stack([identity, tilted, tilted, identity, -tilted * (1 + 1e-6), identity])
    expected = torch.tensor([0.0, 0.0, 0.0, torch.pi, 0.0, 0.0])
    for distance in (rotation_distance, quat_error_magnitude):
        angle = distance(q1, q2)
        assert torch.isfinite(angle).all(), distance.__name__
        torch.testing.assert_close(angle, expected, atol=2e-3, rtol=0)  # float32 asin near 1: ~1e-3
    n = len(q1)
    reward, *_ = compute_rewards(
        torch.zeros(n, dtype=torch.bool), torch.zeros(n, dtype=torch.bool), torch.zeros(n), torch.zeros(1),
        torch.zeros(n, 3), q1, torch.zeros(n, 3), q2,
        -10.0, 1.0, 0.1, torch.zeros(n, 16), -0.0002, 0.2, 250.0, 0.24, 0.0, 0.1,
    )  # fmt: skip
    assert torch.isfinite(reward).all()
