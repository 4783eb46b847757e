# Copyright (c) 2022-2026, The Isaac Lab Project Developers (https://github.com/isaac-sim/IsaacLab/blob/main/CONTRIBUTORS.md).
# All rights reserved.
#
# SPDX-License-Identifier: BSD-3-Clause
#
# Isaac Lab 3.0's scripts/tutorials/01_assets/run_articulation.py, ported by the 3.0 mapping
# (docs/porting_3.md: isaaclab.app / .sim -> simlab.app / .sim, isaaclab.assets -> simlab.v3.assets,
# isaaclab_assets -> simlab.v3.robots). Lines that differ besides the imports, in ``design_scene``: 3.0
# clones two origins with ``isaaclab.cloner`` (clone_plan_from_env_0, replicate), which simlab does not map;
# here the two origin groups are made as the 2.x tutorial does, and the cart-poles' prim path names them.
# The robot is built as 3.0 builds it, ``cartpole_cfg.class_type(cartpole_cfg)``. ``run_simulator`` and ``main``
# are 3.0's text: ``data.default_root_pose.torch``, ``write_root_pose_to_sim_index(root_pose=...)``,
# ``write_joint_position_to_sim_index(position=...)``, ``actuators.target_command.set_effort_index(value=...)``.
# tests/test_isaaclab3_asset_api.py runs it.

"""This script demonstrates how to spawn a cart-pole and interact with it.

.. code-block:: bash

    # Usage
    uv run python scripts/tutorials/01_assets/run_articulation.py

"""

"""Launch Isaac Sim Simulator first."""


import argparse

from simlab.app import AppLauncher

# add argparse arguments
parser = argparse.ArgumentParser(description="Tutorial on spawning and interacting with an articulation.")
# append AppLauncher cli args
AppLauncher.add_app_launcher_args(parser)
# parse the arguments
args_cli = parser.parse_args()

# launch omniverse app
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

"""Rest everything follows."""

import torch  # noqa: E402

import simlab.sim.utils as prim_utils  # noqa: E402
import simlab.v3.sim as sim_utils  # noqa: E402
from simlab.sim import SimulationContext  # noqa: E402
from simlab.v3.assets import Articulation, AssetBaseCfg  # noqa: E402

##
# Pre-defined configs
##
from simlab.v3.robots import CARTPOLE_CFG  # isort:skip  # noqa: E402


def design_scene(sim: SimulationContext) -> tuple[dict, torch.Tensor]:
    """Designs the scene."""
    ground_cfg = AssetBaseCfg(prim_path="/World/defaultGroundPlane", spawn=sim_utils.GroundPlaneCfg())
    light_cfg = AssetBaseCfg(
        prim_path="/World/Light",
        spawn=sim_utils.DomeLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75)),
    )
    # (3.0 clones "/World/Origin{}" with isaaclab.cloner; here the two origin groups are made as in 2.x)
    origins = [[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    prim_utils.create_prim("/World/Origin1", "Xform", translation=origins[0])
    prim_utils.create_prim("/World/Origin2", "Xform", translation=origins[1])
    cartpole_cfg = CARTPOLE_CFG.replace(prim_path="/World/Origin.*/Robot")
    ground_cfg.spawn.func(ground_cfg.prim_path, ground_cfg.spawn)
    light_cfg.spawn.func(light_cfg.prim_path, light_cfg.spawn)
    cartpole = cartpole_cfg.class_type(cartpole_cfg)

    return {"cartpole": cartpole}, torch.tensor(origins, device=sim.device)


def run_simulator(sim: sim_utils.SimulationContext, entities: dict[str, Articulation], origins: torch.Tensor):
    """Runs the simulation loop."""
    # Extract scene entities
    # note: we only do this here for readability. In general, it is better to access the entities directly from
    #   the dictionary. This dictionary is replaced by the InteractiveScene class in the next tutorial.
    robot = entities["cartpole"]
    # Define simulation stepping
    sim_dt = sim.get_physics_dt()
    count = 0
    # Simulation loop
    while simulation_app.is_running():
        # Reset
        if count % 500 == 0:
            # reset counter
            count = 0
            # reset the scene entities
            # root state
            # we offset the root state by the origin since the states are written in simulation world frame
            # if this is not done, then the robots will be spawned at the (0, 0, 0) of the simulation world
            root_pose = robot.data.default_root_pose.torch.clone()
            root_pose[:, :3] += origins
            robot.write_root_pose_to_sim_index(root_pose=root_pose)
            root_vel = robot.data.default_root_vel.torch.clone()
            robot.write_root_velocity_to_sim_index(root_velocity=root_vel)
            # set joint positions with some noise
            joint_pos, joint_vel = (
                robot.data.default_joint_pos.torch.clone(),
                robot.data.default_joint_vel.torch.clone(),
            )
            joint_pos += torch.rand_like(joint_pos) * 0.1
            robot.write_joint_position_to_sim_index(position=joint_pos)
            robot.write_joint_velocity_to_sim_index(velocity=joint_vel)
            # clear internal buffers
            robot.reset()
            print("[INFO]: Resetting robot state...")
        # Apply random action
        # -- generate random joint efforts
        efforts = torch.randn_like(robot.data.joint_pos.torch) * 5.0
        # -- apply action to the robot
        robot.actuators.target_command.set_effort_index(value=efforts)
        # -- write data to sim
        robot.write_data_to_sim()
        # Perform step
        sim.step()
        # Increment counter
        count += 1
        # Update buffers
        robot.update(sim_dt)


def main():
    """Main function."""
    # Load kit helper
    sim_cfg = sim_utils.SimulationCfg(device=args_cli.device)
    sim = SimulationContext(sim_cfg)
    # Set main camera
    sim.set_camera_view([2.5, 0.0, 4.0], [0.0, 0.0, 2.0])
    # Design scene
    scene_entities, scene_origins = design_scene(sim)
    # Play the simulator
    sim.reset()
    # Now we are ready!
    print("[INFO]: Setup complete...")
    # Run the simulator
    run_simulator(sim, scene_entities, scene_origins)


if __name__ == "__main__":
    # run the main function
    main()
    # close sim app
    simulation_app.close()
