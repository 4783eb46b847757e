"""Record a motion clip (Isaac Lab's .npz motion format) from a trained humanoid policy.

    python scripts/tools/record_motion_clip.py --out humanoid_run_recorded.npz          # Humanoid-v0's shipped policy
    python scripts/tools/record_motion_clip.py --task simlab/Humanoid-Direct-v0 --checkpoint PATH --out my_clip.npz

The policy is played on the CPU (``--num_envs`` envs, mean actions); after ``--skip_seconds`` (the
start from rest) each env step's joint states and body poses and velocities are recorded, as the
env's articulation reads them (``joint_pos``, ``joint_vel``, ``body_pos_w`` less the env origin,
``body_quat_w``, ``body_lin_vel_w`` of the body frame origins, ``body_ang_vel_w``). The clip is the
first env that was not reset during the ``--seconds`` recorded. A clip made this way is a motion
the humanoid's own physics produced, so a policy of the same body can reproduce every feature of it
(AMP's discriminator can only tell the two apart by style, not by what the simulator cannot do).
The file stores the root's and the joints' states; the loader fills the body states by forward
kinematics, which gives them back within 2e-5 (``--body_states`` stores them too, as Isaac Lab does).

The humanoid tasks (``simlab/Humanoid-v0``, ``simlab/Humanoid-Direct-v0``) use the same
``humanoid.xml`` as the AMP humanoid (joint and body names match), and run towards +x.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import torch

from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.tasks.direct.humanoid_amp.motions.motion_file import write_motion_file


class ClipRecorder:
    """An ``on_step`` hook for :func:`simlab.cli.play.run_play`: the robot's state of every env step."""

    def __init__(self, skip_seconds: float, asset_name: str = "robot"):
        self.skip_seconds = skip_seconds
        self.asset_name = asset_name
        self.frames: dict[str, list[torch.Tensor]] = {}  # per motion-file array, one tensor per step
        self.episode_steps: list[torch.Tensor] = []
        self.step_dt = float("nan")
        self.dof_names: list[str] = []
        self.body_names: list[str] = []

    def __call__(self, env, obs, actions) -> None:
        robot = env.scene[self.asset_name]
        self.step_dt = float(env.step_dt)
        self.dof_names, self.body_names = list(robot.joint_names), list(robot.body_names)
        self.episode_steps.append(env.episode_length_buf.clone().cpu())
        if len(self.episode_steps) * self.step_dt <= self.skip_seconds:
            return
        data = robot.data
        origins = env.scene.env_origins[:, None, :]
        for key, value in (
            ("dof_positions", data.joint_pos),
            ("dof_velocities", data.joint_vel),
            ("body_positions", data.body_pos_w - origins),
            ("body_rotations", data.body_quat_w),
            ("body_linear_velocities", data.body_lin_vel_w),
            ("body_angular_velocities", data.body_ang_vel_w),
        ):
            self.frames.setdefault(key, []).append(value.clone().cpu())

    def clip(self) -> tuple[dict, int]:
        """The recorded motion of the first env that ran without a reset; (clip, env index)."""
        if not self.frames:
            raise RuntimeError("Nothing was recorded: play longer than --skip_seconds.")
        recorded = len(self.frames["dof_positions"])
        # an env's episode step grows by one every step unless it was reset
        steps = torch.stack(self.episode_steps[-recorded:])  # (frames, envs)
        unbroken = (steps[1:] == steps[:-1] + 1).all(dim=0)
        if not bool(unbroken.any()):
            raise RuntimeError(
                "Every env was reset while recording (a fall, or the episode's time limit): record fewer --seconds."
            )
        env = int(torch.nonzero(unbroken)[0])
        clip = {"fps": 1.0 / self.step_dt, "dof_names": self.dof_names, "body_names": self.body_names}
        clip.update({key: torch.stack(values)[:, env].numpy() for key, values in self.frames.items()})
        return clip, env


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--task", default="simlab/Humanoid-v0", help="A humanoid task with a trained policy.")
    parser.add_argument("--checkpoint", default=None, help="rsl_rl checkpoint (default: the task's pretrained one).")
    parser.add_argument("--out", required=True, help="The .npz motion file to write.")
    parser.add_argument("--num_envs", type=int, default=4)
    parser.add_argument("--skip_seconds", type=float, default=2.0, help="Start from rest: not recorded.")
    parser.add_argument("--seconds", type=float, default=6.0, help="Length of the clip.")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--log_root", default="logs", help="Where play copies the pretrained policy.")
    parser.add_argument(
        "--body_states", action="store_true", help="Store the body states too (5x the bytes; Isaac Lab's own form)."
    )
    args = parser.parse_args(argv)
    if not args.seconds > 0 or args.skip_seconds < 0:
        parser.error(f"--seconds must be > 0 and --skip_seconds >= 0, got {args.seconds} and {args.skip_seconds}")

    play_argv = ["play", "--task", args.task, "--library", "rsl_rl", "--headless", "--device", "cpu"]
    seconds = args.skip_seconds + args.seconds
    play_argv += ["--num_envs", str(args.num_envs), "--seed", str(args.seed), "--no_export", "--seconds", str(seconds)]
    play_argv += ["--log_root", args.log_root]
    play_argv += ["--checkpoint", args.checkpoint] if args.checkpoint else ["--use_pretrained_checkpoint"]
    recorder = ClipRecorder(args.skip_seconds)
    run_play(build_parser().parse_args(play_argv), [], on_step=recorder)

    try:
        clip, env = recorder.clip()
    except RuntimeError as e:  # the policy fell in every env: say so, no traceback
        parser.exit(2, f"{parser.prog}: error: {e}\n")
    write_motion_file(args.out, **clip, body_states=args.body_states)
    torso = clip["body_names"].index("torso")
    pos = clip["body_positions"][:, torso]
    duration = (len(pos) - 1) / clip["fps"]
    speed = (pos[-1, :2] - pos[0, :2]) / duration
    print(
        f"Wrote {args.out}: env {env}, {len(pos)} frames at {clip['fps']:.1f} fps ({duration:.2f} s); torso "
        f"velocity over the clip ({speed[0]:.3f}, {speed[1]:.3f}) m/s, height {np.mean(pos[:, 2]):.3f} m"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
