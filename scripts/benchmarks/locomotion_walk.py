"""Does a quadruped learn to walk? Train a velocity task with rsl_rl, then play the policy and
measure it (issue 12, item 6).

    python scripts/benchmarks/locomotion_walk.py --device cuda --num_envs 4096 --max_iterations 300
    python scripts/benchmarks/locomotion_walk.py --device cuda --terrain rough --num_envs 4096 --train_seconds 360
    python scripts/benchmarks/locomotion_walk.py --device cuda --robot anymal_c --num_envs 4096
    python scripts/benchmarks/locomotion_walk.py --device cpu --num_envs 8 --max_iterations 2 --play_seconds 1

``--robot go2`` (``simlab/Velocity-*-Unitree-Go2-v0``) or ``anymal_c`` (``...-Anymal-C-v0``);
``--terrain flat`` or ``rough``.

Flat: each command (forward 0.5 and 1.0 m/s, sideways 0.5 m/s, turning 1 rad/s) is played for
``--play_seconds`` on ``--play_envs`` envs of the task's play config (no observation noise, no
pushes). Reported per command, averaged over envs and over the steps after the first
``--settle_seconds`` (the policy starts each play from a standstill):

* planar velocity error: ``|v_xy command - v_xy|`` in the base frame [m/s] (target <= 0.2)
* yaw-rate error: ``|w_z command - w_z|`` [rad/s] (target <= 0.3)
* fall fraction: envs whose episode ended in a termination (base contact) (target < 2 %)

Rough: training prints the curriculum's mean terrain level (the mean row of all envs, what the
env logs as ``Curriculum/terrain_levels``) every ``--curve_every`` iterations. Then the policy
plays on the stairs tiles of the same (seeded) terrain: ``--stairs_envs`` envs on each stairs
column (pyramid stairs: start on the top platform and walk down; inverted stairs: start in the pit
and climb out) of each row in ``--stairs_rows``, commanded ``--stairs_speed`` m/s straight ahead
(each env faces a random direction) for ``--stairs_seconds``. An env *crosses* when its base
gets past the last step (farther than ``size / 2 - border_width`` from the tile's centre along x
or y) before any fall; reported per kind and row: the step height, the fraction that crosses, the
mean height change of the base from the start to the crossing point, and the falls.

With ``--video PATH`` the first play is rendered to an mp4 (flat: env 0 of the first command; rough:
an env climbing out of the lowest row's inverted stairs). ``--checkpoint PATH`` skips
training and measures a saved policy (e.g. the ``model_final.pt`` of an earlier run, whose curve is
in that run's output): ``--device cpu`` plays a GPU-trained policy on MuJoCo C.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import gymnasium as gym
import torch
from rsl_rl.runners import OnPolicyRunner

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.rl.rsl_rl import RslRlVecEnvWrapper
from simlab.rl.utils import require
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry, parse_env_cfg
from simlab.terrains import MeshPyramidStairsTerrainCfg

ROBOTS = {"go2": "Unitree-Go2", "anymal_c": "Anymal-C"}
COMMANDS = {
    "forward 0.5 m/s": (0.5, 0.0, 0.0),
    "forward 1.0 m/s": (1.0, 0.0, 0.0),
    "sideways 0.5 m/s": (0.0, 0.5, 0.0),
    "turning 1 rad/s": (0.0, 0.0, 1.0),
}


def task_id(args: argparse.Namespace, play: bool = False) -> str:
    return f"simlab/Velocity-{args.terrain.capitalize()}-{ROBOTS[args.robot]}{'-Play' if play else ''}-v0"


def seed_terrain(cfg, seed: int) -> None:
    """Train and play on the very same generated terrain (the generator caches it by config)."""
    generator = cfg.scene.terrain.terrain_generator
    if generator is not None:
        generator.seed = seed


def mean_terrain_level(env: RslRlVecEnvWrapper) -> float:
    return float(env.unwrapped.scene.terrain.terrain_levels.float().mean())


def make_runner(args: argparse.Namespace, num_envs: int, log_dir: str | None):
    """The task's env (seeded terrain) and an rsl_rl runner of its agent config; (env, runner, agent cfg)."""
    task = task_id(args)
    env_cfg = parse_env_cfg(task, device=args.device, num_envs=num_envs)
    env_cfg.seed = args.seed
    seed_terrain(env_cfg, args.seed)
    agent_cfg = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    agent_cfg.seed = args.seed
    agent_cfg.device = args.device
    if args.max_iterations is not None:
        agent_cfg.max_iterations = args.max_iterations
    env = RslRlVecEnvWrapper(gym.make(task, cfg=env_cfg), clip_actions=agent_cfg.clip_actions)
    runner = OnPolicyRunner(env, agent_cfg.to_rsl_rl_dict(), log_dir=log_dir, device=args.device)
    return env, runner, agent_cfg


