"""Legged locomotion: the Go2 and ANYmal-C models, the locomotion MDP terms, the velocity tasks."""

from __future__ import annotations

import math

import gymnasium as gym
import pytest
import torch

import simlab.envs.mdp as mdp
import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401 - registers the tasks
import simlab.utils.math as math_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg
from simlab.managers import SceneEntityCfg
from simlab.robots.anymal import ANYMAL_C_CFG
from simlab.robots.unitree import UNITREE_GO2_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import ContactSensorCfg
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.utils import configclass

N = 4

# Isaac Lab's articulation order: the links and joints level by level down the tree.
GO2_JOINTS = [f"{leg}_{part}_joint" for part in ("hip", "thigh", "calf") for leg in ("FL", "FR", "RL", "RR")]
GO2_BODIES = ["base"] + [
    f"{leg}_{part}" for part in ("hip", "thigh", "calf", "foot") for leg in ("FL", "FR", "RL", "RR")
]
ANYMAL_JOINTS = [f"{leg}_{part}" for part in ("HAA", "HFE", "KFE") for leg in ("LF", "LH", "RF", "RH")]
ANYMAL_BODIES = ["base"] + [
    f"{leg}_{part}" for part in ("HIP", "THIGH", "SHANK", "FOOT") for leg in ("LF", "LH", "RF", "RH")
]


# -- robots ----------------------------------------------------------------------------------------


def robot_scene(robot_cfg: ArticulationCfg, num_envs: int = 2):
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot: ArticulationCfg = robot_cfg.replace(prim_path="{ENV_REGEX_NS}/Robot")
        contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*")

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(SceneCfg(num_envs=num_envs, env_spacing=2.0))
    sim.reset()
    return sim, scene


@pytest.mark.parametrize(
    ("robot_cfg", "joints", "bodies", "feet", "height_band"),
    [
        (UNITREE_GO2_CFG, GO2_JOINTS, GO2_BODIES, ".*_foot", (0.22, 0.36)),
        (ANYMAL_C_CFG, ANYMAL_JOINTS, ANYMAL_BODIES, ".*_FOOT", (0.44, 0.56)),
    ],
    ids=["go2", "anymal_c"],
)
def test_quadruped_stands_on_its_feet_under_its_default_pd_targets(robot_cfg, joints, bodies, feet, height_band):
    sim, scene = robot_scene(robot_cfg)
    robot, contacts = scene["robot"], scene["contacts"]
    assert robot.joint_names == joints and robot.body_names == bodies
    # the worlds start at the configured joint positions, and the geometry agrees with them
    torch.testing.assert_close(robot.data.joint_pos, robot.data.default_joint_pos)
    robot.set_joint_position_target(robot.data.default_joint_pos)
    heights = []
    for _ in range(600):  # 3 s
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        heights.append(robot.data.root_pos_w[:, 2].clone())
    settled = torch.stack(heights[100:])  # after the drop from the spawn height
    assert settled.min() > height_band[0] and settled.max() < height_band[1], (settled.min(), settled.max())
    assert (robot.data.projected_gravity_b[:, 2] < -0.98).all(), "the base stays level"
    assert robot.data.root_lin_vel_w.norm(dim=1).max() < 0.05, "and comes to rest"
    foot_ids, _ = contacts.find_bodies(feet)
    touching = contacts.data.net_forces_w.norm(dim=-1) > 1.0
    assert touching[:, foot_ids].all(), "all four feet carry the robot"
    others = [i for i in range(contacts.num_bodies) if i not in foot_ids]
    assert not touching[:, others].any(), "nothing but the feet touches the ground"
    weight = float(robot.data.default_mass[0].sum()) * 9.81
    torch.testing.assert_close(contacts.data.net_forces_w[..., 2].sum(1), torch.full((2,), weight), rtol=0.02, atol=0.0)


# -- velocity tasks --------------------------------------------------------------------------------


def make_task(task: str, num_envs: int = N, **overrides):
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    for key, value in overrides.items():
        target = cfg
        *path, last = key.split(".")
        for part in path:
            target = getattr(target, part)
        setattr(target, last, value)
    return gym.make(task, cfg=cfg).unwrapped


