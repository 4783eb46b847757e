"""Isaac Lab's other quadrupeds (issue 41.2): each robot's model (joint and body names in Isaac Lab's
order, total mass against the published model's), standing on its feet at its default pose, its
velocity tasks (registered with their criterion, built and stepped), and Isaac Lab's own task files
for it (``tests/ported/isaaclab_velocity_<robot>``) run after the import mapping."""

from __future__ import annotations

import importlib
import sys
from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym
import mujoco
import pytest
import torch

import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.assets import ArticulationCfg, AssetBaseCfg
from simlab.envs import ManagerBasedRLEnv
from simlab.robots import anymal, unitree
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
}
IDS = sorted(ROBOTS)


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
    """3 s on flat ground under the robot's own actuators holding the default joint positions."""
    robot = ROBOTS[name]
    sim, scene = robot_scene(robot.cfg)
    articulation, contacts = scene["robot"], scene["contacts"]
    assert articulation.joint_names == robot.joints()
    assert articulation.body_names == robot.bodies()
    torch.testing.assert_close(articulation.data.joint_pos, articulation.data.default_joint_pos)
    articulation.set_joint_position_target(articulation.data.default_joint_pos)
    heights = []
    for _ in range(600):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        heights.append(articulation.data.root_pos_w[:, 2].clone())
    settled = torch.stack(heights[100:])  # after the drop from the spawn height
    low, high = robot.height_band
    assert settled.min() > low and settled.max() < high, (settled.min(), settled.max())
    assert (articulation.data.projected_gravity_b[:, 2] < -0.98).all(), "the base stays level"
    assert articulation.data.root_lin_vel_w.norm(dim=1).max() < 0.05, "and comes to rest"
    foot_ids, _ = contacts.find_bodies(robot.feet)
    touching = contacts.data.net_forces_w.norm(dim=-1) > 1.0
    assert touching[:, foot_ids].all(), "all four feet carry the robot"
    others = [i for i in range(contacts.num_bodies) if i not in foot_ids]
    assert not touching[:, others].any(), "nothing but the feet touches the ground"
    weight = float(articulation.data.default_mass[0].sum()) * 9.81
    torch.testing.assert_close(contacts.data.net_forces_w[..., 2].sum(1), torch.full((2,), weight), rtol=0.02, atol=0.0)


# -- tasks -----------------------------------------------------------------------------------------


def task_ids(name: str) -> list[str]:
    task = ROBOTS[name].task
    return [f"simlab/Velocity-{t}-{task}{p}-v0" for t in ("Flat", "Rough") for p in ("", "-Play")]


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
        for _ in range(steps):
            obs, reward, terminated, truncated, _ = env.step(0.3 * torch.randn(N, env.action_manager.total_action_dim))
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        assert torch.isfinite(env.scene["robot"].data.joint_pos).all()
    finally:
        env.close()


@pytest.mark.parametrize("name", IDS)
@pytest.mark.parametrize("terrain", ["Flat", "Rough"])
def test_task_builds_and_steps(name, terrain):
    task = f"simlab/Velocity-{terrain}-{ROBOTS[name].task}-v0"
    step_env(parse_env_cfg(task, device="cpu", num_envs=N), rough=terrain == "Rough")


# -- Isaac Lab's own task files --------------------------------------------------------------------

PORTED_CLASSES = {"go1": "UnitreeGo1", "a1": "UnitreeA1", "anymal_b": "AnymalB", "anymal_d": "AnymalD"}


def ported(name: str, terrain: str):
    sys.path.insert(0, str(PORTED))
    try:
        module = importlib.import_module(f"isaaclab_velocity_{name}.{terrain.lower()}_env_cfg")
    finally:
        sys.path.remove(str(PORTED))
    return getattr(module, f"{PORTED_CLASSES[name]}{terrain}EnvCfg")()


def weights(cfg) -> dict[str, float]:
    return {name: term.weight for name, term in vars(cfg.rewards).items() if term is not None}


@pytest.mark.parametrize("name", sorted(PORTED_CLASSES))
@pytest.mark.parametrize("terrain", ["Flat", "Rough"])
def test_isaac_labs_own_task_file_runs_after_the_import_mapping(name, terrain):
    cfg = ported(name, terrain)
    ours = parse_env_cfg(f"simlab/Velocity-{terrain}-{ROBOTS[name].task}-v0", device="cpu", num_envs=N)
    assert weights(cfg) == weights(ours)
    assert cfg.actions.joint_pos.scale == ours.actions.joint_pos.scale
    step_env(cfg, rough=terrain == "Rough", steps=5)
