"""Configs of the AMP humanoid (Isaac Lab's ``HumanoidAmpEnvCfg`` and its walk / run / dance clips).

The robot is simlab's 21-joint MuJoCo humanoid (``simlab/robots/assets/humanoid.xml``), not Isaac
Lab's 28-joint AMP humanoid: the clips shipped here are made for it
(``motions/kinematic_clips.py``). A motion file for another skeleton must name this humanoid's
joints and the bodies ``torso``, ``right_hand``, ``left_hand``, ``right_foot``, ``left_foot``.
"""

from __future__ import annotations

import os
from dataclasses import MISSING

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg
from simlab.envs import DirectRLEnvCfg, ViewerCfg
from simlab.robots.humanoid import HUMANOID_CFG, HUMANOID_GEARS
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, SimulationCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg
from simlab.utils import configclass

from .motions import MOTIONS_DIR

NUM_JOINTS = 21
KEY_BODIES = ("right_hand", "left_hand", "right_foot", "left_foot")
# joint positions, joint velocities, root height, root tangent and normal, root linear and angular
# velocity, key body positions relative to the root
AMP_OBSERVATION_SIZE = 2 * NUM_JOINTS + 1 + 6 + 3 + 3 + 3 * len(KEY_BODIES)

# PD position drives: the policy's actions are joint targets (Isaac Lab's AMP humanoid takes its
# gains from its USD; these are chosen for the 41 kg MuJoCo humanoid, stiff enough to hold a pose
# against gravity and soft enough to stay stable at 120 Hz). Each drive's torque is limited to the
# humanoid's gear (its motor in the torque-driven tasks): a drive at its limit leaves MuJoCo's
# implicit integration (the force no longer depends on the velocity), so its full torque acts
# explicitly, and the former 300 N m on every joint (a foot weighs 0.5 kg) swung light joints by
# up to 150 rad/s per step, flipping the drive from one limit to the other until the world blew up
# (on MuJoCo Warp: nefc past njmax; tests/test_contact_buffers.py).
AMP_HUMANOID_CFG = HUMANOID_CFG.replace(
    prim_path="/World/envs/env_.*/Robot",
    actuators={
        "body": ImplicitActuatorCfg(
            joint_names_expr=[".*"],
            stiffness={
                "lower_waist:.*": 400.0,
                "pelvis": 400.0,
                ".*_thigh:.*": 400.0,
                ".*_shin": 300.0,
                ".*_foot:.*": 100.0,
                ".*_upper_arm:.*": 100.0,
                ".*_lower_arm": 60.0,
            },
            damping={
                "lower_waist:.*": 40.0,
                "pelvis": 40.0,
                ".*_thigh:.*": 40.0,
                ".*_shin": 30.0,
                ".*_foot:.*": 10.0,
                ".*_upper_arm:.*": 10.0,
                ".*_lower_arm": 6.0,
            },
            velocity_limit_sim={".*": 100.0},
            armature={".*": 0.01},
            effort_limit_sim=HUMANOID_GEARS,
        ),
    },
)


@configclass
class HumanoidAmpEnvCfg(DirectRLEnvCfg):
    """Humanoid AMP environment config (base class); the subclasses name the motion file."""

    # env
    episode_length_s = 10.0
    decimation = 4

    # spaces
    observation_space = AMP_OBSERVATION_SIZE
    action_space = NUM_JOINTS
    state_space = 0
    num_amp_observations = 2
    """Frames in the AMP observation (the current one and the ones before it, one env step apart)."""
    amp_observation_space = AMP_OBSERVATION_SIZE
    """Size of one AMP frame; the env's ``amp_observation_space`` holds ``num_amp_observations`` of them."""

    early_termination = True
    termination_height = 0.5

    motion_file: str = MISSING
    reference_body = "torso"
    key_bodies: tuple = KEY_BODIES
    reset_strategy = "random"  # default, random, random-start
    """How each env's humanoid starts an episode.

    * default: the asset's initial state.
    * random: a reference state of the motion at a uniformly drawn time (reference-state initialisation).
    * random-start: the reference state at the motion's start (time zero).
    """
    reference_lift = 0.05
    """Height [m] added to reference root positions at reset, so the feet start just above the ground."""

    imitation_reward = False
    """The env's reward: False gives a constant 1 (Isaac Lab; the agent's task reward scale is 0, so the
    discriminator alone teaches). True gives a task reward for the clip's poses and pace, each in (0, 1]:
    ``exp(-(e / pose_sigma)^2)`` with e the RMS joint error to the nearest clip frame, plus
    ``exp(-((v - v_clip) / speed_sigma)^2)`` with v the torso's forward speed; the agent's
    ``task_reward_scale`` must then be set above 0 for it to count."""
    pose_sigma = 0.3
    """Joint RMS error [rad] at which the pose reward has fallen to 1/e."""
    speed_sigma = 0.3
    """Forward speed error [m/s] at which the pace reward has fallen to 1/e."""

    # simulation: 120 Hz physics, 30 Hz control (Isaac Lab: 60 Hz x 2; the stiff PD drives of the
    # light MuJoCo limbs need the shorter step). MuJoCo Warp's buffers per world: measured peaks of
    # 15 contacts and 61 constraint rows (64 envs, 300 steps of random actions, reference-state
    # resets, no early termination: scripts/tools/measure_contact_buffers.py), reserved 4x over
    sim: SimulationCfg = SimulationCfg(dt=1 / 120, render_interval=decimation, mujoco=MujocoCfg(nconmax=64, njmax=320))
    terrain = GroundPlaneCfg(
        physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0, restitution=0.0)
    )

    # videos follow env 0's humanoid from its left side
    viewer: ViewerCfg = ViewerCfg(
        eye=(0.0, -4.0, 0.3), lookat=(0.0, 0.0, -0.3), origin_type="asset_root", asset_name="robot"
    )

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=10.0, replicate_physics=True)

    # robot
    robot: ArticulationCfg = AMP_HUMANOID_CFG


@configclass
class HumanoidAmpDanceEnvCfg(HumanoidAmpEnvCfg):
    motion_file = os.path.join(MOTIONS_DIR, "humanoid_dance.npz")


@configclass
class HumanoidAmpRunEnvCfg(HumanoidAmpEnvCfg):
    # recorded from Humanoid-v0's policy (scripts/tools/record_motion_clip.py): every frame is one this
    # body's physics produced, and AMP learns it (docs/performance.md); the kinematic run clip,
    # humanoid_run.npz, stays available through env.motion_file
    motion_file = os.path.join(MOTIONS_DIR, "humanoid_run_recorded.npz")


@configclass
class HumanoidAmpWalkEnvCfg(HumanoidAmpEnvCfg):
    # recorded as the run's, from Humanoid-v0 trained with half its progress reward (a 0.93 m/s walk; the
    # commands are in docs/performance.md): AMP learned it where the generator's walk, humanoid_walk.npz
    # (still there for env.motion_file), taught only standing
    motion_file = os.path.join(MOTIONS_DIR, "humanoid_walk_recorded.npz")
