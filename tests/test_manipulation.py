"""Manipulation MDP pieces and tasks: frame transformer, pose command, gripper and IK actions, the reach
and lift terms, and the registered Franka tasks (a few CPU steps each, and a scripted grasp)."""

from __future__ import annotations

from dataclasses import MISSING

import gymnasium as gym
import pytest
import torch
from test_franka_dynamics import FrankaSceneCfg

import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401 - registers the tasks
import simlab.utils.math as math_utils
from simlab.assets import RigidObjectCfg
from simlab.envs import ManagerBasedRLEnv
from simlab.managers import SceneEntityCfg
from simlab.scene import InteractiveScene
from simlab.sensors import FrameTransformerCfg, OffsetCfg
from simlab.tasks.manager_based.manipulation.lift import mdp as lift_mdp
from simlab.tasks.manager_based.manipulation.lift.config.franka import ik_abs_env_cfg as lift_ik_abs
from simlab.tasks.manager_based.manipulation.lift.config.franka import joint_pos_env_cfg as lift_joint_pos
from simlab.tasks.manager_based.manipulation.lift.config.franka.joint_pos_env_cfg import CUBE_MJCF
from simlab.tasks.manager_based.manipulation.reach import mdp as reach_mdp
from simlab.tasks.manager_based.manipulation.reach.config.franka import ik_abs_env_cfg as reach_ik_abs
from simlab.tasks.manager_based.manipulation.reach.config.franka import joint_pos_env_cfg as reach_joint_pos
from simlab.tasks.manager_based.manipulation.reach.config.franka import osc_env_cfg as reach_osc
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.utils import configclass

TASKS = [
    "simlab/Reach-Franka-v0",
    "simlab/Reach-Franka-Play-v0",
    "simlab/Reach-Franka-IK-Abs-v0",
    "simlab/Reach-Franka-IK-Rel-v0",
    "simlab/Reach-Franka-OSC-v0",
    "simlab/Lift-Cube-Franka-v0",
    "simlab/Lift-Cube-Franka-Play-v0",
    "simlab/Lift-Cube-Franka-IK-Abs-v0",
    "simlab/Lift-Cube-Franka-IK-Rel-v0",
]


def make_env(cfg_class, num_envs: int = 2, **changes) -> ManagerBasedRLEnv:
    cfg = cfg_class()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    cfg.seed = 0
    for path, value in changes.items():
        owner = cfg
        *parents, leaf = path.split(".")
        for p in parents:
            owner = getattr(owner, p)
        setattr(owner, leaf, value)
    return ManagerBasedRLEnv(cfg)


# -- frame transformer -------------------------------------------------------------------------------


@configclass
class FrankaCubeSceneCfg(FrankaSceneCfg):
    cube = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Object",
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.5, 0.1, 0.3)),
        spawn=sim_utils.MjcfFileCfg(asset_path=CUBE_MJCF),
    )
    ee_frame: FrameTransformerCfg = MISSING


def frame_scene(ee_frame: FrameTransformerCfg):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.01, device="cpu"))
    cfg = FrankaCubeSceneCfg(num_envs=2, env_spacing=2.0, ee_frame=ee_frame)
    scene = InteractiveScene(cfg)
    sim.reset()
    return sim, scene