@pytest.mark.parametrize(
    ("task", "obs_dim"),
    [
        ("simlab/Velocity-Flat-Unitree-Go2-v0", 48),
        ("simlab/Velocity-Rough-Unitree-Go2-v0", 48 + 17 * 11),  # + the 1.6 m x 1.0 m height scan
        ("simlab/Velocity-Flat-Anymal-C-Play-v0", 48),
        ("simlab/Velocity-Rough-Anymal-C-v0", 48 + 17 * 11),
    ],
)
def test_velocity_task_steps(task, obs_dim):
    env = make_task(task)
    obs, _ = env.reset()
    assert obs["policy"].shape == (N, obs_dim)
    assert env.graph_blockers() == [], "the step can be captured as a CUDA graph"
    for _ in range(10):
        obs, reward, terminated, truncated, extras = env.step(0.3 * torch.randn(N, 12))
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    assert set(extras["final_obs"]) == {"policy"}
    env.close()


def test_velocity_task_ids_cover_isaac_labs():
    ids = set(gym.registry)
    for robot in ("Unitree-Go2", "Anymal-C"):
        for terrain in ("Flat", "Rough"):
            for play in ("", "-Play"):
                assert f"simlab/Velocity-{terrain}-{robot}{play}-v0" in ids


def test_fallen_robot_is_reset_alone():
    env = make_task("simlab/Velocity-Flat-Unitree-Go2-v0")
    env.reset()
    for _ in range(5):
        env.step(torch.zeros(N, 12))
    robot = env.scene["robot"]
    # Env 0's base lies on the ground (illegal base contact); the others stand.
    root = robot.data.root_state_w.clone()
    root[0, 2] = 0.05
    robot.write_root_state_to_sim(root)
    _, _, terminated, truncated, extras = env.step(torch.zeros(N, 12))
    assert terminated.tolist() == [True, False, False, False] and not truncated.any()
    assert env.episode_length_buf.tolist() == [0, 6, 6, 6]
    assert robot.data.root_pos_w[0, 2] > 0.3, "back at the spawn height"
    assert extras["log"]["Episode_Termination/base_contact"] == 1
    env.close()


# -- MDP terms of the locomotion tasks, on known states -------------------------------------------


@pytest.fixture(scope="module")
def go2():
    env = make_task("simlab/Velocity-Flat-Unitree-Go2-v0")
    env.reset()
    for _ in range(25):  # settle on the feet
        env.step(torch.zeros(N, 12))
    yield env
    env.close()


def resolved(env, cfg: SceneEntityCfg) -> SceneEntityCfg:
    cfg = cfg.copy()
    cfg.resolve(env.scene)
    return cfg


def set_command(env, command: tuple[float, float, float]) -> None:
    term = env.command_manager.get_term("base_velocity")
    term.vel_command_b[:] = torch.tensor(command)


def test_feet_air_time_rewards_each_touchdown_after_a_long_flight(go2):
    sensor = go2.scene["contact_forces"]
    feet = resolved(go2, SceneEntityCfg("contact_forces", body_names=".*_foot"))
    data = sensor.data
    buffers = (data.current_contact_time, data.current_air_time, data.last_air_time)
    saved = [t.clone() for t in buffers]
    contact, air, last_air = (t.clone() for t in buffers)
    # foot 0 touched down 0.01 s ago after 0.7 s in the air; foot 1 has stood for 0.5 s;
    # foot 2 is in the air; foot 3 just touched down after 0.3 s (a short step: it costs)
    contact[:, feet.body_ids] = torch.tensor([0.01, 0.5, 0.0, 0.005])
    air[:, feet.body_ids] = torch.tensor([0.0, 0.0, 0.2, 0.0])
    last_air[:, feet.body_ids] = torch.tensor([0.7, 0.7, 0.7, 0.3])
    for buffer, value in zip(buffers, (contact, air, last_air)):
        buffer.copy_(value)
    set_command(go2, (0.5, 0.0, 0.0))
    reward = mdp.feet_air_time(go2, command_name="base_velocity", sensor_cfg=feet, threshold=0.5)
    torch.testing.assert_close(reward, torch.full((N,), (0.7 - 0.5) + (0.3 - 0.5)))
    set_command(go2, (0.05, 0.05, 1.0))  # planar command under 0.1 m/s: no stepping asked for
    assert not mdp.feet_air_time(go2, command_name="base_velocity", sensor_cfg=feet, threshold=0.5).any()
    for buffer, value in zip(buffers, saved):
        buffer.copy_(value)


