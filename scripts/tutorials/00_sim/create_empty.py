"""Create an empty simulation and step it.

The Isaac Lab (2.x) tutorial of the same name with ``isaaclab`` imports replaced by ``simlab``.

    python scripts/tutorials/00_sim/create_empty.py --headless --device cpu --max_app_steps 100
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Tutorial on creating an empty stage.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

from simlab.sim import SimulationCfg, SimulationContext  # noqa: E402


def main():
    """Main function."""
    # Initialize the simulation context
    sim_cfg = SimulationCfg(dt=0.01)
    sim = SimulationContext(sim_cfg)
    # Set main camera
    sim.set_camera_view([2.5, 2.5, 2.5], [0.0, 0.0, 0.0])
    # Play the simulator
    sim.reset()
    # Now we are ready!
    print("[INFO]: Setup complete...")
    # Simulate physics
    while simulation_app.is_running():
        # perform step
        sim.step()


if __name__ == "__main__":
    main()
    simulation_app.close()