def test_frame_transformer_gives_offset_frames_in_world_and_source():
    ee = FrameTransformerCfg(
        prim_path="{ENV_REGEX_NS}/Robot/panda_link0",
        target_frames=[
            FrameTransformerCfg.FrameCfg(
                prim_path="{ENV_REGEX_NS}/Robot/panda_hand",
                name="end_effector",
                offset=OffsetCfg(pos=(0.0, 0.0, 0.1034)),
            ),
            FrameTransformerCfg.FrameCfg(prim_path="{ENV_REGEX_NS}/Robot/panda_.*finger"),
            FrameTransformerCfg.FrameCfg(prim_path="{ENV_REGEX_NS}/Object"),
        ],
    )
    sim, scene = frame_scene(ee_frame=ee)
    robot, cube, sensor = scene["robot"], scene["cube"], scene["ee_frame"]
    data = sensor.data
    assert data.target_frame_names == ["end_effector", "panda_leftfinger", "panda_rightfinger", "Object"]
    hand = robot.find_bodies("panda_hand")[0][0]
    expected = robot.data.body_pos_w[:, hand] + math_utils.quat_apply(
        robot.data.body_quat_w[:, hand], torch.tensor([0.0, 0.0, 0.1034]).repeat(2, 1)
    )
    torch.testing.assert_close(data.target_pos_w[:, 0], expected)
    torch.testing.assert_close(data.target_quat_w[:, 0], robot.data.body_quat_w[:, hand])
    torch.testing.assert_close(data.target_pos_w[:, 3], cube.data.root_pos_w)
    # the source is the fixed base at each env's origin, unrotated: source-frame = world minus origin
    torch.testing.assert_close(data.source_pos_w, scene.env_origins)
    torch.testing.assert_close(data.target_pos_source, data.target_pos_w - scene.env_origins[:, None])
    torch.testing.assert_close(data.target_pos_source[:, 3], torch.tensor([[0.5, 0.1, 0.3]] * 2))
    # the frames follow the robot
    q = robot.data.joint_pos.clone()
    q[:, 0] += 0.5
    robot.write_joint_position_to_sim(q)
    yaw = math_utils.quat_from_euler_xyz(torch.zeros(2), torch.zeros(2), torch.full((2,), 0.5))
    moved = math_utils.quat_apply(yaw, expected - scene.env_origins) + scene.env_origins
    torch.testing.assert_close(data.target_pos_w[:, 0], moved, atol=1e-5, rtol=0)


def test_frame_transformer_errors_name_what_exists():
    bad_body = FrameTransformerCfg(
        prim_path="{ENV_REGEX_NS}/Robot/panda_link0",
        target_frames=[FrameTransformerCfg.FrameCfg(prim_path="{ENV_REGEX_NS}/Robot/panda_eef")],
    )
    with pytest.raises(ValueError, match="no body of 'Robot' matches 'panda_eef'.*panda_hand"):
        frame_scene(ee_frame=bad_body)
    sim_utils.SimulationContext.clear_instance()
    named_regex = FrameTransformerCfg(
        prim_path="{ENV_REGEX_NS}/Robot/panda_link0",
        target_frames=[FrameTransformerCfg.FrameCfg(prim_path="{ENV_REGEX_NS}/Robot/panda_.*finger", name="tips")],
    )
    with pytest.raises(ValueError, match="matches 2 bodies"):
        frame_scene(ee_frame=named_regex)
    sim_utils.SimulationContext.clear_instance()
    bad_entity = FrameTransformerCfg(prim_path="{ENV_REGEX_NS}/Gripper/hand", target_frames=[])
    with pytest.raises(ValueError, match=r"no entity 'Gripper'; entities: \['Object', 'Robot'\]"):
        frame_scene(ee_frame=bad_entity)


# -- commands, rewards, observations -----------------------------------------------------------------


def test_pose_command_samples_in_its_ranges_and_measures_the_body():
    env = make_env(reach_joint_pos.FrankaReachEnvCfg, num_envs=8)
    env.reset()
    term = env.command_manager.get_term("ee_pose")
    command = env.command_manager.get_command("ee_pose")
    r = term.cfg.ranges
    for axis, (low, high) in enumerate((r.pos_x, r.pos_y, r.pos_z)):
        assert ((command[:, axis] >= low) & (command[:, axis] <= high)).all()
    # roll 0, pitch pi: the commanded hand's z axis points down whatever the yaw
    z_axis = math_utils.quat_apply(command[:, 3:7], torch.tensor([0.0, 0.0, 1.0]).repeat(8, 1))
    torch.testing.assert_close(z_axis, torch.tensor([0.0, 0.0, -1.0]).repeat(8, 1), atol=1e-5, rtol=0)
    env.step(torch.zeros(8, env.action_manager.total_action_dim))
    robot = env.scene["robot"]
    hand = robot.find_bodies("panda_hand")[0][0]
    goal_w = command[:, :3] + env.scene.env_origins
    torch.testing.assert_close(
        term.metrics["position_error"], (robot.data.body_pos_w[:, hand] - goal_w).norm(dim=-1), atol=1e-5, rtol=0
    )
    asset_cfg = SceneEntityCfg("robot", body_names=["panda_hand"])
    asset_cfg.resolve(env.scene)
    err = reach_mdp.position_command_error(env, "ee_pose", asset_cfg)
    torch.testing.assert_close(err, term.metrics["position_error"], atol=1e-5, rtol=0)
    torch.testing.assert_close(
        reach_mdp.position_command_error_tanh(env, 0.1, "ee_pose", asset_cfg), 1 - torch.tanh(err / 0.1)
    )
    torch.testing.assert_close(
        reach_mdp.orientation_command_error(env, "ee_pose", asset_cfg),
        term.metrics["orientation_error"],
        atol=1e-4,
        rtol=0,
    )
    torch.testing.assert_close(
        reach_mdp.orientation_command_error_tanh(env, 0.1, "ee_pose", asset_cfg),
        1 - torch.tanh(term.metrics["orientation_error"] / 0.1),
        atol=1e-4,
        rtol=0,
    )
    env.close()


