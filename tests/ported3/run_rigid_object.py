# Isaac Lab 3.0's scripts/tutorials/01_assets/run_rigid_object.py, written out under the 3.0 mapping
# (isaaclab.app -> simlab.app; isaaclab.sim -> simlab.v3.sim, its schema configs UsdPhysicsRigidBodyCfg,
# MassCfg, UsdPhysicsCollisionCfg as 2.x's; isaaclab.utils.math -> simlab.v3.utils.math; isaaclab.assets ->
# simlab.v3.assets). Nothing else differs: four cones under /World/Origin{i}, reset every 250 steps through
# data.default_root_pose.torch (x, y, z, w) and write_root_pose_to_sim_index. tests/test_isaaclab3_tutorials.py
# runs it.

"""Cones dropped at random heights above four origins, again every 250 steps."""

import argparse

from simlab.app import add_launcher_args, launch_simulation

parser = argparse.ArgumentParser(description="Tutorial on spawning and interacting with a rigid object.")
add_launcher_args(parser)
args_cli = parser.parse_args()

import torch  # noqa: E402

import simlab.v3.sim as sim_utils  # noqa: E402
import simlab.v3.utils.math as math_utils  # noqa: E402
from simlab.v3.assets import RigidObject, RigidObjectCfg  # noqa: E402
from simlab.v3.sim import SimulationContext  # noqa: E402


def design_scene():
    cfg = sim_utils.GroundPlaneCfg()
    cfg.func("/World/defaultGroundPlane", cfg)
    cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.8, 0.8, 0.8))
    cfg.func("/World/Light", cfg)
    # one group per origin, a cone in each
    origins = [[0.25, 0.25, 0.0], [-0.25, 0.25, 0.0], [0.25, -0.25, 0.0], [-0.25, -0.25, 0.0]]
    for i, origin in enumerate(origins):
        sim_utils.create_prim(f"/World/Origin{i}", "Xform", translation=origin)
    cone_cfg = RigidObjectCfg(
        prim_path="/World/Origin.*/Cone",
        spawn=sim_utils.ConeCfg(
            radius=0.1,
            height=0.2,
            rigid_props=sim_utils.UsdPhysicsRigidBodyCfg(),
            mass_props=sim_utils.MassCfg(mass=1.0),
            collision_props=sim_utils.UsdPhysicsCollisionCfg(),
            visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.0, 1.0, 0.0), metallic=0.2),
        ),
        init_state=RigidObjectCfg.InitialStateCfg(),
    )
    return {"cone": RigidObject(cfg=cone_cfg)}, origins


def run_simulator(sim: sim_utils.SimulationContext, entities: dict[str, RigidObject], origins: torch.Tensor):
    cone_object = entities["cone"]
    sim_dt = sim.get_physics_dt()
    count = 0
    while sim.is_headless_or_exist_active_visualizer():
        if count % 250 == 0:
            count = 0
            root_pose = cone_object.data.default_root_pose.torch.clone()
            # a random point on a cylinder above each origin
            root_pose[:, :3] += origins
            root_pose[:, :3] += math_utils.sample_cylinder(
                radius=0.1, h_range=(0.25, 0.5), size=cone_object.num_instances, device=cone_object.device
            )
            cone_object.write_root_pose_to_sim_index(root_pose=root_pose)
            cone_object.write_root_velocity_to_sim_index(root_velocity=cone_object.data.default_root_vel.torch.clone())
            cone_object.reset()
            print("[INFO]: Resetting object state...")
        cone_object.write_data_to_sim()
        sim.step()
        count += 1
        cone_object.update(sim_dt)
        if count % 50 == 0:
            print(f"Root position (in world): {cone_object.data.root_pos_w.torch}")


def main():
    sim_cfg = sim_utils.SimulationCfg(device=args_cli.device)
    with launch_simulation(sim_cfg, args_cli):
        sim = SimulationContext(sim_cfg)
        sim.set_camera_view(eye=[1.5, 0.0, 1.0], target=[0.0, 0.0, 0.0])
        scene_entities, scene_origins = design_scene()
        scene_origins = torch.tensor(scene_origins, device=sim.device)
        sim.reset()
        print("[INFO]: Setup complete...")
        run_simulator(sim, scene_entities, scene_origins)


if __name__ == "__main__":
    main()