def train(args: argparse.Namespace) -> tuple[OnPolicyRunner, float, list[tuple[int, float, float]]]:
    """Train; returns the runner, the training wall time and, on rough terrain, the curriculum's
    curve as (iteration, seconds, mean terrain level) rows."""
    log_dir = os.path.join(args.log_root, "locomotion_walk", time.strftime("%Y-%m-%d_%H-%M-%S"))
    env, runner, agent_cfg = make_runner(args, args.num_envs, log_dir)
    rough = args.terrain == "rough"
    curve: list[tuple[int, float, float]] = []
    if rough:
        curve.append((0, 0.0, mean_terrain_level(env)))
    # in chunks of --curve_every iterations (one chunk on flat ground), up to --train_seconds
    chunk = args.curve_every if rough else agent_cfg.max_iterations
    done = 0
    start = time.time()
    while done < agent_cfg.max_iterations:
        n = min(chunk, agent_cfg.max_iterations - done)
        runner.learn(num_learning_iterations=n, init_at_random_ep_len=done == 0)
        done += n
        # rsl_rl leaves its counter at the last iteration it ran; the next chunk would repeat that index
        runner.current_learning_iteration = done
        elapsed = time.time() - start
        if rough:
            curve.append((done, elapsed, mean_terrain_level(env)))
            print(f"[curriculum] iteration {done}: mean terrain level {curve[-1][2]:.3f} ({elapsed:.0f} s)", flush=True)
        if args.train_seconds is not None and elapsed >= args.train_seconds:
            print(f"training stopped by --train_seconds {args.train_seconds} after {done} iterations")
            break
    wall = time.time() - start
    runner.save(os.path.join(log_dir, "model_final.pt"))
    print(f"trained {done} iterations on {args.num_envs} envs in {wall:.1f} s; {log_dir}")
    env.close()
    return runner, wall, curve


def load_policy(args: argparse.Namespace):
    """The inference policy of ``--checkpoint`` (an rsl_rl checkpoint of the task's agent)."""
    env, runner, _ = make_runner(args, 1, log_dir=None)
    runner.load(args.checkpoint, map_location=args.device)
    policy = runner.get_inference_policy(device=args.device)
    env.close()
    return policy


def play_cfg(task: str, args: argparse.Namespace, num_envs: int, command: tuple[float, float, float], seconds: float):
    """The task's config for measuring: fixed ``command`` (vx, vy, wz) from a standstill, no time-outs."""
    cfg = parse_env_cfg(task, device=args.device, num_envs=num_envs)
    cfg.seed = args.seed
    seed_terrain(cfg, args.seed)
    vel = cfg.commands.base_velocity
    vel.heading_command = False
    vel.rel_standing_envs = 0.0
    vel.resampling_time_range = (1.0e9, 1.0e9)
    vel.ranges.lin_vel_x = (command[0], command[0])
    vel.ranges.lin_vel_y = (command[1], command[1])
    vel.ranges.ang_vel_z = (command[2], command[2])
    cfg.episode_length_s = seconds + 1.0  # no time-outs inside the measured window
    cfg.viewer.origin_type, cfg.viewer.asset_name = "asset_root", "robot"  # the video follows env 0
    cfg.viewer.eye, cfg.viewer.lookat = (1.2, -1.2, 0.6), (0.0, 0.0, 0.0)
    return cfg


def save_video(frames: list, path: str, step_dt: float) -> None:
    import imageio

    imageio.mimsave(path, frames, fps=round(1.0 / step_dt), format="FFMPEG")
    print(f"video: {path}")