def test_lift_terms_measure_the_object():
    env = make_env(lift_joint_pos.FrankaCubeLiftEnvCfg, num_envs=2)
    env.reset()
    cube, robot = env.scene["object"], env.scene["robot"]
    pose = torch.tensor([[0.5, 0.0, 0.3, 1, 0, 0, 0], [0.6, -0.1, 0.02, 1, 0, 0, 0]], dtype=torch.float32)
    pose[:, :3] += env.scene.env_origins
    cube.write_root_pose_to_sim(pose)
    torch.testing.assert_close(lift_mdp.object_is_lifted(env, 0.04), torch.tensor([1.0, 0.0]))
    torch.testing.assert_close(
        lift_mdp.object_position_in_robot_root_frame(env), torch.tensor([[0.5, 0.0, 0.3], [0.6, -0.1, 0.02]])
    )
    ee = env.scene["ee_frame"].data.target_pos_w[:, 0]
    torch.testing.assert_close(
        lift_mdp.object_ee_distance(env, 0.1), 1 - torch.tanh((pose[:, :3] - ee).norm(dim=-1) / 0.1)
    )
    goal = env.command_manager.get_command("object_pose")[:, :3] + env.scene.env_origins
    expected = torch.tensor([1.0, 0.0]) * (1 - torch.tanh((goal - pose[:, :3]).norm(dim=-1) / 0.3))
    torch.testing.assert_close(lift_mdp.object_goal_distance(env, 0.3, 0.04, "object_pose"), expected)
    assert not lift_mdp.object_reached_goal(env).any()
    assert robot.data.joint_pos.shape == (2, 9)
    env.close()


# -- actions -----------------------------------------------------------------------------------------


def test_binary_gripper_action_opens_and_closes():
    env = make_env(lift_joint_pos.FrankaCubeLiftEnvCfg, num_envs=2)
    env.reset()
    term = env.action_manager.get_term("gripper_action")
    assert term.action_dim == 1
    action = torch.zeros(2, env.action_manager.total_action_dim)
    action[:, -1] = torch.tensor([-1.0, 1.0])
    for _ in range(15):
        env.step(action)
    fingers = env.scene["robot"].find_joints("panda_finger.*")[0]
    torch.testing.assert_close(term.processed_actions, torch.tensor([[0.0, 0.0], [0.04, 0.04]]))
    q = env.scene["robot"].data.joint_pos[:, fingers]
    assert (q[0] < 0.003).all() and (q[1] > 0.037).all()
    env.close()


def test_osc_action_with_closed_loop_force_control_is_refused():
    with pytest.raises(ValueError, match="contact_wrench_stiffness_task .*current_ee_force_b"):
        make_env(
            reach_osc.FrankaReachEnvCfg, **{"actions.arm_action.controller_cfg.contact_wrench_stiffness_task": 0.1}
        )


def test_gripper_config_without_finger_joints_is_refused():
    with pytest.raises(ValueError, match="match no finger joint of 'robot'.*Available strings"):
        make_env(
            lift_joint_pos.FrankaCubeLiftEnvCfg,
            **{"actions.gripper_action.joint_names": ["gripper_.*"]},
        )
    sim_utils.SimulationContext.clear_instance()
    with pytest.raises(ValueError, match=r"gives no value for the joints \['panda_finger_joint2'\]"):
        make_env(
            lift_joint_pos.FrankaCubeLiftEnvCfg,
            **{"actions.gripper_action.open_command_expr": {"panda_finger_joint1": 0.04}},
        )


