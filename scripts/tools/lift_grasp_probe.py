"""What the lift task pays a scripted grasp, and how hard the closed gripper holds the cube.

Runs Isaac Lab's pick-and-lift state machine (``scripts/environments/state_machine/lift_cube_sm.py``,
task ``simlab/Lift-Cube-Franka-IK-Abs-v0``, whose rewards are the lift task's) on the CPU, then prints

* the lift rewards per step (weighted, as the reward manager sums them) at a few steps, averaged over
  all envs and over the envs whose cube is within 5 cm of its goal;
* for the env holding its cube highest at the end: the force on the cube, ramped up at 25 N/s along
  the hand's x (along the pads), -z (down) and y (the grasp axis), at which the cube has moved 3 mm in
  the hand (each from the same state, MuJoCo C on one world copied from the batch, joint targets held).

    python scripts/tools/lift_grasp_probe.py --num_envs 16 --seed 0 --steps 240
"""

from __future__ import annotations

import argparse
import runpy
import sys
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np
import torch

SM_SCRIPT = Path(__file__).resolve().parents[1] / "environments" / "state_machine" / "lift_cube_sm.py"


def run_state_machine(num_envs: int, seed: int, steps: int) -> tuple[object, list[tuple[torch.Tensor, torch.Tensor]]]:
    """Run the state machine script; return its env and, per env step, (weighted rewards, cube-goal distance)."""
    made, rows = {}, []
    make = gym.make

    def make_and_watch(*args, **kwargs):
        env = make(*args, **kwargs)
        unwrapped, step = env.unwrapped, env.step

        def watched_step(action):
            out = step(action)
            cube = unwrapped.scene["object"].data.root_pos_w - unwrapped.scene.env_origins
            goal = unwrapped.command_manager.get_command("object_pose")[:, :3]
            rows.append((unwrapped.reward_manager._step_reward.clone(), torch.linalg.norm(cube - goal, dim=1)))
            return out

        env.step = watched_step
        made["env"] = env
        return env

    gym.make = make_and_watch
    argv = sys.argv
    sys.argv = [str(SM_SCRIPT), "--num_envs", str(num_envs), "--headless", "--device", "cpu"]
    sys.argv += ["--seed", str(seed), "--max_app_steps", str(steps)]
    try:
        runpy.run_path(str(SM_SCRIPT), run_name="__main__")
    finally:
        sys.argv, gym.make = argv, make
    return made["env"].unwrapped, rows


def _cube_in_hand(data: mujoco.MjData, cube: int, hand: int) -> np.ndarray:
    return data.xmat[hand].reshape(3, 3).T @ (data.xpos[cube] - data.xpos[hand])


def holding_forces(env, env_id: int, rate_n_per_s: float = 25.0, slip_m: float = 0.003) -> dict[str, float | None]:
    """Force on the cube [N] at which it has moved ``slip_m`` in the hand, per direction."""
    model, physics = env.sim.model, env.sim.physics
    cube = next(i for i in range(model.nbody) if model.body(i).name.endswith("Object"))
    hand = next(i for i in range(model.nbody) if model.body(i).name.endswith("panda_hand"))
    directions = {"along the pads (hand x)": (0, 1.0), "down (hand -z)": (2, -1.0), "grasp axis (hand y)": (1, 1.0)}
    found = {}
    for name, (axis, sign) in directions.items():
        data = mujoco.MjData(model)
        for field in ("qpos", "qvel", "ctrl"):
            getattr(data, field)[:] = physics.data(field)[env_id].numpy()
        mujoco.mj_forward(model, data)
        start, found[name] = _cube_in_hand(data, cube, hand), None
        for k in range(int(40.0 / (rate_n_per_s * model.opt.timestep))):  # up to 40 N
            force = rate_n_per_s * model.opt.timestep * k
            data.xfrc_applied[cube, :3] = data.xmat[hand].reshape(3, 3)[:, axis] * sign * force
            mujoco.mj_step(model, data)
            if np.linalg.norm(_cube_in_hand(data, cube, hand) - start) > slip_m:
                found[name] = force
                break
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--num_envs", type=int, default=16)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--steps", type=int, default=240, help="State machine steps (one 5 s episode is 250).")
    args = parser.parse_args()
    env, rows = run_state_machine(args.num_envs, args.seed, args.steps)
    names = [name for name, _ in env.reward_manager._terms]
    np.set_printoptions(precision=3, suppress=True)
    print(f"\nlift rewards per step (weighted): {names}")
    for step in sorted({10, 60, 95, 150, 200, args.steps} & set(range(1, len(rows) + 1))):
        reward, distance = rows[step - 1]
        at_goal = distance < 0.05
        text = reward[at_goal].mean(0).numpy() if at_goal.any() else "-"
        print(f"step {step}: all envs {reward.mean(0).numpy()}; {int(at_goal.sum())} envs at the goal {text}")
    cube_z = env.scene["object"].data.root_pos_w[:, 2] - env.scene.env_origins[:, 2]
    holder = int(torch.argmax(cube_z))
    print(f"\nenv {holder} holds its cube at z = {float(cube_z[holder]):.3f} m; cube weight {0.1 * 9.81:.2f} N")
    for name, force in holding_forces(env, holder).items():
        print(f"  force {name} that moves the cube 3 mm in the hand: {force if force is None else round(force, 2)} N")


if __name__ == "__main__":
    main()
