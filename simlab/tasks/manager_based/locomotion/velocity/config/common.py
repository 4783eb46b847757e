"""Settings that Isaac Lab's per-robot velocity configs repeat word for word, written once.

Each robot keeps its own small files and Isaac Lab's class names (``UnitreeGo1RoughEnvCfg``, ...);
their ``__post_init__`` calls these on ``self``:

* :func:`unitree_rough` - Isaac Lab's rough recipe for the Unitree quadrupeds (Go1, A1, Go2);
* :func:`humanoid_rough` - the rough recipe the G1 and H1 share (tuned for MuJoCo, see ``g1/rough_env_cfg.py``);
* :func:`biped_events` - the bipeds' events (G1, H1, Cassie): no pushes or mass changes, start at rest;
* :func:`unitree_flat`, :func:`anymal_flat` - each family's flat rewards, on flat ground;
* :func:`flat_ground` - a plane, no height scan, no terrain curriculum;
* :func:`play` - the ``_PLAY`` variants: 50 envs, no observation noise, no pushes;
  :func:`humanoid_play` - the G1's and H1's: 40 s episodes, walking forward at 1 m/s.
"""

from __future__ import annotations

import math

from simlab.assets import ArticulationCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.tasks.manager_based.locomotion.velocity import mdp
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import LocomotionVelocityRoughEnvCfg


def reset_at_rest(cfg: LocomotionVelocityRoughEnvCfg) -> None:
    """Start at the default joint pose, at rest, anywhere in a 1 m square with any heading."""
    cfg.events.reset_robot_joints.params["position_range"] = (1.0, 1.0)
    cfg.events.reset_base.params = {
        "pose_range": {"x": (-0.5, 0.5), "y": (-0.5, 0.5), "yaw": (-3.14, 3.14)},
        "velocity_range": {k: (0.0, 0.0) for k in ("x", "y", "z", "roll", "pitch", "yaw")},
    }


def unitree_rough(cfg: LocomotionVelocityRoughEnvCfg, robot: ArticulationCfg, base: str) -> None:
    """Isaac Lab's Unitree rough task: ``robot`` (its base body named ``base``, its feet ``.*_foot``),
    smaller obstacles for a small robot, no pushes, a heavier payload range, a standing reset."""
    cfg.scene.robot = robot.replace(prim_path="{ENV_REGEX_NS}/Robot")
    cfg.scene.height_scanner.prim_path = "{ENV_REGEX_NS}/Robot/" + base
    # smaller obstacles for a small robot
    cfg.scene.terrain.terrain_generator.sub_terrains["boxes"].grid_height_range = (0.025, 0.1)
    cfg.scene.terrain.terrain_generator.sub_terrains["random_rough"].noise_range = (0.01, 0.06)
    cfg.scene.terrain.terrain_generator.sub_terrains["random_rough"].noise_step = 0.01
    cfg.actions.joint_pos.scale = 0.25
    # events
    cfg.events.push_robot = None
    cfg.events.add_base_mass.params["mass_distribution_params"] = (-1.0, 3.0)
    cfg.events.add_base_mass.params["asset_cfg"].body_names = base
    cfg.events.base_external_force_torque.params["asset_cfg"].body_names = base
    reset_at_rest(cfg)
    cfg.events.base_com = None
    # rewards
    cfg.rewards.feet_air_time.params["sensor_cfg"].body_names = ".*_foot"
    cfg.rewards.feet_air_time.weight = 0.01
    cfg.rewards.undesired_contacts = None
    cfg.rewards.dof_torques_l2.weight = -0.0002
    cfg.rewards.track_lin_vel_xy_exp.weight = 1.5
    cfg.rewards.track_ang_vel_z_exp.weight = 0.75
    cfg.rewards.dof_acc_l2.weight = -2.5e-7
    # terminations
    cfg.terminations.base_contact.params["sensor_cfg"].body_names = base


def biped_events(cfg: LocomotionVelocityRoughEnvCfg, body_names: str | list[str]) -> None:
    """The bipeds' events: no pushes, no mass or centre-of-mass changes, the (zero) external force on
    ``body_names``; start at rest."""
    cfg.events.push_robot = None
    cfg.events.add_base_mass = None
    cfg.events.base_com = None
    cfg.events.base_external_force_torque.params["asset_cfg"].body_names = body_names
    reset_at_rest(cfg)