def test_ik_action_for_a_missing_body_lists_the_bodies():
    with pytest.raises(ValueError, match="Unmatched keys: \\['panda_eef'\\].*panda_hand"):
        make_env(reach_ik_abs.FrankaReachEnvCfg, **{"actions.arm_action.body_name": "panda_eef"})


def test_absolute_ik_action_moves_the_end_effector_frame_to_the_commanded_pose():
    env = make_env(reach_ik_abs.FrankaReachEnvCfg, num_envs=2)
    env.reset()
    term = env.action_manager.get_term("arm_action")
    assert term.action_dim == 7
    pos, quat = term._ee_pose_b()
    target = torch.cat([pos + torch.tensor([[0.1, -0.05, -0.08], [-0.05, 0.12, 0.05]]), quat], dim=-1)
    # the task's actions span the workspace: command = action * scale + offset
    action = (target - torch.tensor(term.cfg.offset)) / torch.tensor(term.cfg.scale)
    for _ in range(240):  # the damped (lambda 0.45) IK closes the error in a few seconds
        env.step(action)
    pos, quat = term._ee_pose_b()
    assert (pos - target[:, :3]).norm(dim=-1).max() < 2e-3
    assert math_utils.quat_error_magnitude(quat, target[:, 3:]).max() < 1e-2
    # the frame is 0.107 m along the hand's z axis
    robot = env.scene["robot"]
    hand = robot.find_bodies("panda_hand")[0][0]
    tip = robot.data.body_pos_w[:, hand] + math_utils.quat_apply(
        robot.data.body_quat_w[:, hand], torch.tensor([0.0, 0.0, 0.107]).repeat(2, 1)
    )
    torch.testing.assert_close(tip - env.scene.env_origins, pos, atol=1e-5, rtol=0)
    env.close()


def test_absolute_ik_reach_stays_bounded_under_random_actions():
    """An untrained policy's Gaussian actions (random, often unreachable poses, quaternions of any
    length): the arm moves within the Franka's joint speed limits (applied before each physics step,
    as PhysX does in its solver) and nothing blows up. Before the limits and the normalized targets,
    saturated drives spun joints to 1e5 rad/s and MuJoCo reported an unstable simulation."""
    env = make_env(reach_ik_abs.FrankaReachEnvCfg, num_envs=16)
    env.reset()
    robot = env.scene["robot"]
    arm = robot.find_joints("panda_joint.*")[0]
    torch.testing.assert_close(robot.data.joint_velocity_limits[0, arm], torch.tensor([2.175] * 4 + [2.61] * 3))
    generator = torch.Generator().manual_seed(0)
    fastest, lowest = 0.0, 0.0
    for _ in range(90):
        _, reward, *_ = env.step(torch.randn(16, 7, generator=generator))
        assert torch.isfinite(robot.data.joint_pos).all() and torch.isfinite(reward).all()
        fastest = max(fastest, robot.data.joint_vel[:, arm].abs().max().item())
        lowest = min(lowest, reward.min().item())
    # one physics step at the effort limit adds a few rad/s to a capped speed; 1e5 was the blow-up
    assert fastest < 15.0
    assert lowest > -0.1
    env.close()


def test_a_scripted_ik_grasp_lifts_the_cube():
    """Hand above the cube, down, close, up (targets interpolated, hand pointing straight down): the
    pads hold the cube, so the lift task is solvable."""
    env = make_env(lift_ik_abs.FrankaCubeLiftEnvCfg, num_envs=2)
    env.reset()
    cube = env.scene["object"]
    term = env.action_manager.get_term("arm_action")
    ee, _ = term._ee_pose_b()
    down = torch.tensor([[0.0, 1.0, 0.0, 0.0]]).repeat(2, 1)  # hand z along -z, fingers along world y
    for _ in range(20):  # the cube settles on the table
        env.step(torch.cat([ee, down, torch.ones(2, 1)], dim=-1))
    start = (cube.data.root_pos_w - env.scene.env_origins).clone()

    def go(offset, gripper: float, steps: int, move_steps: int):
        nonlocal ee
        goal = start + torch.tensor(offset)
        for i in range(steps):
            along = min(1.0, (i + 1) / move_steps)
            env.step(torch.cat([ee + along * (goal - ee), down, torch.full((2, 1), gripper)], dim=-1))
        ee = goal

    go([0.0, 0.0, 0.12], 1.0, 60, 40)
    go([0.0, 0.0, 0.0], 1.0, 40, 25)
    go([0.0, 0.0, 0.0], -1.0, 20, 1)
    go([0.0, 0.0, 0.25], -1.0, 60, 40)
    lifted = cube.data.root_pos_w - env.scene.env_origins
    assert (lifted[:, 2] > start[:, 2] + 0.2).all(), lifted
    torch.testing.assert_close(lifted[:, :2], start[:, :2], atol=0.01, rtol=0)
    env.close()