def test_feet_slide_is_the_speed_of_the_feet_that_touch(go2):
    robot, sensor = go2.scene["robot"], go2.scene["contact_forces"]
    feet_sensor = resolved(go2, SceneEntityCfg("contact_forces", body_names=".*_foot"))
    feet_robot = resolved(go2, SceneEntityCfg("robot", body_names=".*_foot"))
    history = sensor.data.net_forces_w_history
    saved = history.clone()
    # the whole robot glides at (0.6, 0.8) m/s, joints still: every foot moves at 1 m/s
    robot.write_root_velocity_to_sim(torch.tensor([[0.6, 0.8, 0.0, 0.0, 0.0, 0.0]]).repeat(N, 1))
    robot.write_joint_velocity_to_sim(torch.zeros(N, 12))
    history.zero_()
    history[:, 1, feet_sensor.body_ids[0], 2] = 30.0  # foot 0 touched within the history
    history[:, 0, feet_sensor.body_ids[3], 0] = 5.0  # foot 3 touches now (sideways force)
    history[:, 2, feet_sensor.body_ids[2], 2] = 0.5  # foot 2: under the 1 N contact threshold
    reward = mdp.feet_slide(go2, sensor_cfg=feet_sensor, asset_cfg=feet_robot)
    torch.testing.assert_close(reward, torch.full((N,), 2.0))
    history.copy_(saved)


def test_apply_external_force_torque_by_mask(go2):
    robot = go2.scene["robot"]
    base = resolved(go2, SceneEntityCfg("robot", body_names="base"))
    mask = torch.tensor([False, True, False, True])
    mdp.apply_external_force_torque(go2, mask, (0.0, 0.0), (0.0, 0.0), asset_cfg=base)
    wrenches = robot.permanent_wrench_composer
    assert not wrenches.active, "zero ranges on a robot without wrenches change nothing"
    mdp.apply_external_force_torque(go2, mask, (5.0, 5.0), (-1.0, -1.0), asset_cfg=base)
    expected = torch.zeros(N, 3)
    expected[mask] = 5.0
    torch.testing.assert_close(wrenches.composed_force[:, 0], expected)
    torch.testing.assert_close(wrenches.composed_torque[:, 0], -expected / 5.0)
    assert not wrenches.composed_force[:, 1:].any(), "only the base is pushed"
    robot.set_external_force_and_torque(torch.zeros(N, 1, 3), torch.zeros(N, 1, 3), body_ids=base.body_ids)


def test_velocity_command_heading_control_and_standing_envs(go2):
    term = go2.command_manager.get_term("base_velocity")
    assert term.cfg.heading_command and term.cfg.heading_control_stiffness == 0.5
    robot = go2.scene["robot"]
    heading = robot.data.heading_w.clone()
    saved = (term.heading_target.clone(), term.is_heading_env.clone(), term.is_standing_env.clone())
    # targets 0.4 rad left, 0.4 rad right, 3 rad left (clipped to 1 rad/s) of the current heading
    term.heading_target[:] = heading + torch.tensor([0.4, -0.4, 3.0, 0.4])
    term.is_heading_env[:] = True
    term.is_standing_env[:] = torch.tensor([False, False, False, True])
    term.vel_command_b[:] = torch.tensor([0.8, -0.2, 0.0])
    term._update_command()
    expected_yaw = torch.tensor([0.2, -0.2, 1.0, 0.0])
    torch.testing.assert_close(term.command[:, 2], expected_yaw, atol=1e-5, rtol=0.0)
    torch.testing.assert_close(term.command[3], torch.zeros(3), msg="the standing env is told to stand")
    torch.testing.assert_close(term.command[0, :2], torch.tensor([0.8, -0.2]))
    # resampling by mask draws new commands only where the mask is set
    before = term.command.clone()
    term._resample_command(torch.tensor([True, False, False, False]))
    assert torch.equal(term.command[1:3], before[1:3]) and not torch.equal(term.command[0], before[0])
    term.heading_target[:], term.is_heading_env[:], term.is_standing_env[:] = saved


def test_height_scan_and_base_height_over_scanned_ground():
    env = make_task(
        "simlab/Velocity-Rough-Unitree-Go2-v0",
        num_envs=2,
        **{
            "scene.terrain.terrain_type": "plane",
            "scene.terrain.terrain_generator": None,
            "curriculum.terrain_levels": None,
        },
    )
    env.reset()
    env.step(torch.zeros(2, 12))
    scanner = resolved(env, SceneEntityCfg("height_scanner"))
    robot = env.scene["robot"]
    base_z = robot.data.root_pos_w[:, 2]
    scan = mdp.height_scan(env, sensor_cfg=scanner)
    assert scan.shape == (2, 17 * 11)
    # over a plane at z = 0 every ray hits z = 0: each reads the scanner's height minus the 0.5 m offset
    hits = env.scene["height_scanner"].data.ray_hits_w
    torch.testing.assert_close(hits[..., 2], torch.zeros(2, 187), atol=1e-5, rtol=0.0)
    scanner_z = env.scene["height_scanner"].data.pos_w[:, 2]
    torch.testing.assert_close(scanner_z, base_z, atol=5e-3, rtol=0.0)  # on the base (read at its last update)
    torch.testing.assert_close(scan, (scanner_z - 0.5)[:, None].expand(2, 187), atol=1e-5, rtol=0.0)
    target = 0.3
    torch.testing.assert_close(
        mdp.base_height_l2(env, target_height=target, sensor_cfg=scanner), (base_z - target) ** 2, atol=1e-5, rtol=0.0
    )
    env.close()


