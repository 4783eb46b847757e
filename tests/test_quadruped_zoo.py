"""Isaac Lab's other quadrupeds (issue 41.2): each robot's model (joint and body names in Isaac Lab's
order, total mass against the published model's), standing on its feet at its default pose, its
velocity tasks (registered with their criterion, built and stepped), and Isaac Lab's own task files
for it (``tests/ported/isaaclab_velocity_<robot>``) run after the import mapping."""

from __future__ import annotations

import importlib
import sys
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import gymnasium as gym
import mujoco
import pytest
import torch

import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.assets import ArticulationCfg, AssetBaseCfg
from simlab.envs import ManagerBasedRLEnv
from simlab.robots import anymal, spot, unitree
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import ContactSensorCfg
from simlab.tasks.manager_based.locomotion.velocity import criterion as velocity_criterion
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.utils import configclass

N = 3
PORTED = Path(__file__).parent / "ported"
SCAN = 17 * 11  # the rough tasks' 1.6 m x 1.0 m height scan


@dataclass
class Quadruped:
    cfg: ArticulationCfg
    task: str  # the name in the task ids: simlab/Velocity-<Flat|Rough>-<task>-v0
    base: str
    legs: tuple[str, ...]  # in Isaac Lab's order
    parts: tuple[str, ...]  # joints, root to foot
    links: tuple[str, ...]  # bodies below the base, root to foot
    joint_name: str  # "{leg}_{part}" pattern
    body_name: str
    feet: str
    published_mass: float  # kg, the sum over the published model's bodies
    height_band: tuple[float, float]  # where the base settles at the default pose [m]
    terrains: tuple[str, ...] = ("Flat", "Rough")
    stand_cfg: ArticulationCfg | None = None  # the standing test's robot, where not ``cfg`` itself
    # the standing test's simulation (the robot's task's physics where the default 5 ms step won't do)
    stand_sim: sim_utils.SimulationCfg = field(default_factory=lambda: sim_utils.SimulationCfg(dt=0.005))
    stand_seconds: float = 3.0
    rest_speed: float = 0.05  # the base's speed at the end of it [m/s]

    def joints(self) -> list[str]:
        # Isaac Lab's articulation order: level by level down the tree, the legs in order at each level
        return [self.joint_name.format(leg=leg, part=part) for part in self.parts for leg in self.legs]

    def bodies(self) -> list[str]:
        return [self.base] + [self.body_name.format(leg=leg, part=part) for part in self.links for leg in self.legs]


ROBOTS = {
    # menagerie's unitree_go1: trunk 5.204 + 4 x (hip 0.68 + thigh 1.009 + calf and foot 0.195862)
    "go1": Quadruped(
        unitree.UNITREE_GO1_CFG,
        "Unitree-Go1",
        "trunk",
        ("FL", "FR", "RL", "RR"),
        ("hip", "thigh", "calf"),
        ("hip", "thigh", "calf", "foot"),
        "{leg}_{part}_joint",
        "{leg}_{part}",
        ".*_foot",
        5.204 + 4 * (0.68 + 1.009 + 0.195862),
        (0.22, 0.36),
    ),
    # menagerie's unitree_a1: trunk 4.713 + 4 x (hip 0.696 + thigh 1.013 + calf and foot 0.226)
    "a1": Quadruped(
        unitree.UNITREE_A1_CFG,
        "Unitree-A1",
        "trunk",
        ("FL", "FR", "RL", "RR"),
        ("hip", "thigh", "calf"),
        ("hip", "thigh", "calf", "foot"),
        "{leg}_{part}_joint",
        "{leg}_{part}",
        ".*_foot",
        4.713 + 4 * (0.696 + 1.013 + 0.226),
        (0.2, 0.36),
    ),
    # ANYbotics' anymal_b_simple_description URDF: the sum over its links (menagerie's anymal_b, 33.3 kg,
    # has heavier base and shank inertials than ANYbotics' file)
    "anymal_b": Quadruped(
        anymal.ANYMAL_B_CFG,
        "Anymal-B",
        "base",
        ("LF", "LH", "RF", "RH"),
        ("HAA", "HFE", "KFE"),
        ("HIP", "THIGH", "SHANK", "FOOT"),
        "{leg}_{part}",
        "{leg}_{part}",
        ".*_FOOT",
        16.793507758 + 4 * (1.42462064 + 1.634976467 + 0.207204302 + 0.140170767),
        (0.4, 0.55),
    ),
    # ANYbotics' anymal_d_simple_description URDF: the sum over its links
    "anymal_d": Quadruped(
        anymal.ANYMAL_D_CFG,
        "Anymal-D",
        "base",
        ("LF", "LH", "RF", "RH"),
        ("HAA", "HFE", "KFE"),
        ("HIP", "THIGH", "SHANK", "FOOT"),
        "{leg}_{part}",
        "{leg}_{part}",
        ".*_FOOT",
        51.53921,
        (0.48, 0.62),
    ),
    # Boston Dynamics' published mass of Spot (menagerie's links, 50.34 kg, scaled to it)
    "spot": Quadruped(
        spot.SPOT_CFG,
        "Spot",
        "body",
        ("fl", "fr", "hl", "hr"),
        ("hx", "hy", "kn"),
        ("hip", "uleg", "lleg", "foot"),
        "{leg}_{part}",
        "{leg}_{part}",
        ".*_foot",
        32.7,
        # Isaac Lab's kp 60 holds it low: the knees sag 0.3-0.5 rad under its weight and the base
        # rocks slowly (0.35-0.44 m) before it settles
        (0.33, 0.5),
        terrains=("Flat",),
        # its task's physics: 2 ms steps, elliptic friction cones (flat_env_cfg.py)
        stand_sim=sim_utils.SimulationCfg(dt=0.002, mujoco=sim_utils.MujocoCfg(cone="elliptic", impratio=10.0)),
        stand_seconds=5.0,
        rest_speed=0.1,  # still rocking (period ~3.5 s), which kd 1.5 damps slowly
    ),
}
IDS = sorted(ROBOTS)


