"""Teleoperate a manipulation task with a keyboard, gamepad or SpaceMouse.

Isaac Lab's ``environments/teleoperation/teleop_se3_agent.py`` with ``isaaclab`` imports replaced by
``simlab`` and task ids mapped (``Isaac-Lift-Cube-Franka-IK-Rel-v0`` ->
``simlab/Lift-Cube-Franka-IK-Rel-v0``). The keyboard's keys come from simlab's live viewer: type
them in MuJoCo's window (``--viewer native``) or hold the buttons of the web page's Teleop tab
(``--viewer web``). What simlab leaves out: Isaac Lab's XR hand tracking and IsaacTeleop stack.
What it adds: the reach task gets a device without the gripper term (its action has none), and
every 50 steps the script prints where the end effector is (for checking a run).

    python scripts/environments/teleoperation/teleop_se3_agent.py --task simlab/Reach-Franka-IK-Rel-v0 \\
        --teleop_device keyboard --device cpu --viewer web
"""

import argparse
from collections.abc import Callable

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Teleoperation for simlab environments.")
parser.add_argument("--num_envs", type=int, default=1, help="Number of environments to simulate.")
parser.add_argument(
    "--teleop_device",
    type=str,
    default="keyboard",
    help=(
        "Teleop device: keyboard, spacemouse or gamepad, or the name of a device under the env config's"
        " 'teleop_devices'."
    ),
)
parser.add_argument("--task", type=str, default=None, help="Name of the task.")
parser.add_argument("--sensitivity", type=float, default=1.0, help="Sensitivity factor.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()

app_launcher = AppLauncher(vars(args_cli))
simulation_app = app_launcher.app

import logging  # noqa: E402

import gymnasium as gym  # noqa: E402
import torch  # noqa: E402

import simlab.tasks  # noqa: E402, F401
from simlab.devices import (  # noqa: E402
    Se3Gamepad,
    Se3GamepadCfg,
    Se3Keyboard,
    Se3KeyboardCfg,
    Se3SpaceMouse,
    Se3SpaceMouseCfg,
)
from simlab.devices.teleop_device_factory import create_teleop_device  # noqa: E402
from simlab.envs import ManagerBasedRLEnvCfg  # noqa: E402
from simlab.managers import TerminationTermCfg as DoneTerm  # noqa: E402
from simlab.tasks.manager_based.manipulation.lift import mdp  # noqa: E402
from simlab.tasks.utils import parse_env_cfg  # noqa: E402

logger = logging.getLogger(__name__)


def main() -> None:
    """Make the env and the device, then step the env with the device's command until the app stops."""
    env_cfg = parse_env_cfg(args_cli.task, device=args_cli.device, num_envs=args_cli.num_envs)
    if not isinstance(env_cfg, ManagerBasedRLEnvCfg):
        raise ValueError(
            "Teleoperation is only supported for ManagerBasedRLEnv environments. "
            f"Received environment config type: {type(env_cfg).__name__}"
        )
    # no time limit; the lift goal is never resampled and reaching it ends the episode
    env_cfg.terminations.time_out = None
    if "Lift" in args_cli.task:
        env_cfg.commands.object_pose.resampling_time_range = (1.0e9, 1.0e9)
        env_cfg.terminations.object_reached_goal = DoneTerm(func=mdp.object_reached_goal)

    try:
        env = gym.make(args_cli.task, cfg=env_cfg).unwrapped
        if "Reach" in args_cli.task:
            logger.warning(
                f"The environment '{args_cli.task}' does not support gripper control. The device command will be"
                " ignored."
            )
    except Exception as e:
        logger.error(f"Failed to create environment: {e}")
        simulation_app.close()
        return

    should_reset_recording_instance = False
    teleoperation_active = True

    def reset_recording_instance() -> None:
        """Reset the env at the next step."""
        nonlocal should_reset_recording_instance
        should_reset_recording_instance = True
        print("Reset triggered - Environment will reset on next step")

    def start_teleoperation() -> None:
        nonlocal teleoperation_active
        teleoperation_active = True
        print("Teleoperation activated")

    def stop_teleoperation() -> None:
        nonlocal teleoperation_active
        teleoperation_active = False
        print("Teleoperation deactivated")

    teleoperation_callbacks: dict[str, Callable[[], None]] = {
        "R": reset_recording_instance,
        "START": start_teleoperation,
        "STOP": stop_teleoperation,
        "RESET": reset_recording_instance,
    }

    teleop_interface = None
    try:
        if hasattr(env_cfg, "teleop_devices") and args_cli.teleop_device in env_cfg.teleop_devices.devices:
            teleop_interface = create_teleop_device(
                args_cli.teleop_device, env_cfg.teleop_devices.devices, teleoperation_callbacks
            )
        else:
            logger.warning(
                f"No teleop device '{args_cli.teleop_device}' found in environment config. Creating default."
            )
            sensitivity = args_cli.sensitivity
            # the reach task's action has no gripper
            gripper = "Reach" not in args_cli.task
            if args_cli.teleop_device.lower() == "keyboard":
                teleop_interface = Se3Keyboard(
                    Se3KeyboardCfg(
                        pos_sensitivity=0.05 * sensitivity, rot_sensitivity=0.05 * sensitivity, gripper_term=gripper
                    )
                )
            elif args_cli.teleop_device.lower() == "spacemouse":
                teleop_interface = Se3SpaceMouse(
                    Se3SpaceMouseCfg(
                        pos_sensitivity=0.05 * sensitivity, rot_sensitivity=0.05 * sensitivity, gripper_term=gripper
                    )
                )
            elif args_cli.teleop_device.lower() == "gamepad":
                teleop_interface = Se3Gamepad(
                    Se3GamepadCfg(
                        pos_sensitivity=0.1 * sensitivity, rot_sensitivity=0.1 * sensitivity, gripper_term=gripper
                    )
                )
            else:
                logger.error(f"Unsupported teleop device: {args_cli.teleop_device}")
                logger.error("Supported: keyboard, spacemouse, gamepad, or a device in the env config.")
                env.close()
                simulation_app.close()
                return

            for key, callback in teleoperation_callbacks.items():
                try:
                    teleop_interface.add_callback(key, callback)
                except (ValueError, TypeError) as e:
                    logger.warning(f"Failed to add callback for key {key}: {e}")
    except Exception as e:
        logger.error(f"Failed to create teleop device: {e}")
        env.close()
        simulation_app.close()
        return

    if teleop_interface is None:
        logger.error("Failed to create teleop interface")
        env.close()
        simulation_app.close()
        return

    print(f"Using teleop device: {teleop_interface}")

    # the end effector the IK action moves (simlab's progress line)
    robot = env.scene["robot"]
    ee_body = robot.find_bodies(env_cfg.actions.arm_action.body_name)[0][0]

    env.reset()
    teleop_interface.reset()
    print("Teleoperation started. Press 'R' to reset the environment.")

    count = 0
    while simulation_app.is_running():
        try:
            with torch.inference_mode():
                action = teleop_interface.advance()
                if teleoperation_active:
                    actions = action.repeat(env.num_envs, 1)
                    env.step(actions)
                else:
                    env.sim.render()

                if should_reset_recording_instance:
                    env.reset()
                    teleop_interface.reset()
                    should_reset_recording_instance = False
                    print("Environment reset complete")

                count += 1
                if count % 50 == 0:
                    ee = robot.data.body_pos_w[0, ee_body] - env.scene.env_origins[0]
                    print(f"[INFO]: step {count}: end effector at {[round(v, 4) for v in ee.tolist()]}", flush=True)
        except Exception as e:
            logger.error(f"Error during simulation step: {e}")
            break

    env.close()
    print("Environment closed")


if __name__ == "__main__":
    main()
    simulation_app.close()