def play_command(policy, args: argparse.Namespace, command: tuple[float, float, float], video: str | None) -> dict:
    """Play ``command`` on fresh envs; the mean errors after the settling time and the falls."""
    cfg = play_cfg(task_id(args, play=True), args, args.play_envs, command, args.play_seconds)
    env = RslRlVecEnvWrapper(gym.make(task_id(args, play=True), cfg=cfg, render_mode="rgb_array" if video else None))
    base = env.unwrapped
    robot = base.scene["robot"]
    target = torch.tensor(command, device=base.device)
    steps = round(args.play_seconds / base.step_dt)
    settle = round(args.settle_seconds / base.step_dt)
    fallen = torch.zeros(base.num_envs, dtype=torch.bool, device=base.device)
    vel_error = torch.zeros((), device=base.device)
    yaw_error = torch.zeros((), device=base.device)
    frames = []
    obs = env.get_observations()
    with torch.inference_mode():
        for step in range(steps):
            obs, _, dones, extras = env.step(policy(obs))
            fallen |= (dones > 0) & ~extras["time_outs"].bool()
            if step >= settle:
                vel_error += torch.linalg.norm(robot.data.root_lin_vel_b[:, :2] - target[:2], dim=1).mean()
                yaw_error += (robot.data.root_ang_vel_b[:, 2] - target[2]).abs().mean()
            if video:
                frames.append(base.render())
    measured = steps - settle
    if video:
        save_video(frames, video, base.step_dt)
    env.close()
    return {
        "vel_error": float(vel_error) / measured,
        "yaw_error": float(yaw_error) / measured,
        "fall_fraction": float(fallen.float().mean()),
    }


def stairs_tiles(generator, rows: list[int]) -> list:
    """The tiles of the stairs columns (pyramid and inverted) in ``rows``, by row then column."""
    stairs = [
        t
        for t in generator.tiles
        if t.row in rows and isinstance(generator.cfg.sub_terrains[t.kind], MeshPyramidStairsTerrainCfg)
    ]
    if not stairs:
        raise ValueError(f"the terrain has no stairs tiles in rows {rows} (it has {generator.cfg.num_rows} rows)")
    return sorted(stairs, key=lambda t: (t.row, t.col))