def robot_scene(robot_cfg: ArticulationCfg, num_envs: int = 2, sim_cfg: sim_utils.SimulationCfg | None = None):
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot: ArticulationCfg = robot_cfg.replace(prim_path="{ENV_REGEX_NS}/Robot")
        contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*")

    sim_cfg = (sim_cfg or sim_utils.SimulationCfg(dt=0.005)).replace(device="cpu")
    sim = sim_utils.SimulationContext(sim_cfg)
    scene = InteractiveScene(SceneCfg(num_envs=num_envs, env_spacing=2.0))
    sim.reset()
    return sim, scene


# -- robots ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", IDS)
def test_model_mass_matches_the_published_model(name):
    robot = ROBOTS[name]
    model = mujoco.MjModel.from_xml_path(robot.cfg.spawn.asset_path)
    assert model.nu == 0 and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert model.body(1).name == robot.base
    total = float(model.body_mass.sum())
    assert abs(total - robot.published_mass) <= 0.05 * robot.published_mass, (total, robot.published_mass)
    # every leg joint is limited and its limits hold the default pose
    assert model.jnt_limited[1:].all()


@pytest.mark.parametrize("name", IDS)
def test_stands_on_its_feet_at_its_default_pose(name):
    """``stand_seconds`` on flat ground, its actuators (its own unless ``stand_cfg`` stiffens them)
    holding the default joint positions."""
    robot = ROBOTS[name]
    sim, scene = robot_scene(robot.stand_cfg or robot.cfg, sim_cfg=robot.stand_sim)
    dt = sim.get_physics_dt()
    steps = round(robot.stand_seconds / dt)
    articulation, contacts = scene["robot"], scene["contacts"]
    assert articulation.joint_names == robot.joints()
    assert articulation.body_names == robot.bodies()
    torch.testing.assert_close(articulation.data.joint_pos, articulation.data.default_joint_pos)
    articulation.set_joint_position_target(articulation.data.default_joint_pos)
    heights, support = [], []
    for _ in range(steps):
        scene.write_data_to_sim()
        sim.step()
        scene.update(dt)
        heights.append(articulation.data.root_pos_w[:, 2].clone())
        support.append(contacts.data.net_forces_w[..., 2].sum(1))
    settled = torch.stack(heights[round(0.5 / dt) :])  # after the drop from the spawn height
    low, high = robot.height_band
    assert settled.min() > low and settled.max() < high, (settled.min(), settled.max())
    assert (articulation.data.projected_gravity_b[:, 2] < -0.98).all(), "the base stays level"
    assert articulation.data.root_lin_vel_w.norm(dim=1).max() < robot.rest_speed, "and comes to rest"
    foot_ids, _ = contacts.find_bodies(robot.feet)
    touching = contacts.data.net_forces_w.norm(dim=-1) > 1.0
    assert touching[:, foot_ids].all(), "all four feet carry the robot"
    others = [i for i in range(contacts.num_bodies) if i not in foot_ids]
    assert not touching[:, others].any(), "nothing but the feet touches the ground"
    # over the last 0.5 s the ground carries the robot's weight (the actuator nets leave a slight bob)
    weight = float(articulation.data.default_mass[0].sum()) * 9.81
    last = torch.stack(support[-round(0.5 / dt) :]).mean(0)
    torch.testing.assert_close(last, torch.full((2,), weight), rtol=0.02, atol=0.0)


# -- tasks -----------------------------------------------------------------------------------------


