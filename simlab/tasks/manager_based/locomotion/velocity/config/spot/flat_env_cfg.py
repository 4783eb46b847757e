"""Boston Dynamics Spot velocity tracking (Isaac Lab's ``Isaac-Velocity-Flat-Spot-v0``): "flat" is a
cobblestone road of flat and slightly rough tiles, 50 Hz control (Isaac Lab's) over 200 Hz physics
(Isaac Lab: 500 Hz), Spot's own gait, clearance and smoothness rewards (``spot.mdp``) and its own
commands, observations and events."""

import simlab.sim as sim_utils
import simlab.tasks.manager_based.locomotion.velocity.config.spot.mdp as spot_mdp
import simlab.tasks.manager_based.locomotion.velocity.mdp as mdp
import simlab.terrains as terrain_gen
from simlab.envs import ViewerCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg, SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.robots.spot import SPOT_STIFF_CFG
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import LocomotionVelocityRoughEnvCfg
from simlab.terrains import TerrainImporterCfg
from simlab.utils import configclass
from simlab.utils.noise import AdditiveUniformNoiseCfg as Unoise

COBBLESTONE_ROAD_CFG = terrain_gen.TerrainGeneratorCfg(
    size=(8.0, 8.0),
    border_width=20.0,
    num_rows=9,
    num_cols=21,
    horizontal_scale=0.1,
    vertical_scale=0.005,
    slope_threshold=0.75,
    difficulty_range=(0.0, 1.0),
    use_cache=False,
    sub_terrains={
        "flat": terrain_gen.MeshPlaneTerrainCfg(proportion=0.2),
        "random_rough": terrain_gen.HfRandomUniformTerrainCfg(
            proportion=0.2, noise_range=(0.02, 0.05), noise_step=0.02, border_width=0.25
        ),
    },
)
"""Isaac Lab's Spot ground: flat and 2-5 cm rough tiles in equal shares."""

_FEET = SceneEntityCfg("contact_forces", body_names=".*_foot")

ISAAC_LAB_PHYSICS_DT = 0.002
"""The physics step of Isaac Lab's Spot task, in which ``SPOT_CFG``'s actuator delays are counted."""


def delay_in_physics_steps(isaac_lab_steps: int, dt: float) -> int:
    """An actuator delay of ``isaac_lab_steps`` of Isaac Lab's 2 ms physics steps as the nearest whole
    number of steps of ``dt``: Spot's 0-4 steps (0-8 ms) are 0-2 steps of 5 ms (0-10 ms)."""
    return round(isaac_lab_steps * ISAAC_LAB_PHYSICS_DT / dt)


@configclass
class SpotActionsCfg:
    joint_pos = mdp.JointPositionActionCfg(asset_name="robot", joint_names=[".*"], scale=0.2, use_default_offset=True)


@configclass
class SpotCommandsCfg:
    base_velocity = mdp.UniformVelocityCommandCfg(
        asset_name="robot",
        resampling_time_range=(10.0, 10.0),
        rel_standing_envs=0.1,
        rel_heading_envs=0.0,
        heading_command=False,
        ranges=mdp.UniformVelocityCommandCfg.Ranges(
            lin_vel_x=(-2.0, 3.0), lin_vel_y=(-1.5, 1.5), ang_vel_z=(-2.0, 2.0)
        ),
    )


@configclass
class SpotObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        base_lin_vel = ObsTerm(func=mdp.base_lin_vel, noise=Unoise(n_min=-0.1, n_max=0.1))
        base_ang_vel = ObsTerm(func=mdp.base_ang_vel, noise=Unoise(n_min=-0.1, n_max=0.1))
        projected_gravity = ObsTerm(func=mdp.projected_gravity, noise=Unoise(n_min=-0.05, n_max=0.05))
        velocity_commands = ObsTerm(func=mdp.generated_commands, params={"command_name": "base_velocity"})
        joint_pos = ObsTerm(func=mdp.joint_pos_rel, noise=Unoise(n_min=-0.05, n_max=0.05))
        joint_vel = ObsTerm(func=mdp.joint_vel_rel, noise=Unoise(n_min=-0.5, n_max=0.5))
        actions = ObsTerm(func=mdp.last_action)

        def __post_init__(self):
            self.enable_corruption = False  # Isaac Lab's Spot trains without observation noise
            self.concatenate_terms = True

    policy: PolicyCfg = PolicyCfg()