def test_terminations_of_a_tilted_or_low_base(go2):
    robot = go2.scene["robot"]
    state = robot.data.root_state_w.clone()
    tilt = torch.tensor([0.2, 0.6, 1.2, 2.0])  # rad about x
    state[:, 3:7] = torch.stack([torch.cos(tilt / 2), torch.sin(tilt / 2), 0 * tilt, 0 * tilt], dim=1)
    state[:, 2] = torch.tensor([0.3, 0.1, 0.3, 0.1])
    robot.write_root_state_to_sim(state)
    assert mdp.bad_orientation(go2, limit_angle=math.pi / 4).tolist() == [False, False, True, True]
    assert mdp.root_height_below_minimum(go2, minimum_height=0.2).tolist() == [False, True, False, True]
    torch.testing.assert_close(mdp.flat_orientation_l2(go2), torch.sin(tilt) ** 2)
    go2.reset()


# -- porting ---------------------------------------------------------------------------------------

ISAACLAB_STYLE_GO2_TASK = """
import isaaclab_tasks.manager_based.locomotion.velocity.mdp as mdp
from isaaclab.managers import RewardTermCfg as RewTerm
from isaaclab.managers import SceneEntityCfg
from isaaclab.utils import configclass
from isaaclab_assets.robots.unitree import UNITREE_GO2_CFG
from isaaclab_tasks.manager_based.locomotion.velocity.velocity_env_cfg import LocomotionVelocityRoughEnvCfg


@configclass
class MyGo2FlatEnvCfg(LocomotionVelocityRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.robot = UNITREE_GO2_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.scene.terrain.terrain_type = "plane"
        self.scene.terrain.terrain_generator = None
        self.scene.height_scanner = None
        self.observations.policy.height_scan = None
        self.curriculum.terrain_levels = None
        self.rewards.feet_air_time.params["sensor_cfg"].body_names = ".*_foot"
        self.rewards.undesired_contacts.params["sensor_cfg"].body_names = ".*_thigh"
        self.rewards.feet_slide = RewTerm(
            func=mdp.feet_slide,
            weight=-0.25,
            params={
                "sensor_cfg": SceneEntityCfg("contact_forces", body_names=".*_foot"),
                "asset_cfg": SceneEntityCfg("robot", body_names=".*_foot"),
            },
        )
"""


def test_isaac_lab_style_velocity_task_runs_after_the_import_mapping():
    from test_porting import port

    namespace: dict = {}
    exec(compile(port(ISAACLAB_STYLE_GO2_TASK), "my_go2_env_cfg.py", "exec"), namespace)
    cfg = namespace["MyGo2FlatEnvCfg"]()
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = N, "cpu", 0
    from simlab.envs import ManagerBasedRLEnv

    env = ManagerBasedRLEnv(cfg)
    obs, _ = env.reset()
    assert obs["policy"].shape == (N, 48)
    for _ in range(3):
        _, reward, *_ = env.step(torch.zeros(N, 12))
    assert torch.isfinite(reward).all() and "feet_slide" in env.reward_manager.active_terms
    env.close()


