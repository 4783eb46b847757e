"""Porting check: an Isaac Lab direct task runs after rewriting its imports and nothing else.

``ISAACLAB_CARTPOLE`` is a direct cartpole written the Isaac Lab (2.x) way, with ``isaaclab``
imports. The test applies SPEC's import mapping ("Porting from Isaac Lab") by regex, writes the
result to a file, imports it and runs it, and checks that it behaves like simlab's own cartpole.
"""

from __future__ import annotations

import re
import sys

import torch
from conftest import load_script

ISAACLAB_CARTPOLE = """
from __future__ import annotations

import math
import torch
from collections.abc import Sequence

from isaaclab_assets.robots.cartpole import CARTPOLE_CFG

import isaaclab.sim as sim_utils
from isaaclab.assets import Articulation, ArticulationCfg
from isaaclab.envs import DirectRLEnv, DirectRLEnvCfg
from isaaclab.scene import InteractiveSceneCfg
from isaaclab.sim import SimulationCfg
from isaaclab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from isaaclab.utils import configclass
from isaaclab.utils.math import sample_uniform


@configclass
class CartpoleEnvCfg(DirectRLEnvCfg):
    # env
    decimation = 2
    episode_length_s = 5.0
    action_scale = 100.0  # [N]
    action_space = 1
    observation_space = 4
    state_space = 0

    # simulation
    sim: SimulationCfg = SimulationCfg(dt=1 / 120, render_interval=decimation)

    # robot
    robot_cfg: ArticulationCfg = CARTPOLE_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    cart_dof_name = "slider_to_cart"
    pole_dof_name = "cart_to_pole"

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=4.0, replicate_physics=True)

    # reset
    max_cart_pos = 3.0
    initial_pole_angle_range = [-0.25, 0.25]

    # reward scales
    rew_scale_alive = 1.0
    rew_scale_terminated = -2.0
    rew_scale_pole_pos = -1.0
    rew_scale_cart_vel = -0.01
    rew_scale_pole_vel = -0.005


class CartpoleEnv(DirectRLEnv):
    cfg: CartpoleEnvCfg

    def __init__(self, cfg: CartpoleEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)

        self._cart_dof_idx, _ = self.cartpole.find_joints(self.cfg.cart_dof_name)
        self._pole_dof_idx, _ = self.cartpole.find_joints(self.cfg.pole_dof_name)
        self.action_scale = self.cfg.action_scale

        self.joint_pos = self.cartpole.data.joint_pos
        self.joint_vel = self.cartpole.data.joint_vel

    def _setup_scene(self):
        self.cartpole = Articulation(self.cfg.robot_cfg)
        # add ground plane
        spawn_ground_plane(prim_path="/World/ground", cfg=GroundPlaneCfg())
        # clone and replicate
        self.scene.clone_environments(copy_from_source=False)
        # we need to explicitly filter collisions for CPU simulation
        if self.device == "cpu":
            self.scene.filter_collisions(global_prim_paths=[])
        # add articulation to scene
        self.scene.articulations["cartpole"] = self.cartpole
        # add lights
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def _pre_physics_step(self, actions: torch.Tensor) -> None:
        self.actions = self.action_scale * actions.clone()

    def _apply_action(self) -> None:
        self.cartpole.set_joint_effort_target(self.actions, joint_ids=self._cart_dof_idx)

    def _get_observations(self) -> dict:
        obs = torch.cat(
            (
                self.joint_pos[:, self._pole_dof_idx[0]].unsqueeze(dim=1),
                self.joint_vel[:, self._pole_dof_idx[0]].unsqueeze(dim=1),
                self.joint_pos[:, self._cart_dof_idx[0]].unsqueeze(dim=1),
                self.joint_vel[:, self._cart_dof_idx[0]].unsqueeze(dim=1),
            ),
            dim=-1,
        )
        observations = {"policy": obs}
        return observations

    def _get_rewards(self) -> torch.Tensor:
        total_reward = compute_rewards(
            self.cfg.rew_scale_alive,
            self.cfg.rew_scale_terminated,
            self.cfg.rew_scale_pole_pos,
            self.cfg.rew_scale_cart_vel,
            self.cfg.rew_scale_pole_vel,
            self.joint_pos[:, self._pole_dof_idx[0]],
            self.joint_vel[:, self._pole_dof_idx[0]],
            self.joint_pos[:, self._cart_dof_idx[0]],
            self.joint_vel[:, self._cart_dof_idx[0]],
            self.reset_terminated,
        )
        return total_reward

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        self.joint_pos = self.cartpole.data.joint_pos
        self.joint_vel = self.cartpole.data.joint_vel

        time_out = self.episode_length_buf >= self.max_episode_length - 1
        out_of_bounds = torch.any(torch.abs(self.joint_pos[:, self._cart_dof_idx]) > self.cfg.max_cart_pos, dim=1)
        out_of_bounds = out_of_bounds | torch.any(torch.abs(self.joint_pos[:, self._pole_dof_idx]) > math.pi / 2, dim=1)
        return out_of_bounds, time_out

    def _reset_idx(self, env_ids: Sequence[int] | None):
        if env_ids is None:
            env_ids = self.cartpole._ALL_INDICES
        super()._reset_idx(env_ids)

        joint_pos = self.cartpole.data.default_joint_pos[env_ids]
        joint_pos[:, self._pole_dof_idx] += sample_uniform(
            self.cfg.initial_pole_angle_range[0] * math.pi,
            self.cfg.initial_pole_angle_range[1] * math.pi,
            joint_pos[:, self._pole_dof_idx].shape,
            joint_pos.device,
        )
        joint_vel = self.cartpole.data.default_joint_vel[env_ids]

        default_root_state = self.cartpole.data.default_root_state[env_ids]
        default_root_state[:, :3] += self.scene.env_origins[env_ids]

        self.joint_pos[env_ids] = joint_pos
        self.joint_vel[env_ids] = joint_vel

        self.cartpole.write_root_pose_to_sim(default_root_state[:, :7], env_ids)
        self.cartpole.write_root_velocity_to_sim(default_root_state[:, 7:], env_ids)
        self.cartpole.write_joint_state_to_sim(joint_pos, joint_vel, None, env_ids)


@torch.jit.script
def compute_rewards(
    rew_scale_alive: float,
    rew_scale_terminated: float,
    rew_scale_pole_pos: float,
    rew_scale_cart_vel: float,
    rew_scale_pole_vel: float,
    pole_pos: torch.Tensor,
    pole_vel: torch.Tensor,
    cart_pos: torch.Tensor,
    cart_vel: torch.Tensor,
    reset_terminated: torch.Tensor,
):
    rew_alive = rew_scale_alive * (1.0 - reset_terminated.float())
    rew_termination = rew_scale_terminated * reset_terminated.float()
    rew_pole_pos = rew_scale_pole_pos * torch.sum(torch.square(pole_pos).unsqueeze(dim=1), dim=-1)
    rew_cart_vel = rew_scale_cart_vel * torch.sum(torch.abs(cart_vel).unsqueeze(dim=1), dim=-1)
    rew_pole_vel = rew_scale_pole_vel * torch.sum(torch.abs(pole_vel).unsqueeze(dim=1), dim=-1)
    total_reward = rew_alive + rew_termination + rew_pole_pos + rew_cart_vel + rew_pole_vel
    return total_reward
"""

