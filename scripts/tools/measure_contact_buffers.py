"""Measure how many contacts and constraint rows a task's worlds use on MuJoCo Warp, to size
``sim.mujoco.nconmax`` / ``njmax`` in its config.

    python scripts/tools/measure_contact_buffers.py --tasks simlab/Humanoid-AMP-Walk-Direct-v0
    python scripts/tools/measure_contact_buffers.py --tasks simlab/Lift-Cube-Franka-IK-Rel-v0 --device cuda:0 \
        --num_envs 1024

Each task runs ``--steps`` env steps of uniform random actions in [-1, 1] (episodes shortened to
``--episode_length_s`` so that the rollout crosses resets) with buffers ``--headroom`` times what
its config reserves, and reports the most contacts and rows any world had after a physics step,
what the config reserves, and the ratio; and the most iterations the constraint solver took in a
world (what ``sim.mujoco.iterations`` caps). ``--device cpu`` runs MuJoCo Warp's kernels on Warp's CPU
device (slow: keep ``--num_envs`` small). A world that diverged is reported: its counts mean nothing.
"""

from __future__ import annotations

import argparse
import sys
import time


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tasks", nargs="+", required=True, help="Gymnasium ids.")
    parser.add_argument("--device", default="cpu", help="cpu (Warp's CPU device) or cuda:N.")
    parser.add_argument("--num_envs", type=int, default=16)
    parser.add_argument("--steps", type=int, default=200, help="Env steps of random actions.")
    parser.add_argument("--episode_length_s", type=float, default=3.0, help="Episode length while measuring.")
    parser.add_argument("--headroom", type=int, default=4, help="Buffers while measuring, times the config's.")
    parser.add_argument("--margin", type=float, default=2.0, help="The config must reserve this times the peak.")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.contact_buffers import measure_task_buffers

    ok = True
    for task in args.tasks:
        start = time.perf_counter()
        peaks, diverged, reserved = measure_task_buffers(
            task, args.num_envs, args.steps, args.device, args.seed, args.headroom, args.episode_length_s
        )
        took = time.perf_counter() - start
        rows = [
            ("contacts per world", peaks.contacts_per_world, reserved["nconmax"], "nconmax"),
            ("constraint rows per world", peaks.constraint_rows, reserved["njmax"], "njmax"),
        ]
        print(f"{task}: {args.num_envs} envs x {args.steps} steps on {args.device} ({took:.0f} s), {diverged} diverged")
        for what, peak, size, setting in rows:
            ratio = size / peak if peak else float("inf")
            verdict = "ok" if ratio >= args.margin else f"TOO SMALL (< {args.margin}x)"
            print(f"  {what:26s} peak {peak:5d}   {setting} {size:5d}   {ratio:5.1f}x  {verdict}")
            ok &= ratio >= args.margin
        print(f"  contacts of all worlds per world (the pooled nconmax): peak {peaks.contacts_pooled}")
        print(
            f"  solver iterations in one world and physics step: peak {peaks.solver_iterations}"
            f" (sim.mujoco.iterations {reserved['iterations']})"
        )
        ok &= diverged == 0
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
