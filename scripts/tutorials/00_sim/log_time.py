"""Write the simulated time of every step to ``logs/docker_tutorial/log.txt``.

Makes the calls of Isaac Lab's (2.x) ``00_sim/log_time.py`` (its docker tutorial's script) under the
import mapping: the log folder below the working directory, ``sim.get_physics_dt()``, one line per step.

    python scripts/tutorials/00_sim/log_time.py --headless --device cpu --max_app_steps 100
"""

import argparse
import os

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Log the simulated time while the simulation plays.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

from simlab.sim import SimulationCfg, SimulationContext  # noqa: E402


def main() -> None:
    log_dir = os.path.abspath(os.path.join("logs", "docker_tutorial"))
    os.makedirs(log_dir, exist_ok=True)
    print(f"[INFO] Logging experiment to directory: {log_dir}")
    sim = SimulationContext(SimulationCfg(dt=0.01))
    sim.set_camera_view([2.5, 2.5, 2.5], [0.0, 0.0, 0.0])
    sim.reset()
    print("[INFO]: Setup complete...")
    dt, sim_time = sim.get_physics_dt(), 0.0
    with open(os.path.join(log_dir, "log.txt"), "w") as log_file:
        while simulation_app.is_running():
            log_file.write(f"{sim_time}\n")
            sim.step()
            sim_time += dt


if __name__ == "__main__":
    main()
    simulation_app.close()