def test_yaw_frame_and_world_frame_tracking_rewards(go2):
    robot = go2.scene["robot"]
    state = robot.data.root_state_w.clone()
    # yawed 90 deg left and pitched 0.5 rad, moving along world +y at 1 m/s and turning about world z
    yaw = torch.tensor([math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)])
    pitch = torch.tensor([math.cos(0.25), 0.0, math.sin(0.25), 0.0])
    state[:, 3:7] = math_utils.quat_mul(yaw, pitch).expand(N, 4)
    state[:, 7:13] = torch.tensor([0.0, 1.0, 0.0, 0.0, 0.0, 0.5])
    robot.write_root_state_to_sim(state)
    set_command(go2, (1.0, 0.0, 0.5))
    # in the yaw-aligned frame the robot moves straight ahead: the command is met exactly
    torch.testing.assert_close(
        mdp.track_lin_vel_xy_yaw_frame_exp(go2, std=0.5, command_name="base_velocity"), torch.ones(N)
    )
    torch.testing.assert_close(mdp.track_ang_vel_z_world_exp(go2, command_name="base_velocity", std=0.5), torch.ones(N))
    # in the pitched base frame the forward speed reads cos(0.5) and the yaw rate 0.5 cos(0.5)
    forward_error = (1.0 - math.cos(0.5)) ** 2
    side = robot.data.root_lin_vel_b[:, 1]
    torch.testing.assert_close(side, torch.zeros(N), atol=1e-5, rtol=0.0)
    torch.testing.assert_close(
        mdp.track_lin_vel_xy_exp(go2, std=0.5, command_name="base_velocity"),
        torch.full((N,), math.exp(-forward_error / 0.25)),
    )
    yaw_error = (0.5 - 0.5 * math.cos(0.5)) ** 2
    torch.testing.assert_close(
        mdp.track_ang_vel_z_exp(go2, std=0.5, command_name="base_velocity"),
        torch.full((N,), math.exp(-yaw_error / 0.25)),
    )
    go2.reset()


def test_randomize_rigid_body_com_moves_the_base_com(go2):
    base = resolved(go2, SceneEntityCfg("robot", body_names="base"))
    robot = go2.scene["robot"]
    body = robot._body_ids[base.body_ids[0]]
    model_com = torch.as_tensor(go2.sim.model.body_ipos[body], dtype=torch.float32)
    mdp.randomize_rigid_body_com(go2, torch.tensor([1, 2]), {"x": (0.05, 0.05), "z": (-0.01, 0.01)}, asset_cfg=base)
    com = go2.sim.physics.model_field("body_ipos")[:, body]
    torch.testing.assert_close(com[[0, 3]], model_com.expand(2, 3))
    torch.testing.assert_close(com[[1, 2], 0], model_com[0] + torch.full((2,), 0.05))
    torch.testing.assert_close(com[[1, 2], 1], model_com[1].expand(2))
    assert ((com[[1, 2], 2] - model_com[2]).abs() <= 0.01 + 1e-6).all()
    with pytest.raises(ValueError, match="unknown com_range key"):
        mdp.randomize_rigid_body_com(go2, None, {"roll": (0.0, 0.1)}, asset_cfg=base)
    mdp.randomize_rigid_body_com(go2, None, {}, asset_cfg=base)  # back to the model's


def test_rough_task_curriculum_moves_robots_that_stay_put_down_a_row():
    """Go2 rough, robots told to walk 1 m/s forward that do not move (zero actions) end their 1 s
    episodes short of half the commanded distance: terrain_levels_vel moves each down one row (to
    no lower than 0), puts its origin on the new tile, and the env logs the mean level."""
    cfg = parse_env_cfg("simlab/Velocity-Rough-Unitree-Go2-v0", device="cpu", num_envs=8)
    cfg.seed = 0
    cfg.episode_length_s = 1.0
    vel = cfg.commands.base_velocity
    vel.heading_command, vel.rel_standing_envs = False, 0.0
    vel.ranges.lin_vel_x, vel.ranges.lin_vel_y, vel.ranges.ang_vel_z = (1.0, 1.0), (0.0, 0.0), (0.0, 0.0)
    cfg.scene.terrain.max_init_terrain_level = 9
    cfg.events.reset_base.params["pose_range"] = {"yaw": (-3.14, 3.14)}  # start on the origins themselves
    env = gym.make("simlab/Velocity-Rough-Unitree-Go2-v0", cfg=cfg).unwrapped
    terrain = env.scene.terrain
    env.reset()
    assert env.cfg.scene.terrain.terrain_generator.curriculum  # rows are difficulty levels
    before = terrain.terrain_levels.clone()
    assert int(before.max()) > 0
    logged = None
    for _ in range(round(1.0 / env.step_dt)):
        _, _, terminated, truncated, extras = env.step(torch.zeros(8, 12))
        if "Curriculum/terrain_levels" in extras.get("log", {}):
            logged = float(extras["log"]["Curriculum/terrain_levels"])
    assert bool(truncated.all() | terminated.all())
    torch.testing.assert_close(terrain.terrain_levels, (before - 1).clamp(min=0))
    assert logged == pytest.approx(float(terrain.terrain_levels.float().mean()))
    torch.testing.assert_close(
        env.scene.env_origins, terrain.terrain_origins[terrain.terrain_levels, terrain.terrain_types]
    )
    env.close()
