"""What a height scan costs per env step: the pose it needs, how often it casts, and the rough G1's
contact buffers on the terrain it scans (issue 39)."""

from __future__ import annotations

import torch

import simlab.sim as sim_utils
from simlab.assets import AssetBaseCfg
from simlab.robots.unitree import UNITREE_GO2_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import RayCasterCfg, patterns
from simlab.utils import configclass


def test_height_scanner_on_a_child_body_needs_the_kinematics_not_a_forward():
    """A scanner on a body below the floating base (the G1's torso_link) reads its pose from the
    kinematics pass: on MuJoCo Warp a forward is the collision and a constraint solve (262 launches for
    the rough G1, a fifth physics step per env step), the kinematics 22. Same hits as after a forward."""

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot = UNITREE_GO2_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        scanner = RayCasterCfg(
            prim_path="{ENV_REGEX_NS}/Robot/FL_thigh",
            offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 20.0)),
            ray_alignment="yaw",
            pattern_cfg=patterns.GridPatternCfg(resolution=0.5, size=[1.0, 1.0]),
            mesh_prim_paths=["/World/ground"],
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu", engine="mujoco_warp"))
    scene = InteractiveScene(SceneCfg(num_envs=2, env_spacing=2.0))
    sim.reset()
    physics, robot, scanner = sim.physics, scene["robot"], scene["scanner"]
    forwards = []
    original = physics.forward
    physics.forward = lambda *args, **kwargs: forwards.append(1) or original(*args, **kwargs)
    for _ in range(3):
        robot.set_joint_position_target(robot.data.default_joint_pos + 0.2)
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
    assert physics.is_stale
    forwards.clear()
    pos, hits = scanner.data.pos_w.clone(), scanner.data.ray_hits_w.clone()
    assert forwards == [], "the scan ran a forward"
    sim.forward()
    scanner.update(0.0, force_recompute=True)
    torch.testing.assert_close(pos, robot.data.body_pos_w[:, robot.find_bodies("FL_thigh")[0][0]])
    torch.testing.assert_close(scanner.data.ray_hits_w, hits)
