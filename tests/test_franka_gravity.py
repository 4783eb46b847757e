"""The Franka's joint-position PD under gravity, and ``disable_gravity`` on both physics engines.

Isaac Lab's ``FRANKA_PANDA_CFG`` keeps gravity on (kp 80 N m/rad): holding the default pose, the
shoulder and elbow sag by the gravity torque over the stiffness, and a reach policy has to aim its
joint targets past the pose it wants. ``disable_gravity=True`` (``FRANKA_PANDA_HIGH_PD_CFG``) becomes
MuJoCo's gravity compensation on every body, which MuJoCo Warp applies too: the arm then holds its
targets.
"""

import pytest
import torch

from simlab.envs import ManagerBasedRLEnv
from simlab.tasks.manager_based.manipulation.reach.config.franka.joint_pos_env_cfg import FrankaReachEnvCfg


def _hold_default_pose(disable_gravity: bool, engine: str) -> tuple[torch.Tensor, torch.Tensor]:
    """(joint error to the targets (7,), hand position (3,) in the base frame) after 2 s of zero actions."""
    cfg = FrankaReachEnvCfg()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.sim.engine = engine
    cfg.seed = 0
    cfg.events.reset_robot_joints.params["position_range"] = (1.0, 1.0)  # start at the default pose
    cfg.scene.robot.spawn.rigid_props.disable_gravity = disable_gravity
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        robot = env.scene["robot"]
        arm = robot.find_joints("panda_joint.*")[0]
        hand = robot.find_bodies("panda_hand")[0][0]
        for _ in range(60):
            env.step(torch.zeros(2, 7))
        error = (robot.data.joint_pos_target[0, arm] - robot.data.joint_pos[0, arm]).clone()
        hand_b = (robot.data.body_pos_w[0, hand] - robot.data.root_pos_w[0]).clone()
    finally:
        env.close()
    return error, hand_b


@pytest.mark.parametrize("engine", ["mujoco", "mujoco_warp"])
def test_disable_gravity_removes_the_sag_of_the_pd_drive(engine):
    sag, hand_sagging = _hold_default_pose(disable_gravity=False, engine=engine)
    held, hand_held = _hold_default_pose(disable_gravity=True, engine=engine)
    # with gravity: the shoulder (joint 2) and elbow (joint 4) hang about 0.13 and 0.22 rad below their
    # targets (gravity torques of about 11 and 18 N m over kp 80), the hand ~16 cm lower than commanded
    assert 0.08 < sag[1].abs() < 0.2 and 0.15 < sag[3].abs() < 0.3, sag
    drop = hand_held - hand_sagging
    assert 0.12 < torch.linalg.norm(drop) < 0.2 and drop[2] > 0.1, drop
    # compensated: every joint holds its target
    assert held.abs().max() < 1e-3, held