# SPEC "Porting from Isaac Lab": the import mapping, most specific first.
IMPORT_MAPPING = [
    (r"\bisaaclab_assets\.robots\b", "simlab.robots"),
    (r"\bisaaclab_assets\b", "simlab.robots"),
    (r"\bisaaclab_tasks\b", "simlab.tasks"),
    (r"\bisaaclab_rl\b", "simlab.rl"),
    (r"\bisaaclab\b", "simlab"),
]


def port(source: str) -> str:
    """Rewrite the ``isaaclab`` imports of ``source``; only import lines change."""
    lines = []
    for line in source.splitlines(keepends=True):
        if re.match(r"\s*(from|import)\s+isaaclab", line):
            for pattern, replacement in IMPORT_MAPPING:
                line = re.sub(pattern, replacement, line)
        lines.append(line)
    return "".join(lines)


def import_file(path, name: str):
    return load_script(path, name)


def test_the_mapping_only_touches_imports():
    ported = port(ISAACLAB_CARTPOLE)
    assert "isaaclab" not in ported
    assert "from simlab.robots.cartpole import CARTPOLE_CFG" in ported
    assert "import simlab.sim as sim_utils" in ported
    changed = [(a, b) for a, b in zip(ISAACLAB_CARTPOLE.splitlines(), ported.splitlines()) if a != b]
    assert changed and all(a.lstrip().startswith(("from isaaclab", "import isaaclab")) for a, _ in changed)


