"""How a rough-task humanoid stands at its default pose on each backend: contacts per sole, base height,
tilt, falls and foot slip, on the rough terrain and on a plane (issue 39).

Zero actions hold the default pose under the task's PD drives. Both engines run on the CPU (MuJoCo
Warp on Warp's CPU device), so the numbers compare the collision pipelines, not the hardware::

    .venv/bin/python scripts/benchmarks/humanoid_stance.py --robot G1 --envs 32 --seconds 3 --seeds 0 1
"""

from __future__ import annotations

import argparse

import mujoco
import numpy as np
import torch


def _sole_geoms(model: mujoco.MjModel, foot_bodies: list[int]) -> list[np.ndarray]:
    return [np.flatnonzero(model.geom_bodyid == body) for body in foot_bodies]


def _contacts_per_sole(env, soles: list[np.ndarray]) -> np.ndarray:
    """(worlds, soles) contacts of each sole with anything, as the engine's collision made them."""
    physics, model = env.sim.physics, env.sim.model
    sole_of_geom = np.full(model.ngeom, -1)
    for i, geoms in enumerate(soles):
        sole_of_geom[geoms] = i
    counts = np.zeros((env.num_envs, len(soles)), dtype=int)
    if hasattr(physics, "wp_data"):  # MuJoCo Warp: its contact buffer
        data = physics.wp_data
        n = int(data.nacon.numpy()[0])
        geom = data.contact.geom.numpy()[:n]
        world = data.contact.worldid.numpy()[:n]
        dist = data.contact.dist.numpy()[:n]
        for g, w, d in zip(geom, world, dist, strict=True):
            sole = max(sole_of_geom[g[0]], sole_of_geom[g[1]])
            if sole >= 0 and d < 0.0:
                counts[w, sole] += 1
        return counts
    # MuJoCo C: each world's state through one MjData, its collision run by mj_forward
    robot = env.scene["robot"]
    data = mujoco.MjData(model)
    root = robot.data.root_state_w[:, :7].cpu().numpy()
    joints = robot.data.joint_pos.cpu().numpy()
    adr = model.jnt_qposadr[
        [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"Robot/{n}") for n in robot.joint_names]
    ]
    free = model.jnt_qposadr[np.flatnonzero(model.jnt_type == mujoco.mjtJoint.mjJNT_FREE)[0]]
    for w in range(env.num_envs):
        data.qpos[free : free + 7] = root[w] - np.r_[env.scene.env_origins[w].cpu().numpy(), np.zeros(4)]
        data.qpos[adr] = joints[w]
        mujoco.mj_forward(model, data)
        for c in data.contact[: data.ncon]:
            sole = max(sole_of_geom[c.geom1], sole_of_geom[c.geom2])
            if sole >= 0 and c.dist < 0.0:
                counts[w, sole] += 1
    return counts


def stance(
    task: str,
    engine: str,
    ground: str,
    envs: int,
    seconds: float,
    seed: int,
    gains: str = "task",
    device: str = "cpu",
) -> dict[str, float]:
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.manager_based.locomotion.velocity.config.common import flat_ground
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    cfg = parse_env_cfg(task, device=device, num_envs=envs)
    cfg.sim.engine, cfg.sim.use_cuda_graph, cfg.seed = engine, False, seed
    if ground == "plane":
        flat_ground(cfg)
    if gains == "stiff":  # every drive kp 1000 / kd 30, as tests/test_humanoid_robots.py stands the robots
        robot = cfg.scene.robot
        robot.actuators = {
            name: group.replace(stiffness=1000.0, damping=30.0) for name, group in robot.actuators.items()
        }
        for group in robot.actuators.values():
            group.effort_limit_sim = None
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        env.reset()
        robot, sensor = env.scene["robot"], env.scene["contact_forces"]
        feet = robot.find_bodies(".*_ankle_roll_link|.*_ankle_link")[0]
        sensor_feet = sensor.find_bodies(".*_ankle_roll_link|.*_ankle_link")[0]
        model = env.sim.model
        names = [robot.body_names[i] for i in feet]
        soles = _sole_geoms(model, [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"Robot/{n}") for n in names])
        actions = torch.zeros(env.num_envs, env.action_manager.total_action_dim, device=env.device)
        steps = round(seconds / env.step_dt)
        falls, slip, slip_n, height, tilt, contacts = 0, 0.0, 0, [], [], []
        first_fall = seconds
        for step in range(steps):
            _, _, terminated, _, _ = env.step(actions)
            falls += int(terminated.sum())
            if falls and first_fall == seconds:
                first_fall = (step + 1) * env.step_dt
            in_contact = sensor.data.net_forces_w[:, sensor_feet].norm(dim=-1) > 1.0
            speed = robot.data.body_lin_vel_w[:, feet, :2].norm(dim=-1)
            slip += float(speed[in_contact].sum())
            slip_n += int(in_contact.sum())
            if step >= steps // 2:  # the settled half
                feet_z = robot.data.body_pos_w[:, feet, 2].mean(-1)
                height.append(robot.data.root_pos_w[:, 2] - feet_z)
                gravity = robot.data.projected_gravity_b
                tilt.append(torch.rad2deg(torch.acos((-gravity[:, 2]).clamp(-1, 1))))
                if (steps - 1 - step) % 10 == 0:
                    contacts.append(_contacts_per_sole(env, soles))
        contacts = np.stack(contacts)
        touching = contacts[contacts > 0]  # soles on the ground (a stepping or fallen robot lifts some)
        return {
            "contacts_per_touching_sole": float(touching.mean()),
            "touching_soles_below_3": float((touching < 3).mean()),
            "soles_in_air": float((contacts == 0).mean()),
            "base_over_feet_m": float(torch.stack(height).mean()),
            "tilt_deg": float(torch.stack(tilt).mean()),
            "tilt_deg_max": float(torch.stack(tilt).max()),
            "falls": falls,
            "first_fall_s": first_fall,
            "foot_slip_mps": slip / max(slip_n, 1),
        }
    finally:
        env.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="G1", choices=["G1", "H1"])
    parser.add_argument("--envs", type=int, default=32)
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--device", default="cpu", help="cuda:0 runs MuJoCo Warp on the GPU (--engines mujoco_warp)")
    parser.add_argument("--engines", nargs="+", default=["mujoco", "mujoco_warp"])
    parser.add_argument("--grounds", nargs="+", default=["rough", "plane"])
    parser.add_argument("--gains", default="task", choices=["task", "stiff"], help="stiff: kp 1000, kd 30")
    args = parser.parse_args()
    task = f"simlab/Velocity-Rough-{args.robot}-v0"
    for ground in args.grounds:
        for engine in args.engines:
            for seed in args.seeds:
                row = stance(task, engine, ground, args.envs, args.seconds, seed, args.gains, args.device)
                print(ground, engine, seed, " ".join(f"{k}={v:.3g}" for k, v in row.items()), flush=True)


if __name__ == "__main__":
    main()
