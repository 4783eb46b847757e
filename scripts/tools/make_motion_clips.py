"""Write the AMP humanoid's walk, run and dance clips (Isaac Lab's .npz motion format).

    python scripts/tools/make_motion_clips.py                 # into the package's motions folder
    python scripts/tools/make_motion_clips.py --out my_clips --clips walk --fps 30

The clips come from the kinematic gait generator in
``simlab/tasks/direct/humanoid_amp/motions/kinematic_clips.py`` (joint-angle sinusoids, MuJoCo
forward kinematics, finite-difference velocities); the script prints each clip's cadence and the
forward speed that follows from it.
"""

from __future__ import annotations

import argparse

from simlab.tasks.direct.humanoid_amp.motions import MOTIONS_DIR
from simlab.tasks.direct.humanoid_amp.motions.kinematic_clips import CLIPS, write_clips


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=MOTIONS_DIR, help="Folder for humanoid_<clip>.npz (default: the package's).")
    parser.add_argument("--clips", nargs="+", default=list(CLIPS), choices=list(CLIPS), help="Clips to write.")
    parser.add_argument("--fps", type=float, default=60.0, help="Frames per second of the clips.")
    args = parser.parse_args()
    for name, stats in write_clips(args.out, args.clips, args.fps).items():
        print(
            f"humanoid_{name}.npz: {stats['duration_s']:.2f} s, cadence {stats['cadence_hz']:.3f} cycles/s, "
            f"forward speed {stats['forward_speed_m_s']:.3f} m/s, torso height {stats['mean_torso_height_m']:.3f} m"
        )
    print(f"Wrote {len(args.clips)} clips to {args.out}")


if __name__ == "__main__":
    main()