def test_isaac_lab_cartpole_runs_after_the_import_mapping(tmp_path):
    path = tmp_path / "isaaclab_cartpole_env.py"
    path.write_text(port(ISAACLAB_CARTPOLE))
    module = import_file(path, "isaaclab_cartpole_env")
    try:
        cfg = module.CartpoleEnvCfg(seed=3)
        # Fixed initial angles: Isaac Lab's reset draws for the resetting envs, simlab's for every
        # env (kept where they reset), so only deterministic resets give the same random stream.
        cfg.initial_pole_angle_range = [0.1, 0.1]
        cfg.scene.num_envs = 8
        cfg.sim.device = "cpu"
        env = module.CartpoleEnv(cfg)
        obs, _ = env.reset()
        assert obs["policy"].shape == (8, 4)
        ported_obs, resets = [obs["policy"].clone()], 0
        generator = torch.Generator().manual_seed(0)
        actions = [2 * torch.rand(8, 1, generator=generator) - 1 for _ in range(150)]
        for action in actions:
            obs, reward, terminated, truncated, extras = env.step(action)
            ported_obs.append(obs["policy"].clone())
            resets += int((terminated | truncated).sum())
        assert resets > 0, "random pushes end some episodes, which exercises the ported _reset_idx"
        env.close()

        # simlab's own cartpole, same seed and actions: the same trajectory
        from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv, CartpoleEnvCfg

        native_cfg = CartpoleEnvCfg(seed=3)
        native_cfg.initial_pole_angle_range = [0.1, 0.1]
        native_cfg.scene.num_envs = 8
        native_cfg.sim.device = "cpu"
        native = CartpoleEnv(native_cfg)
        obs, _ = native.reset()
        native_obs = [obs["policy"].clone()]
        for action in actions:
            native_obs.append(native.step(action)[0]["policy"].clone())
        native.close()
        torch.testing.assert_close(torch.stack(ported_obs), torch.stack(native_obs))
    finally:
        sys.modules.pop("isaaclab_cartpole_env", None)