def task_ids(name: str) -> list[str]:
    robot = ROBOTS[name]
    return [f"simlab/Velocity-{t}-{robot.task}{p}-v0" for t in robot.terrains for p in ("", "-Play")]


@pytest.mark.parametrize("name", IDS)
def test_tasks_are_registered_with_the_velocity_criterion(name):
    for task in task_ids(name):
        assert task in gym.registry, task
        assert gym.spec(task).kwargs["success_criterion_entry_point"].endswith("criterion:tracks_velocity")
        assert criterion_for(task).description == velocity_criterion.tracks_velocity().description
        assert "rsl_rl_cfg_entry_point" in gym.spec(task).kwargs


def step_env(cfg, rough: bool, steps: int = 20) -> None:
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = N, "cpu", 0
    env = ManagerBasedRLEnv(cfg)
    try:
        obs, _ = env.reset()
        assert obs["policy"].shape == (N, 48 + (SCAN if rough else 0))
        assert env.graph_blockers() == [], "the step can be captured as a CUDA graph"
        for _ in range(steps):
            obs, reward, terminated, truncated, _ = env.step(0.3 * torch.randn(N, env.action_manager.total_action_dim))
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        assert torch.isfinite(env.scene["robot"].data.joint_pos).all()
    finally:
        env.close()


@pytest.mark.parametrize(("name", "terrain"), [(name, t) for name in IDS for t in ROBOTS[name].terrains])
def test_task_builds_and_steps(name, terrain):
    task = f"simlab/Velocity-{terrain}-{ROBOTS[name].task}-v0"
    step_env(parse_env_cfg(task, device="cpu", num_envs=N), rough=terrain == "Rough")


# -- Isaac Lab's own task files --------------------------------------------------------------------

PORTED_CLASSES = {"go1": "UnitreeGo1", "a1": "UnitreeA1", "anymal_b": "AnymalB", "anymal_d": "AnymalD", "spot": "Spot"}


def ported(name: str, terrain: str):
    sys.path.insert(0, str(PORTED))
    try:
        module = importlib.import_module(f"isaaclab_velocity_{name}.{terrain.lower()}_env_cfg")
    finally:
        sys.path.remove(str(PORTED))
    return getattr(module, f"{PORTED_CLASSES[name]}{terrain}EnvCfg")()


def weights(cfg) -> dict[str, float]:
    return {name: term.weight for name, term in vars(cfg.rewards).items() if term is not None}


@pytest.mark.parametrize(
    ("name", "terrain"), [(name, t) for name in sorted(PORTED_CLASSES) for t in ROBOTS[name].terrains]
)
def test_isaac_labs_own_task_file_runs_after_the_import_mapping(name, terrain):
    cfg = ported(name, terrain)
    ours = parse_env_cfg(f"simlab/Velocity-{terrain}-{ROBOTS[name].task}-v0", device="cpu", num_envs=N)
    assert weights(cfg) == weights(ours)
    assert cfg.actions.joint_pos.scale == ours.actions.joint_pos.scale
    step_env(cfg, rough=terrain == "Rough", steps=5)


# -- Spot's own terms, on known contact states -----------------------------------------------------


def fake_env(air: list[list[float]], contact: list[list[float]], commands: list[list[float]]):
    """An env of ``len(air)`` worlds: Spot's four feet (fl, fr, hl, hr) with the given current air and
    contact times, the given velocity commands, the base at rest."""
    feet = ["fl_foot", "fr_foot", "hl_foot", "hr_foot"]
    sensor = SimpleNamespace(
        cfg=SimpleNamespace(track_air_time=True),
        data=SimpleNamespace(current_air_time=torch.tensor(air), current_contact_time=torch.tensor(contact)),
        find_bodies=lambda name: ([feet.index(name)], [name]),
    )
    num_envs = len(air)
    robot = SimpleNamespace(data=SimpleNamespace(root_lin_vel_b=torch.zeros(num_envs, 3)))
    return SimpleNamespace(
        num_envs=num_envs,
        device="cpu",
        scene=FakeScene({"contact_forces": sensor}, robot),
        command_manager=SimpleNamespace(get_command=lambda name: torch.tensor(commands)),
    )


class FakeScene:
    """``scene.sensors[name]`` and ``scene["robot"]``, as the terms read them."""

    def __init__(self, sensors: dict, robot, cfg=None):
        self.sensors, self.robot, self.cfg = sensors, robot, cfg

    def __getitem__(self, name: str):
        return self.robot


def gait_params() -> dict:
    """Isaac Lab's Spot gait reward parameters (its flat_env_cfg.py)."""
    from simlab.managers import SceneEntityCfg

    return {
        "std": 0.1,
        "max_err": 0.2,
        "velocity_threshold": 0.5,
        "synced_feet_pair_names": (("fl_foot", "hr_foot"), ("fr_foot", "hl_foot")),
        "asset_cfg": SceneEntityCfg("robot"),
        "sensor_cfg": SceneEntityCfg("contact_forces"),
    }


