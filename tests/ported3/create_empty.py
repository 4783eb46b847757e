# Isaac Lab 3.0's scripts/tutorials/00_sim/create_empty.py, written out under the 3.0 mapping
# (docs/porting_3.md: isaaclab.app -> simlab.app, isaaclab.sim -> simlab.v3.sim). Nothing else differs:
# a SimulationCfg handed to launch_simulation, the loop on sim.is_headless_or_exist_active_visualizer().
# tests/test_isaaclab3_tutorials.py runs it.

"""An empty simulation, stepped until the app stops."""

import argparse

from simlab.app import add_launcher_args, launch_simulation

parser = argparse.ArgumentParser(description="Tutorial on creating an empty stage.")
add_launcher_args(parser)
args_cli = parser.parse_args()

from simlab.v3.sim import SimulationCfg, SimulationContext  # noqa: E402


def main():
    sim_cfg = SimulationCfg(dt=0.01, device=args_cli.device)
    with launch_simulation(sim_cfg, args_cli):
        sim = SimulationContext(sim_cfg)
        sim.set_camera_view([2.5, 2.5, 2.5], [0.0, 0.0, 0.0])
        sim.reset()
        print("[INFO]: Setup complete...")
        while sim.is_headless_or_exist_active_visualizer():
            sim.step()


if __name__ == "__main__":
    main()