def humanoid_rough(cfg: LocomotionVelocityRoughEnvCfg, robot: ArticulationCfg, torso: str) -> None:
    """The G1's and H1's rough task: ``robot`` scanned from its ``torso_link``, the biped events with the
    external force on ``torso`` (a body-name pattern), level-base and smoothness rewards, forward and
    turning commands only, and an episode that ends when ``torso`` touches the ground or the base tilts
    past 70 degrees (mjlab's fall)."""
    cfg.scene.robot = robot.replace(prim_path="{ENV_REGEX_NS}/Robot")
    cfg.scene.height_scanner.prim_path = "{ENV_REGEX_NS}/Robot/torso_link"
    biped_events(cfg, [torso])
    # rewards
    cfg.rewards.undesired_contacts = None
    cfg.rewards.flat_orientation_l2.weight = -1.0
    cfg.rewards.action_rate_l2.weight = -0.005
    cfg.rewards.dof_acc_l2.weight = -1.25e-7
    # commands: forward and turning only
    cfg.commands.base_velocity.ranges.lin_vel_x = (0.0, 1.0)
    cfg.commands.base_velocity.ranges.lin_vel_y = (0.0, 0.0)
    cfg.commands.base_velocity.ranges.ang_vel_z = (-1.0, 1.0)
    # terminations
    cfg.terminations.base_contact.params["sensor_cfg"].body_names = torso
    cfg.terminations.fell_over = DoneTerm(func=mdp.bad_orientation, params={"limit_angle": math.radians(70.0)})


def flat_ground(cfg: LocomotionVelocityRoughEnvCfg) -> None:
    """A plane, no height scan, no terrain curriculum."""
    cfg.scene.terrain.terrain_type = "plane"
    cfg.scene.terrain.terrain_generator = None
    cfg.scene.height_scanner = None
    cfg.observations.policy.height_scan = None
    cfg.curriculum.terrain_levels = None


def unitree_flat(cfg: LocomotionVelocityRoughEnvCfg) -> None:
    """Isaac Lab's Unitree flat task (from its rough one): level-base and air-time rewards, flat ground."""
    cfg.rewards.flat_orientation_l2.weight = -2.5
    cfg.rewards.feet_air_time.weight = 0.25
    flat_ground(cfg)


def anymal_flat(cfg: LocomotionVelocityRoughEnvCfg) -> None:
    """Isaac Lab's ANYmal flat task (from its rough one): level-base, torque and air-time rewards, flat
    ground."""
    cfg.rewards.flat_orientation_l2.weight = -5.0
    cfg.rewards.dof_torques_l2.weight = -2.5e-5
    cfg.rewards.feet_air_time.weight = 0.5
    flat_ground(cfg)


def play(cfg: LocomotionVelocityRoughEnvCfg, pushes: bool = False) -> None:
    """Isaac Lab's ``_PLAY`` variants: 50 envs, no observation noise, no pushes or external forces (but
    with ``pushes``: Isaac Lab's Cassie keeps its events); on generated terrain, spawned anywhere on a
    small 5 x 5 grid instead of on the curriculum's levels."""
    cfg.scene.num_envs = 50
    cfg.scene.env_spacing = 2.5
    if cfg.scene.terrain.terrain_generator is not None:
        cfg.scene.terrain.max_init_terrain_level = None
        cfg.scene.terrain.terrain_generator.num_rows = 5
        cfg.scene.terrain.terrain_generator.num_cols = 5
        cfg.scene.terrain.terrain_generator.curriculum = False
    cfg.observations.policy.enable_corruption = False
    if not pushes:
        cfg.events.base_external_force_torque = None
        cfg.events.push_robot = None


def humanoid_play(cfg: LocomotionVelocityRoughEnvCfg) -> None:
    """The G1's and H1's ``_PLAY``: :func:`play` with 40 s episodes, walking forward at 1 m/s while
    turning."""
    play(cfg)
    cfg.episode_length_s = 40.0
    cfg.commands.base_velocity.ranges.lin_vel_x = (1.0, 1.0)
    cfg.commands.base_velocity.ranges.lin_vel_y = (0.0, 0.0)
    cfg.commands.base_velocity.ranges.ang_vel_z = (-1.0, 1.0)
    cfg.commands.base_velocity.ranges.heading = (0.0, 0.0)