def test_spot_gait_reward_pays_a_trot_and_not_a_pronk():
    from simlab.managers import RewardTermCfg
    from simlab.tasks.manager_based.locomotion.velocity.config.spot import mdp as spot_mdp

    # env 0 trots (fl+hr in the air 0.2 s while fr+hl stand 0.2 s), env 1 pronks (all four in the air
    # 0.2 s), env 2 trots but is neither commanded nor moving
    air = [[0.2, 0.0, 0.0, 0.2], [0.2, 0.2, 0.2, 0.2], [0.2, 0.0, 0.0, 0.2]]
    contact = [[0.0, 0.2, 0.2, 0.0], [0.0, 0.0, 0.0, 0.0], [0.0, 0.2, 0.2, 0.0]]
    env = fake_env(air, contact, [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    params = gait_params()
    term = spot_mdp.GaitReward(RewardTermCfg(func=spot_mdp.GaitReward, weight=10.0, params=params), env)
    reward = term(env, **params)
    # the pronk: synced pairs agree (1), each of the four opposed pairs misses by 0.2 s twice:
    # exp(-(0.04 + 0.04) / 0.1) each
    torch.testing.assert_close(reward, torch.tensor([1.0, float(torch.exp(torch.tensor(-3.2))), 0.0]))
    with pytest.raises(ValueError, match="two pairs"):
        bad = dict(params, synced_feet_pair_names=(("fl_foot", "hr_foot"),))
        spot_mdp.GaitReward(RewardTermCfg(func=spot_mdp.GaitReward, weight=1.0, params=bad), env)


def test_spots_two_actuator_models_reach_mujocos_ctrl_in_one_write():
    """Spot's hips (delayed PD) and knees (remotized PD) clip into one buffer, written to MuJoCo's ctrl in
    one kernel (issue 41): each joint's ctrl is its own model's torque, in the model's joint order."""
    sim, scene = robot_scene(spot.SPOT_CFG, num_envs=3)
    robot = scene["robot"]
    generator = torch.Generator().manual_seed(0)
    targets = robot.data.default_joint_pos + 0.5 * torch.randn(robot.data.default_joint_pos.shape, generator=generator)
    robot.set_joint_position_target(targets)
    robot.write_data_to_sim()
    ctrl = sim.physics.data("ctrl")
    for name, actuator in robot.actuators.items():
        columns = [sim.model.actuator(f"{robot.prefix}{joint}").id for joint in actuator.joint_names]
        assert torch.any(actuator.applied_effort != 0.0), name
        assert torch.equal(ctrl[:, columns], actuator.applied_effort), name
    hips, knees = robot.actuators["spot_hip"], robot.actuators["spot_knee"]
    assert hips.applied_effort.untyped_storage().data_ptr() == knees.applied_effort.untyped_storage().data_ptr()


def test_spot_gait_reward_is_the_product_over_pairs_of_isaac_labs_kernel():
    """The six pairs in one gather (issue 41: 74 -> 16 kernels a step) pay what Isaac Lab's loop over the
    pairs pays: exp(-(min(x^2, e^2) + min(y^2, e^2)) / std) multiplied over them (the product's order
    may round otherwise)."""
    from simlab.managers import RewardTermCfg
    from simlab.tasks.manager_based.locomotion.velocity.config.spot import mdp as spot_mdp

    generator = torch.Generator().manual_seed(0)
    air, contact = (0.4 * torch.rand(64, 4, generator=generator) for _ in range(2))
    env = fake_env(air.tolist(), contact.tolist(), [[1.0, 0.0, 0.0]] * 64)
    params = gait_params()
    term = spot_mdp.GaitReward(RewardTermCfg(func=spot_mdp.GaitReward, weight=10.0, params=params), env)

    def kernel(x, y):
        return torch.exp(-(torch.square(x).clamp(max=0.2**2) + torch.square(y).clamp(max=0.2**2)) / 0.1)

    fl, fr, hl, hr = range(4)
    expected = torch.ones(64)
    for i, j in ((fl, hr), (fr, hl)):
        expected = expected * kernel(air[:, i] - air[:, j], contact[:, i] - contact[:, j])
    for i, j in ((fl, fr), (hr, hl), (fl, hl), (fr, hr)):
        expected = expected * kernel(air[:, i] - contact[:, j], contact[:, i] - air[:, j])
    assert (expected > 1e-3).any()
    torch.testing.assert_close(term(env, **params), expected, rtol=1e-6, atol=0.0)


def test_spot_air_time_reward_steps_when_moving_and_stands_when_not():
    from simlab.managers import SceneEntityCfg
    from simlab.tasks.manager_based.locomotion.velocity.config.spot import mdp as spot_mdp

    # env 0 moves: phases of 0.1, 0.2 s count, 0.4 s (past mode_time 0.3) does not; env 1 stands still:
    # contact - air, clipped to +-0.3
    air = [[0.1, 0.0, 0.4, 0.0], [0.1, 0.0, 0.0, 0.0]]
    contact = [[0.0, 0.2, 0.0, 0.0], [0.0, 0.2, 0.5, 0.1]]
    env = fake_env(air, contact, [[0.5, 0.0, 0.0], [0.0, 0.0, 0.0]])
    feet = SceneEntityCfg("contact_forces", body_names=".*_foot")
    feet.body_ids = [0, 1, 2, 3]
    reward = spot_mdp.air_time_reward(env, SceneEntityCfg("robot"), feet, mode_time=0.3, velocity_threshold=0.5)
    torch.testing.assert_close(reward, torch.tensor([0.1 + 0.2 + 0.0 + 0.0, -0.1 + 0.2 + 0.3 + 0.1]))


@pytest.mark.parametrize("added_mass", [0.0, 2.5])
def test_spot_task_robot_stands_with_zero_action(added_mass):
    """The Spot task's robot, its body as heavy as the task makes it (nominal and the ``add_base_mass``
    event's +2.5 kg), holds its default pose for 3 s of zero actions on flat ground: no body or leg
    contact ends the episode and the base stays up. Under Isaac Lab's kp 60 this model sank into a
    crouch (base 0.35 m) and, 2.5 kg heavier, touched down with a hind leg within 2 s."""
    cfg = parse_env_cfg("simlab/Velocity-Flat-Spot-v0", device="cpu", num_envs=2)
    cfg.seed = 0
    cfg.scene.terrain.terrain_type, cfg.scene.terrain.terrain_generator = "plane", None
    cfg.curriculum.terrain_levels = None
    cfg.events.physics_material = None  # the ground's friction 1.0
    cfg.events.add_base_mass.params["mass_distribution_params"] = (added_mass, added_mass)
    cfg.events.reset_base.params["velocity_range"] = {}
    cfg.events.reset_robot_joints.params.update(position_range=(0.0, 0.0), velocity_range=(0.0, 0.0))
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        robot = env.scene["robot"]
        actions = torch.zeros(2, env.action_manager.total_action_dim)
        heights = []
        for _ in range(round(3.0 / env.step_dt)):
            _, _, terminated, truncated, _ = env.step(actions)
            assert not (terminated | truncated).any(), "a body or leg touched down"
            heights.append(robot.data.root_pos_w[:, 2].clone())
        settled = torch.stack(heights[round(0.5 / env.step_dt) :])
        assert settled.min() > 0.42, settled.min()
        sag = (robot.data.joint_pos - robot.data.default_joint_pos).abs()
        assert sag.max() < 0.35, sag.max()  # the knees, held by kp against the robot's weight
    finally:
        env.close()


SPOT_TASK = "simlab/Velocity-Flat-Spot-v0"


def throw_spot_onto_the_cobblestones(cfg) -> None:
    """The worst contact case of Spot's task: robots dropped from up to 0.3 m in any orientation (upright
    to upside down), pushed every 0.5-1 s hard enough to roll them over, legs swung across their ranges
    (action scale 1.5), and no body-contact termination, so that fallen robots lie and flail on the
    cobblestones with the body, hips and legs touching."""
    cfg.terminations.body_contact = None
    cfg.events.reset_base.params["pose_range"] = {
        "x": (-0.5, 0.5), "y": (-0.5, 0.5), "z": (0.05, 0.3),
        "roll": (-3.14, 3.14), "pitch": (-1.57, 1.57), "yaw": (-3.14, 3.14),
    }  # fmt: skip
    cfg.events.push_robot.interval_range_s = (0.5, 1.0)
    cfg.events.push_robot.params["velocity_range"] = {
        "x": (-2.0, 2.0), "y": (-2.0, 2.0), "z": (-1.5, 0.5),
        "roll": (-4.0, 4.0), "pitch": (-4.0, 4.0), "yaw": (-2.0, 2.0),
    }  # fmt: skip
    cfg.actions.joint_pos.scale = 1.5


@pytest.mark.parametrize(
    ("num_envs", "env_steps", "episode_s"),
    [(8, 100, 1.5), pytest.param(64, 300, 3.0, marks=pytest.mark.slow)],  # the slow one: docs/locomotion.md
)
def test_spot_buffers_hold_robots_thrown_onto_the_cobblestones(num_envs, env_steps, episode_s):
    """MuJoCo Warp's kernels on Warp's CPU device with the task's own buffers (nconmax 32, njmax 192:
    an overflow raises), in the worst case above. The constraint rows of the worst world fit twice
    (njmax is per world); the contacts of the worst world fit once and the contacts a world pooled
    twice (all worlds share one pool of nconmax * num_envs). 64 worlds for 6 s peaked at 20 contacts
    and 81 constraint rows in a world (pyramidal cones: 4 rows a contact), 3 contacts pooled, at 500 Hz
    physics; at the task's 200 Hz at 16 contacts, 66 rows and 2 pooled."""
    pytest.importorskip("mujoco_warp")
    from simlab.tasks.utils.contact_buffers import measure_task_buffers

    peaks, diverged, reserved = measure_task_buffers(
        SPOT_TASK,
        num_envs=num_envs,
        env_steps=env_steps,
        headroom=1,
        episode_length_s=episode_s,
        configure=throw_spot_onto_the_cobblestones,
    )
    assert diverged == 0
    assert peaks.contacts_per_world >= 8, peaks  # more than four feet touch: the robots lie on the ground
    assert (reserved["nconmax"], reserved["njmax"]) == (32, 192)
    assert reserved["nconmax"] >= max(peaks.contacts_per_world, 2 * peaks.contacts_pooled), peaks
    assert reserved["njmax"] >= 2 * peaks.constraint_rows, peaks


@pytest.mark.parametrize("engine", ["mujoco", "mujoco_warp"])
def test_spot_task_steps_on_both_cpu_backends_as_configured(engine):
    """Spot's task as configured (pyramidal cones with impratio 10, MuJoCo Warp's buffers at nconmax 32
    and njmax 192) builds and steps on MuJoCo C (mjbatch) and on MuJoCo Warp on Warp's CPU device."""
    if engine == "mujoco_warp":
        pytest.importorskip("mujoco_warp")
    cfg = parse_env_cfg(SPOT_TASK, device="cpu", num_envs=N)
    cfg.sim.engine, cfg.sim.use_cuda_graph, cfg.seed = engine, False, 0
    env = ManagerBasedRLEnv(cfg)
    try:
        model = env.sim.model
        assert model.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL and model.opt.impratio == 10.0
        if engine == "mujoco_warp":
            assert (env.sim.physics.nconmax, env.sim.physics.njmax) == (32, 192)
        env.reset()
        for _ in range(10):
            obs, reward, _, _, _ = env.step(0.3 * torch.randn(N, env.action_manager.total_action_dim))
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        if engine == "mujoco_warp":
            env.sim.physics.check_overflow()
    finally:
        env.close()


def test_spot_task_keeps_isaac_labs_control_rate_and_actuator_delays_in_seconds():
    """Spot's task steps MuJoCo at 200 Hz (Isaac Lab: PhysX at 500 Hz) under Isaac Lab's 50 Hz policy;
    the actuators' delays, which Isaac Lab counts in its 2 ms physics steps (0-4), are the nearest
    whole steps of 5 ms: 0-2 (0-10 ms where Isaac Lab's are 0-8 ms)."""
    from simlab.tasks.manager_based.locomotion.velocity.config.spot.flat_env_cfg import delay_in_physics_steps

    cfg = parse_env_cfg(SPOT_TASK, device="cpu", num_envs=N)
    assert (cfg.sim.dt, cfg.decimation) == (0.005, 4)
    assert cfg.sim.dt * cfg.decimation == pytest.approx(0.02)  # Isaac Lab's control period
    assert cfg.scene.contact_forces.update_period == cfg.sim.dt  # the gait rewards see every physics step
    for name, actuator in cfg.scene.robot.actuators.items():
        assert (actuator.min_delay, actuator.max_delay) == (0, 2), name
        assert spot.SPOT_STIFF_CFG.actuators[name].max_delay == 4  # the robot keeps Isaac Lab's steps
    assert [delay_in_physics_steps(k, 0.002) for k in range(5)] == [0, 1, 2, 3, 4]
    assert [delay_in_physics_steps(k, 0.005) for k in range(5)] == [0, 0, 1, 1, 2]


def _trot_open_loop(dt: float, decimation: int, max_delay: int) -> tuple[float, float]:
    """Spot driven by a fixed trot (diagonal pairs in antiphase at 2 Hz: hip flexion +-1 action unit,
    the knees bent by 1.5 units in the swing half) on flat ground for 4 s: the mean displacement along
    x [m] and the mean base height [m] of 4 robots."""
    import math

    cfg = parse_env_cfg(SPOT_TASK, device="cpu", num_envs=4)
    cfg.sim.dt, cfg.decimation, cfg.sim.render_interval, cfg.seed = dt, decimation, decimation, 0
    cfg.scene.contact_forces.update_period = dt
    for actuator in cfg.scene.robot.actuators.values():
        actuator.max_delay = max_delay
    cfg.scene.terrain.terrain_type, cfg.scene.terrain.terrain_generator = "plane", None
    cfg.curriculum.terrain_levels = None
    cfg.events.physics_material = cfg.events.add_base_mass = cfg.events.push_robot = None
    cfg.events.reset_base.params.update(pose_range={}, velocity_range={})
    cfg.events.reset_robot_joints.params.update(position_range=(0.0, 0.0), velocity_range=(0.0, 0.0))
    cfg.terminations.body_contact = None
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        robot = env.scene["robot"]
        names = robot.joint_names
        phase = torch.tensor([0.0 if name[:2] in ("fl", "hr") else math.pi for name in names])
        hy = torch.tensor([float(name.endswith("_hy")) for name in names])
        kn = torch.tensor([float(name.endswith("_kn")) for name in names])
        start = robot.data.root_pos_w[:, 0].clone()
        heights = []
        for k in range(round(4.0 / env.step_dt)):
            wave = torch.sin(2 * math.pi * 2.0 * k * env.step_dt + phase)
            env.step((hy * wave - 1.5 * kn * wave.clamp(min=0)).expand(4, -1).clone())
            heights.append(robot.data.root_pos_w[:, 2].mean().item())
        return (robot.data.root_pos_w[:, 0] - start).mean().item(), sum(heights) / len(heights)
    finally:
        env.close()


def test_spot_trots_open_loop_the_same_at_isaac_labs_physics_rate():
    """The task's 200 Hz physics moves the robot as Isaac Lab's 500 Hz would: the same open-loop trot
    carries it as far (1.60 m backwards in 4 s at either rate) at the same height (0.424 m)."""
    x_500, z_500 = _trot_open_loop(0.002, 10, max_delay=4)
    x_200, z_200 = _trot_open_loop(0.005, 4, max_delay=2)
    assert abs(x_500) > 1.0, x_500  # the trot moves the robot
    assert x_200 == pytest.approx(x_500, abs=0.1)
    assert z_200 == pytest.approx(z_500, abs=0.01)


def _alive_reward_rates(std: float, num_envs: int, seconds: float) -> tuple[torch.Tensor, int]:
    """Spot's task as registered, driven by PPO's first actions (zero-mean Gaussian noise of ``std``):
    the reward per second of every env step that did not end an episode, and the number of falls."""
    cfg = parse_env_cfg(SPOT_TASK, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        noise = torch.Generator().manual_seed(1)
        rates, falls = [], 0
        for _ in range(round(seconds / env.step_dt)):
            actions = std * torch.randn((num_envs, env.action_manager.total_action_dim), generator=noise)
            _, reward, terminated, truncated, _ = env.step(actions)
            rates.append(reward[~(terminated | truncated)] / env.step_dt)
            falls += int(terminated.sum())
        return torch.cat(rates), falls
    finally:
        env.close()


def test_spot_staying_alive_pays_at_the_agents_initial_action_noise():
    """Spot's task has no termination penalty: ending an episode forfeits what staying alive earns, so
    falling pays only where a robot alive loses reward. Under the agent's initial noise (0.5) robots
    alive earn about +7.6 per second (64 envs, 6 s: the tracking kernels +4.7 and the gait +6.1 against
    action smoothness -2.4), +3.3 at Isaac Lab's 1.0; each falls now and then (the noise is PPO's first,
    not a policy's)."""
    from simlab.tasks.utils.parse_cfg import load_cfg_from_registry

    agent = load_cfg_from_registry(SPOT_TASK, "rsl_rl_cfg_entry_point")
    assert agent.actor.distribution_cfg.init_std == 0.5
    rates, falls = _alive_reward_rates(agent.actor.distribution_cfg.init_std, num_envs=16, seconds=3.0)
    assert falls > 0
    assert rates.mean() > 2.0, f"alive: {rates.mean():.2f} per second"


@pytest.mark.slow
def test_spot_robots_under_isaac_labs_initial_noise_do_not_blow_up():
    """Isaac Lab's initial noise (1.0), 64 robots for 6 s at the task's 200 Hz: no env step pays less than
    -50 per second (the worst was -22: a robot flailing). With mjlab's solver caps (10 iterations, 20
    line-search) 0.09 % of the steps did, down to -4.5e6 per second: joint accelerations of 1e10 rad/s^2
    from unconverged solver steps in the joint-acceleration penalty."""
    rates, _ = _alive_reward_rates(1.0, num_envs=64, seconds=6.0)
    assert rates.min() > -50.0, rates.min()


def test_terrain_out_of_bounds_is_the_generated_terrains_edge():
    import simlab.envs.mdp as mdp

    env = parse_env_cfg("simlab/Velocity-Flat-Spot-v0", device="cpu", num_envs=N)
    # Spot's cobblestone road: 9 x 8 m rows and 21 x 8 m columns inside a 20 m border, centred on the
    # origin: |x| up to 56 m, |y| up to 104 m; a 3 m buffer
    robot = SimpleNamespace(data=SimpleNamespace(root_pos_w=torch.tensor([[52.9, 0, 0], [53.1, 0, 0], [0, -101.1, 0]])))
    fake = SimpleNamespace(num_envs=3, device="cpu", scene=FakeScene({}, robot, cfg=env.scene))
    assert mdp.terrain_out_of_bounds(fake, distance_buffer=3.0).tolist() == [False, True, True]
    env.scene.terrain.terrain_type = "plane"
    assert not mdp.terrain_out_of_bounds(fake).any()


# -- ANYmal's symmetry augmentation ----------------------------------------------------------------


def test_anymal_mirrors_swap_legs_flip_signs_and_undo_themselves():
    from simlab.tasks.manager_based.locomotion.velocity.mdp.symmetry import anymal as symmetry

    env = SimpleNamespace(
        unwrapped=SimpleNamespace(
            observation_manager=SimpleNamespace(active_terms={"policy": ["base_lin_vel", "height_scan"]})
        )
    )
    torch.manual_seed(0)
    obs, actions = torch.randn(5, 48 + SCAN), torch.randn(5, 12)
    obs_aug, actions_aug = symmetry.compute_symmetric_states(env, obs, actions)
    assert obs_aug.shape == (20, 48 + SCAN) and actions_aug.shape == (20, 12)
    torch.testing.assert_close(obs_aug[:5], obs)
    # each mirror undoes itself; the fourth block is both mirrors
    of_left_right, _ = symmetry.compute_symmetric_states(env, obs_aug[5:10], None)
    torch.testing.assert_close(of_left_right[5:10], obs)
    torch.testing.assert_close(of_left_right[10:15], obs_aug[15:20])
    of_front_back, _ = symmetry.compute_symmetric_states(env, obs_aug[10:15], None)
    torch.testing.assert_close(of_front_back[10:15], obs)
    # rsl_rl passes the observation groups as a TensorDict: each group mirrored alike
    from tensordict import TensorDict

    grouped, _ = symmetry.compute_symmetric_states(env, TensorDict({"policy": obs}, batch_size=[5]), None)
    assert grouped.batch_size == torch.Size([20])
    torch.testing.assert_close(grouped["policy"], obs_aug)
    # Isaac Lab's joint order: HAA of LF, LH, RF, RH, then HFE, then KFE
    action = torch.zeros(1, 12)
    action[0, 0], action[0, 4] = 0.3, 0.5  # LF_HAA, LF_HFE
    _, mirrored = symmetry.compute_symmetric_states(env, None, action)
    assert mirrored[1, 2] == -0.3 and mirrored[1, 6] == 0.5  # left-right: RF_HAA, RF_HFE
    assert mirrored[2, 1] == 0.3 and mirrored[2, 5] == -0.5  # front-back: LH_HAA, LH_HFE
    assert mirrored[3, 3] == -0.3 and mirrored[3, 7] == -0.5  # both: RH
    assert obs_aug[5, 1] == -obs[0, 1] and obs_aug[5, 5] == -obs[0, 5] and obs_aug[5, 0] == obs[0, 0]
    # the height scan's rows (y) reverse left-right, its columns (x) front-back
    scan = obs[0, 48:].view(11, 17)
    torch.testing.assert_close(obs_aug[5, 48:].view(11, 17), scan.flip(0))
    torch.testing.assert_close(obs_aug[10, 48:].view(11, 17), scan.flip(1))


def test_anymal_default_pose_is_its_own_mirror_image():
    """Isaac Lab's ANYmal pose (HAA 0, HFE +-0.4, KFE -+0.8) is symmetric both ways: the mirrors'
    joint maps and signs agree with the robot's joint axes."""
    from simlab.tasks.manager_based.locomotion.velocity.mdp.symmetry import anymal as symmetry

    sim, scene = robot_scene(anymal.ANYMAL_B_CFG)
    pose = scene["robot"].data.default_joint_pos[:1]
    _, mirrored = symmetry.compute_symmetric_states(None, None, pose)
    for block in range(4):
        torch.testing.assert_close(mirrored[block : block + 1], pose)


def test_anymal_b_registers_its_symmetry_runner():
    from simlab.tasks.utils.parse_cfg import load_cfg_from_registry

    for terrain in ("Flat", "Rough"):
        runner = load_cfg_from_registry(
            f"simlab/Velocity-{terrain}-Anymal-B-v0", "rsl_rl_with_symmetry_cfg_entry_point"
        )
        assert runner.algorithm.symmetry_cfg.use_data_augmentation
        assert runner.algorithm.symmetry_cfg.data_augmentation_func.__name__ == "compute_symmetric_states"