def play_stairs(policy, args: argparse.Namespace, video: str | None) -> list[dict]:
    """Play on the stairs tiles of ``--stairs_rows`` (training's terrain, without the curriculum);
    one result per (kind, row)."""
    task = task_id(args)  # the training config: its terrain keeps the difficulty rows
    # the stairs tiles are only known once the terrain is generated: count them on a generator of
    # the same (seeded, cached) config
    from simlab.terrains.terrain_generator import generate_terrain

    probe = play_cfg(task, args, 1, (args.stairs_speed, 0.0, 0.0), args.stairs_seconds)
    tiles = stairs_tiles(generate_terrain(probe.scene.terrain.terrain_generator), args.stairs_rows)
    per_tile = args.stairs_envs
    cfg = play_cfg(task, args, len(tiles) * per_tile, (args.stairs_speed, 0.0, 0.0), args.stairs_seconds)
    cfg.curriculum.terrain_levels = None  # stay on the chosen tiles (the rows keep their difficulty)
    cfg.observations.policy.enable_corruption = False
    cfg.events.push_robot = None
    cfg.events.base_external_force_torque = None
    # the video follows the first env that climbs out of a pit (the lowest row's inverted stairs),
    # from high enough that the steps around it stay below the camera
    climbing = [i for i, t in enumerate(tiles) if t.kind == "pyramid_stairs_inv"]
    cfg.viewer.env_index = min(climbing, key=lambda i: tiles[i].row) * per_tile if climbing else 0
    cfg.viewer.eye = (1.6, -1.6, 1.4)
    env = RslRlVecEnvWrapper(gym.make(task, cfg=cfg, render_mode="rgb_array" if video else None))
    base = env.unwrapped
    terrain, robot = base.scene.terrain, base.scene["robot"]
    device = base.device
    # put env i on tile i // per_tile, then start every env there
    rows = torch.tensor([t.row for t in tiles for _ in range(per_tile)], device=device)
    cols = torch.tensor([t.col for t in tiles for _ in range(per_tile)], device=device)
    terrain.terrain_levels.copy_(rows)
    terrain.terrain_types.copy_(cols)
    terrain.env_origins.copy_(terrain.terrain_origins[rows, cols])
    obs, _ = env.reset()
    centre = terrain.env_origins[:, :2].clone()  # a stairs tile's origin is its centre
    # the last step ends border_width inside the tile's edge (the generator's tile size, not the sub-config's)
    generator_cfg = terrain.terrain_generator.cfg
    half = min(generator_cfg.size) / 2
    edge = [half - generator_cfg.sub_terrains[t.kind].border_width for t in tiles for _ in range(per_tile)]
    edge = torch.tensor(edge, device=device)
    start_z = robot.data.root_pos_w[:, 2].clone()
    crossed = torch.zeros(base.num_envs, dtype=torch.bool, device=device)
    fallen = torch.zeros_like(crossed)
    height_change = torch.zeros(base.num_envs, device=device)
    frames = []
    with torch.inference_mode():
        for _ in range(round(args.stairs_seconds / base.step_dt)):
            obs, _, dones, extras = env.step(policy(obs))
            fallen |= (dones > 0) & ~extras["time_outs"].bool() & ~crossed
            # the robot's position before a reset would be lost: a fallen env has already failed
            out = (robot.data.root_pos_w[:, :2] - centre).abs().amax(dim=1) > edge
            newly = out & ~crossed & ~fallen
            height_change = torch.where(newly, robot.data.root_pos_w[:, 2] - start_z, height_change)
            crossed |= newly
            if video:
                frames.append(base.render())
    if video:
        save_video(frames, video, base.step_dt)
    env.close()
    groups: dict[tuple[str, int], list[int]] = {}  # (kind, row) -> the tiles' indices
    for i, t in enumerate(tiles):
        groups.setdefault((t.kind, t.row), []).append(i)
    results = []
    for (kind, row), tile_ids in sorted(groups.items()):
        sel = torch.tensor([i * per_tile + k for i in tile_ids for k in range(per_tile)], device=device)
        low, high = terrain.terrain_generator.cfg.sub_terrains[kind].step_height_range
        n_crossed = int(crossed[sel].sum())
        results.append(
            {
                "kind": kind,
                "row": row,
                "envs": len(sel),
                "step_height": sum(low + (high - low) * tiles[i].difficulty for i in tile_ids) / len(tile_ids),
                "crossed": n_crossed / len(sel),
                "height_change": float(height_change[sel][crossed[sel]].mean()) if n_crossed else float("nan"),
                "falls": float(fallen[sel].float().mean()),
            }
        )
    return results


def report_flat(args: argparse.Namespace, policy, wall: float) -> bool:
    rows = []
    for i, (name, command) in enumerate(COMMANDS.items()):
        rows.append((name, play_command(policy, args, command, args.video if i == 0 else None)))
    print(f"\n{task_id(args)}: {args.num_envs} envs, training wall time {wall:.1f} s on {args.device}")
    print(f"play: {args.play_envs} envs x {args.play_seconds} s per command, errors after {args.settle_seconds} s")
    print(f"{'command':<18} {'|v_xy err| [m/s]':>16} {'|w_z err| [rad/s]':>17} {'falls':>7}")
    ok = True
    for name, r in rows:
        print(f"{name:<18} {r['vel_error']:>16.3f} {r['yaw_error']:>17.3f} {r['fall_fraction']:>7.1%}")
        ok &= r["vel_error"] <= 0.2 and r["yaw_error"] <= 0.3 and r["fall_fraction"] < 0.02
    mean_vel = sum(r["vel_error"] for _, r in rows) / len(rows)
    mean_yaw = sum(r["yaw_error"] for _, r in rows) / len(rows)
    falls = sum(r["fall_fraction"] for _, r in rows) / len(rows)
    print(f"{'mean':<18} {mean_vel:>16.3f} {mean_yaw:>17.3f} {falls:>7.1%}")
    print(f"criterion (<= 0.2 m/s, <= 0.3 rad/s, < 2 % falls, each command): {'PASS' if ok else 'FAIL'}")
    return ok


