"""Convert a retargeted CSV (root position xyz, root quaternion xyzw, joint angles per row) into the
tracking tasks' motion clip, as mjlab's and BeyondMimic's ``csv_to_npz.py`` do (their flags are taken
with dashes or underscores):

    python scripts/tools/csv_to_npz.py --input_file dance.csv --input_fps 30 --output_name dance.npz
    simlab train --task simlab/Tracking-Flat-G1-v0 --headless env.commands.motion.motion_file=dance.npz

The robot defaults to the 29-DoF G1 (``unitree_g1_29dof.xml``; ``--robot_mjcf`` for another) and the
output rate to the tracking env's 50 fps. An existing output file is kept unless ``--force`` is given.
The layout and checks: docs/humanoids.md, "From retargeted CSV".
"""

from __future__ import annotations

import argparse
import os
import sys

from simlab.robots.unitree import ASSETS_DIR
from simlab.tasks.manager_based.tracking.motion_clip import clip_from_csv
from simlab.utils.errors import ConfigError, is_intended_error
from simlab.utils.io import atomic_path

G1_29DOF_MJCF = os.path.join(ASSETS_DIR, "unitree_g1_29dof.xml")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--input_file", "--input-file", required=True, help="The retargeted CSV.")
    parser.add_argument("--input_fps", "--input-fps", type=float, default=30.0, help="The CSV's frame rate.")
    parser.add_argument("--output_name", "--output-name", required=True, help="The clip to write (.npz).")
    parser.add_argument("--output_fps", "--output-fps", type=float, default=50.0, help="The clip's frame rate.")
    parser.add_argument("--robot_mjcf", default=G1_29DOF_MJCF, help="The robot's MJCF (default: the 29-DoF G1).")
    parser.add_argument("--force", action="store_true", help="Replace an existing output file.")
    return parser


def main(argv: list[str] | None = None) -> str:
    args = build_parser().parse_args(argv)
    output = args.output_name if args.output_name.endswith(".npz") else f"{args.output_name}.npz"
    if not os.path.isfile(args.input_file):
        raise ConfigError(f"--input_file {args.input_file}: no such file (a retargeted CSV).")
    if os.path.exists(output) and not args.force:
        raise ConfigError(f"--output_name {output} exists; pass --force to replace it, or another name.")
    clip = clip_from_csv(args.input_file, args.robot_mjcf, input_fps=args.input_fps, output_fps=args.output_fps)
    with atomic_path(output, suffix=".npz") as tmp:  # a failed write keeps what was there
        clip.save(tmp)
    print(f"[simlab] {output}: {clip.num_frames} frames at {clip.fps:g} fps ({clip.duration:.2f} s)")
    return output


if __name__ == "__main__":
    try:
        main()
    except Exception as error:  # bad input in one line, as the simlab command prints it
        if not is_intended_error(error):
            raise
        print(f"csv_to_npz.py: error: {error}", file=sys.stderr)
        sys.exit(2)