# A manager-based task written the Isaac Lab way, with the deep import paths and the __post_init__
# settings Isaac Lab's own task configs use (PhysX tuning, the default material, schema configs).
ISAACLAB_ANT_WITH_BOX = """
from __future__ import annotations

import isaaclab.envs.mdp as mdp
import isaaclab.sim as sim_utils
from isaaclab.assets import AssetBaseCfg, DeformableObjectCfg, RigidObjectCfg
from isaaclab.envs import ManagerBasedRLEnvCfg
from isaaclab.managers import EventTermCfg as EventTerm
from isaaclab.managers import ObservationGroupCfg as ObsGroup
from isaaclab.managers import ObservationTermCfg as ObsTerm
from isaaclab.managers import RewardTermCfg as RewTerm
from isaaclab.managers import SceneEntityCfg
from isaaclab.managers import TerminationTermCfg as DoneTerm
from isaaclab.scene import InteractiveSceneCfg
from isaaclab.sim.schemas.schemas_cfg import MassPropertiesCfg, RigidBodyPropertiesCfg
from isaaclab.sim.spawners.from_files.from_files_cfg import GroundPlaneCfg
from isaaclab.sim.spawners.materials.physics_materials_cfg import RigidBodyMaterialCfg
from isaaclab.terrains import TerrainImporterCfg
from isaaclab.utils import configclass

from isaaclab_assets.robots.ant import ANT_CFG


@configclass
class AntSceneCfg(InteractiveSceneCfg):
    terrain = TerrainImporterCfg(
        prim_path="/World/ground",
        terrain_type="plane",
        collision_group=-1,
        physics_material=RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0, restitution=0.0),
    )
    robot = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
    box: RigidObjectCfg | DeformableObjectCfg = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Box",
        spawn=sim_utils.CuboidCfg(
            size=(0.2, 0.2, 0.2), rigid_props=RigidBodyPropertiesCfg(), mass_props=MassPropertiesCfg(mass=1.0)
        ),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(1.5, 0.0, 0.1)),
    )
    light = AssetBaseCfg(prim_path="/World/light", spawn=sim_utils.DistantLightCfg(intensity=3000.0))


@configclass
class ActionsCfg:
    joint_effort = mdp.JointEffortActionCfg(asset_name="robot", joint_names=[".*"], scale=7.5)


@configclass
class ObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        base_lin_vel = ObsTerm(func=mdp.base_lin_vel)
        torso_pose = ObsTerm(func=mdp.body_pose_w, params={"asset_cfg": SceneEntityCfg("robot", body_names="torso")})
        legs_gravity = ObsTerm(
            func=mdp.body_projected_gravity_b, params={"asset_cfg": SceneEntityCfg("robot", body_names=".*_leg")}
        )
        time = ObsTerm(func=mdp.current_time_s)
        time_left = ObsTerm(func=mdp.remaining_time_s)
        joint_pos = ObsTerm(func=mdp.joint_pos_limit_normalized)
        actions = ObsTerm(func=mdp.last_action)

    policy: PolicyCfg = PolicyCfg()


@configclass
class EventCfg:
    reset_base = EventTerm(
        func=mdp.reset_root_state_uniform,
        mode="reset",
        params={"pose_range": {"yaw": (-3.14, 3.14)}, "velocity_range": {}},
    )
    tumble_box = EventTerm(
        func=mdp.reset_root_state_with_random_orientation,
        mode="reset",
        params={"pose_range": {"z": (0.2, 0.2)}, "velocity_range": {}, "asset_cfg": SceneEntityCfg("box")},
    )


@configclass
class RewardsCfg:
    alive = RewTerm(func=mdp.is_alive, weight=0.5)


@configclass
class TerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)


@configclass
class AntWithBoxEnvCfg(ManagerBasedRLEnvCfg):
    scene: AntSceneCfg = AntSceneCfg(num_envs=64, env_spacing=5.0)
    observations: ObservationsCfg = ObservationsCfg()
    actions: ActionsCfg = ActionsCfg()
    events: EventCfg = EventCfg()
    rewards: RewardsCfg = RewardsCfg()
    terminations: TerminationsCfg = TerminationsCfg()

    def __post_init__(self):
        self.decimation = 2
        self.episode_length_s = 16.0
        self.sim.dt = 1 / 120.0
        self.sim.render_interval = self.decimation
        self.sim.physx.bounce_threshold_velocity = 0.2
        self.sim.physx.gpu_max_rigid_patch_count = 10 * 2**15
        self.sim.physics_material.static_friction = 1.0
        self.sim.physics_material.dynamic_friction = 1.0
        self.sim.physics_material.restitution = 0.0
"""


def test_an_isaac_lab_manager_based_config_runs_after_the_import_mapping(tmp_path):
    path = tmp_path / "isaaclab_ant_with_box_env_cfg.py"
    path.write_text(port(ISAACLAB_ANT_WITH_BOX))
    module = import_file(path, "isaaclab_ant_with_box_env_cfg")
    try:
        from simlab.envs import ManagerBasedRLEnv

        cfg = module.AntWithBoxEnvCfg()
        cfg.scene.num_envs, cfg.sim.device, cfg.seed = 4, "cpu", 0
        env = ManagerBasedRLEnv(cfg)
        obs, _ = env.reset()
        # 3 + 7 (torso pose) + 4 x 3 (legs' gravity) + 1 + 1 + 8 + 8
        assert obs["policy"].shape == (4, 40)
        for _ in range(30):
            obs, *_ = env.step(torch.zeros(4, 8))
        time, time_left = obs["policy"][:, 22], obs["policy"][:, 23]
        torch.testing.assert_close(time, torch.full((4,), 30 * env.step_dt))
        torch.testing.assert_close(time + time_left, torch.full((4,), 16.0))
        assert (env.scene["robot"].data.root_pos_w[:, 2] > 0.2).all()  # standing on the terrain's plane
        box_up = env.scene["box"].data.projected_gravity_b
        assert box_up.std(dim=0).max() > 0.1  # the boxes were reset at random orientations, settled on a face
        env.close()
    finally:
        sys.modules.pop("isaaclab_ant_with_box_env_cfg", None)