@configclass
class SpotEventCfg:
    # startup
    physics_material = EventTerm(
        func=mdp.randomize_rigid_body_material,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names=".*"),
            "static_friction_range": (0.3, 1.0),
            "dynamic_friction_range": (0.3, 0.8),
            "restitution_range": (0.0, 0.0),
            "num_buckets": 64,
        },
    )
    add_base_mass = EventTerm(
        func=mdp.randomize_rigid_body_mass,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names="body"),
            "mass_distribution_params": (-2.5, 2.5),
            "operation": "add",
        },
    )
    # reset
    base_external_force_torque = EventTerm(
        func=mdp.apply_external_force_torque,
        mode="reset",
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names="body"),
            "force_range": (0.0, 0.0),
            "torque_range": (-0.0, 0.0),
        },
    )
    reset_base = EventTerm(
        func=mdp.reset_root_state_uniform,
        mode="reset",
        params={
            "pose_range": {"x": (-0.5, 0.5), "y": (-0.5, 0.5), "yaw": (-3.14, 3.14)},
            "velocity_range": {
                "x": (-1.5, 1.5),
                "y": (-1.0, 1.0),
                "z": (-0.5, 0.5),
                "roll": (-0.7, 0.7),
                "pitch": (-0.7, 0.7),
                "yaw": (-1.0, 1.0),
            },
        },
    )
    reset_robot_joints = EventTerm(
        func=spot_mdp.reset_joints_around_default,
        mode="reset",
        params={"position_range": (-0.2, 0.2), "velocity_range": (-2.5, 2.5)},
    )
    # interval
    push_robot = EventTerm(
        func=mdp.push_by_setting_velocity,
        mode="interval",
        interval_range_s=(10.0, 15.0),
        params={"velocity_range": {"x": (-0.5, 0.5), "y": (-0.5, 0.5)}},
    )


@configclass
class SpotRewardsCfg:
    # -- task
    air_time = RewardTermCfg(
        func=spot_mdp.air_time_reward,
        weight=5.0,
        params={"mode_time": 0.3, "velocity_threshold": 0.5, "asset_cfg": SceneEntityCfg("robot"), "sensor_cfg": _FEET},
    )
    base_angular_velocity = RewardTermCfg(
        func=spot_mdp.base_angular_velocity_reward,
        weight=5.0,
        params={"std": 2.0, "asset_cfg": SceneEntityCfg("robot")},
    )
    base_linear_velocity = RewardTermCfg(
        func=spot_mdp.base_linear_velocity_reward,
        weight=5.0,
        params={"std": 1.0, "ramp_rate": 0.5, "ramp_at_vel": 1.0, "asset_cfg": SceneEntityCfg("robot")},
    )
    foot_clearance = RewardTermCfg(
        func=spot_mdp.foot_clearance_reward,
        weight=0.5,
        params={
            "std": 0.05,
            "tanh_mult": 2.0,
            "target_height": 0.1,
            "asset_cfg": SceneEntityCfg("robot", body_names=".*_foot"),
        },
    )
    gait = RewardTermCfg(
        func=spot_mdp.GaitReward,
        weight=10.0,
        params={
            "std": 0.1,
            "max_err": 0.2,
            "velocity_threshold": 0.5,
            "synced_feet_pair_names": (("fl_foot", "hr_foot"), ("fr_foot", "hl_foot")),
            "asset_cfg": SceneEntityCfg("robot"),
            "sensor_cfg": SceneEntityCfg("contact_forces"),
        },
    )
    # -- penalties
    action_smoothness = RewardTermCfg(func=spot_mdp.action_smoothness_penalty, weight=-1.0)
    air_time_variance = RewardTermCfg(
        func=spot_mdp.air_time_variance_penalty, weight=-1.0, params={"sensor_cfg": _FEET}
    )
    base_motion = RewardTermCfg(
        func=spot_mdp.base_motion_penalty, weight=-2.0, params={"asset_cfg": SceneEntityCfg("robot")}
    )
    base_orientation = RewardTermCfg(
        func=spot_mdp.base_orientation_penalty, weight=-3.0, params={"asset_cfg": SceneEntityCfg("robot")}
    )
    foot_slip = RewardTermCfg(
        func=spot_mdp.foot_slip_penalty,
        weight=-0.5,
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names=".*_foot"),
            "sensor_cfg": _FEET,
            "threshold": 1.0,
        },
    )
    joint_acc = RewardTermCfg(
        func=spot_mdp.joint_acceleration_penalty,
        weight=-1.0e-4,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_h[xy]")},
    )
    joint_pos = RewardTermCfg(
        func=spot_mdp.joint_position_penalty,
        weight=-0.7,
        params={
            "asset_cfg": SceneEntityCfg("robot", joint_names=".*"),
            "stand_still_scale": 5.0,
            "velocity_threshold": 0.5,
        },
    )
    joint_torques = RewardTermCfg(
        func=spot_mdp.joint_torques_penalty,
        weight=-5.0e-4,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*")},
    )
    joint_vel = RewardTermCfg(
        func=spot_mdp.joint_velocity_penalty,
        weight=-1.0e-2,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_h[xy]")},
    )