def test_operational_space_action_tracks_the_commanded_pose():
    env = make_env(reach_osc.FrankaReachEnvCfg, num_envs=2)
    env.reset()
    term = env.action_manager.get_term("arm_action")
    assert term.action_dim == 13
    pos, quat = term._ee_pose_b()
    target = torch.cat([pos + torch.tensor([[0.08, -0.05, -0.06], [-0.05, 0.08, 0.05]]), quat], dim=-1)
    stiffness = torch.full((2, 6), 1.5)  # x stiffness_scale 100: 150, inside the limits (50, 200)
    for _ in range(100):  # 3.3 s
        env.step(torch.cat([target, stiffness], dim=-1))
    pos, quat = term._ee_pose_b()
    assert (pos - target[:, :3]).norm(dim=-1).max() < 5e-3
    assert math_utils.quat_error_magnitude(quat, target[:, 3:]).max() < 0.02
    torch.testing.assert_close(term._osc._kp, torch.full((2, 6), 150.0))
    env.close()


# -- the registered tasks ------------------------------------------------------------------------


@pytest.mark.parametrize("task", TASKS)
def test_task_steps_on_the_cpu(task):
    cfg = parse_env_cfg(task, device="cpu", num_envs=4)
    env = gym.make(task, cfg=cfg)
    obs, _ = env.reset(seed=0)
    u = env.unwrapped
    dim = u.action_manager.total_action_dim
    for _ in range(5):
        obs, reward, terminated, truncated, extras = env.step(torch.rand(4, dim) * 2 - 1)
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    assert obs["policy"].shape[0] == 4 and reward.shape == (4,)
    # arm: 7 joints, an absolute pose (7) or a relative one (6); lift adds the gripper's one
    arm = 6 if "IK-Rel" in task else 13 if "OSC" in task else 7  # OSC: pose and 6 stiffnesses
    assert dim == arm + ("Lift" in task)
    assert u.graph_blockers() == []  # on the GPU the step is replayed as one CUDA graph
    env.close()


def test_reach_agents_see_the_commanded_position_at_unit_scale():
    """The commanded position spans tenths of a metre; the reach agent (every variant's) normalizes its
    observations, so that input reaches its networks at the scale of the others (unnormalized it
    learned the orientation and barely the position: docs/manipulation.md)."""
    from simlab.cli.libraries.rsl_rl import make_runner
    from simlab.tasks.utils.parse_cfg import load_cfg_from_registry

    task = "simlab/Reach-Franka-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=64))
    agent_cfg = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    agent_cfg.device = "cpu"
    runner = make_runner(env, agent_cfg, log_dir=None)
    obs = runner.env.get_observations()
    command_x = obs["policy"][:, 18]  # joint positions (9) and velocities (9), then the command's x
    assert command_x.min() >= 0.35 and command_x.max() <= 0.65 and command_x.std() < 0.1
    for model in (runner.alg.actor, runner.alg.critic):
        model.update_normalization(obs)
        seen = model.obs_normalizer(obs["policy"])[:, 18]
        assert abs(float(seen.mean())) < 0.05 and 0.8 < float(seen.std()) < 1.2
    # the IK and OSC variants read the same command: the same agent
    for variant in ("IK-Abs", "IK-Rel", "OSC"):
        cfg = load_cfg_from_registry(f"simlab/Reach-Franka-{variant}-v0", "rsl_rl_cfg_entry_point")
        assert cfg.to_dict() == agent_cfg.to_dict() | {"device": cfg.device}
    env.close()