def report_rough(args: argparse.Namespace, policy, wall: float, curve: list[tuple[int, float, float]]) -> bool:
    results = play_stairs(policy, args, args.video)
    print(f"\n{task_id(args)}: {args.num_envs} envs, training wall time {wall:.1f} s on {args.device}")
    if not curve:  # --checkpoint: the curve is in the training run's output
        print(f"played {args.checkpoint}; its training curve is in that run's output")
    else:
        print("curriculum (mean terrain level of all envs):")
        print(f"{'iteration':>9} {'seconds':>8} {'mean level':>10}")
    for iteration, seconds, level in curve:
        print(f"{iteration:>9d} {seconds:>8.0f} {level:>10.3f}")
    print(f"\nstairs: {args.stairs_envs} envs per tile, {args.stairs_speed} m/s ahead for {args.stairs_seconds} s")
    print(f"{'kind':<20} {'row':>3} {'envs':>5} {'step [m]':>8} {'crossed':>8} {'dz at edge [m]':>14} {'falls':>6}")
    for r in results:
        print(
            f"{r['kind']:<20} {r['row']:>3d} {r['envs']:>5d} {r['step_height']:>8.3f} {r['crossed']:>8.1%}"
            f" {r['height_change']:>14.2f} {r['falls']:>6.1%}"
        )
    rose = curve[-1][2] - curve[0][2] if curve else float("nan")
    climbed = [r for r in results if r["kind"] == "pyramid_stairs_inv"]
    climb_fraction = sum(r["crossed"] * r["envs"] for r in climbed) / max(1, sum(r["envs"] for r in climbed))
    print(f"mean terrain level rose by {rose:.2f}; {climb_fraction:.1%} of the envs climbed out of the inverted stairs")
    climbs = ">= 50 % climb out of the inverted stairs"
    if curve:
        ok, what = rose >= 1.0 and climb_fraction >= 0.5, f"level rises by >= 1 row, {climbs}"
    else:  # --checkpoint: the level's rise is judged from the training run's output
        ok, what = climb_fraction >= 0.5, f"{climbs}; the level's rise: see training"
    print(f"criterion ({what}): {'PASS' if ok else 'FAIL'}")
    return ok


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robot", choices=sorted(ROBOTS), default="go2")
    parser.add_argument("--terrain", choices=("flat", "rough"), default="flat")
    parser.add_argument("--num_envs", type=int, default=4096)
    parser.add_argument("--max_iterations", type=int, default=None, help="Default: the agent config's.")
    parser.add_argument("--train_seconds", type=float, default=None, help="Stop training after this wall time.")
    parser.add_argument("--device", default="cuda" if torch.cuda.is_available() else "cpu")
    parser.add_argument("--seed", type=int, default=42)
    parser.add_argument("--play_envs", type=int, default=64)
    parser.add_argument("--play_seconds", type=float, default=20.0)
    parser.add_argument("--settle_seconds", type=float, default=1.0)
    parser.add_argument("--curve_every", type=int, default=50, help="Rough: iterations between curve points.")
    parser.add_argument("--stairs_rows", type=int, nargs="+", default=[3, 5, 7, 9], help="Rough: rows played.")
    parser.add_argument("--stairs_envs", type=int, default=8, help="Rough: envs per stairs tile.")
    parser.add_argument("--stairs_speed", type=float, default=1.0)
    parser.add_argument("--stairs_seconds", type=float, default=10.0)
    parser.add_argument("--log_root", default="logs")
    parser.add_argument("--video", default=None, help="Write the first play (env 0) to this mp4.")
    parser.add_argument("--checkpoint", default=None, help="Measure this rsl_rl checkpoint instead of training.")
    args = parser.parse_args()
    if args.video:
        require("imageio_ffmpeg")  # before any training: imageio would write an .mp4 path as TIFF without it
    if args.checkpoint and not os.path.isfile(args.checkpoint):
        parser.error(f"--checkpoint {args.checkpoint}: no such file")
    if args.terrain == "flat" and args.play_seconds <= args.settle_seconds:
        parser.error(f"--play_seconds ({args.play_seconds}) must exceed --settle_seconds ({args.settle_seconds})")

    if args.checkpoint:
        policy, wall, curve = load_policy(args), float("nan"), []
    else:
        runner, wall, curve = train(args)
        policy = runner.get_inference_policy(device=args.device)
    ok = report_rough(args, policy, wall, curve) if args.terrain == "rough" else report_flat(args, policy, wall)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