@configclass
class SpotTerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)
    body_contact = DoneTerm(
        func=mdp.illegal_contact,
        params={"sensor_cfg": SceneEntityCfg("contact_forces", body_names=["body", ".*leg"]), "threshold": 1.0},
    )
    terrain_out_of_bounds = DoneTerm(func=mdp.terrain_out_of_bounds, params={"distance_buffer": 3.0}, time_out=True)


@configclass
class SpotFlatEnvCfg(LocomotionVelocityRoughEnvCfg):
    observations: SpotObservationsCfg = SpotObservationsCfg()
    actions: SpotActionsCfg = SpotActionsCfg()
    commands: SpotCommandsCfg = SpotCommandsCfg()
    rewards: SpotRewardsCfg = SpotRewardsCfg()
    terminations: SpotTerminationsCfg = SpotTerminationsCfg()
    events: SpotEventCfg = SpotEventCfg()
    viewer = ViewerCfg(eye=(10.5, 10.5, 0.3), origin_type="world", env_index=0, asset_name="robot")

    def __post_init__(self):
        super().__post_init__()
        # 50 Hz control as Isaac Lab's, over MuJoCo's 200 Hz physics (mjlab's quadrupeds' rate) where
        # Isaac Lab steps PhysX at 500 Hz: 4 physics steps a policy step instead of 10. The robot
        # stands and trots open-loop the same at either rate (docs/locomotion.md); the foot contact's
        # 4 ms time constant becomes MuJoCo's floor of two physics steps, 10 ms.
        self.decimation = 4
        self.episode_length_s = 20.0
        self.sim.dt = 0.005
        self.sim.render_interval = self.decimation
        self.sim.physics_material.static_friction = 1.0
        self.sim.physics_material.dynamic_friction = 1.0
        self.sim.physics_material.friction_combine_mode = "multiply"
        self.sim.physics_material.restitution_combine_mode = "multiply"
        # Friction: pyramidal cones (MuJoCo's default, simlab's, and that of Isaac Lab's MuJoCo-Warp
        # velocity presets) with impratio 10 (menagerie's Spot option): the robot stands as with
        # menagerie's elliptic cones (tests/test_quadruped_zoo.py) and the GPU step is 20 % faster (the
        # elliptic cone's Hessian is rebuilt in every Newton iteration). docs/locomotion.md has the A/B.
        self.sim.mujoco.cone = "pyramidal"
        self.sim.mujoco.impratio = 10.0
        # MuJoCo Warp's buffers per world, from the worst case driven on the CPU (robots thrown onto the
        # cobblestones, pushed and flailing, 64 worlds for 6 s: at most 20 contacts and 81 rows in a world,
        # 3 contacts a world pooled, at 500 Hz; 16, 66 and 2 at 200 Hz): instead of its height-field
        # estimate (128 contacts, 1048 rows: each row is a thread in every Newton iteration). The worlds
        # share one pool of nconmax * num_envs.
        self.sim.mujoco.nconmax = 32
        self.sim.mujoco.njmax = 192
        # MuJoCo's solver caps (100 iterations, 50 line-search) kept: mjlab's 10 / 20 cut the GPU's Newton
        # loop (up to 17 iterations at 200 Hz) but, under PPO's first noise, robots fell sooner and
        # joint accelerations blew up to 1e10 rad/s^2 in unconverged steps (docs/locomotion.md)
        # the gait rewards read the feet's contacts at every physics step
        self.scene.contact_forces.update_period = self.sim.dt
        # kp 100 where Isaac Lab has 60: this model has no upright stance at 60 (robots/spot.py)
        self.scene.robot = SPOT_STIFF_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        # Isaac Lab's actuator delays count its 2 ms physics steps; the same seconds in this task's steps
        for actuator in self.scene.robot.actuators.values():
            actuator.min_delay = delay_in_physics_steps(actuator.min_delay, self.sim.dt)
            actuator.max_delay = delay_in_physics_steps(actuator.max_delay, self.sim.dt)
        self.scene.terrain = TerrainImporterCfg(
            prim_path="/World/ground",
            terrain_type="generator",
            terrain_generator=COBBLESTONE_ROAD_CFG,
            max_init_terrain_level=COBBLESTONE_ROAD_CFG.num_rows - 1,
            collision_group=-1,
            physics_material=sim_utils.RigidBodyMaterialCfg(
                friction_combine_mode="multiply",
                restitution_combine_mode="multiply",
                static_friction=1.0,
                dynamic_friction=1.0,
            ),
        )
        self.scene.height_scanner = None


@configclass
class SpotFlatEnvCfg_PLAY(SpotFlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.scene.terrain.max_init_terrain_level = None
        if self.scene.terrain.terrain_generator is not None:
            self.scene.terrain.terrain_generator.num_rows = 5
            self.scene.terrain.terrain_generator.num_cols = 5
            self.scene.terrain.terrain_generator.curriculum = False
        self.observations.policy.enable_corruption = False
