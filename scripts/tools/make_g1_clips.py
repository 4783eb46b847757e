"""Make the G1 tracking clips shipped with simlab (``simlab/tasks/manager_based/tracking/config/g1/motions``).

Each clip is written here as joint-angle curves of the 29-DoF G1; the pelvis is then placed, frame by
frame, so that both soles rest flat on the ground where they started (forward kinematics of the MJCF:
no floating, no sliding, no sinking), and the frames go through the retargeted-CSV converter.

    python scripts/tools/make_g1_clips.py            # rewrites the npz files
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from simlab.robots.unitree import ASSETS_DIR
from simlab.tasks.manager_based.tracking.motion_clip import clip_from_csv, model_joint_names

MJCF = Path(ASSETS_DIR) / "unitree_g1_29dof.xml"
OUT = Path(__file__).resolve().parents[2] / "simlab/tasks/manager_based/tracking/config/g1/motions"
FPS = 50.0
SOLES = ("left_sole_inner", "left_sole_outer", "right_sole_inner", "right_sole_outer")

# G1_29DOF_CFG's knees-bent pose
STANCE = {
    "hip_pitch": -0.312,
    "knee": 0.669,
    "ankle_pitch": -0.363,
    "elbow": 0.6,
    "shoulder_pitch": 0.2,
}


def legs(pose: dict[str, float], knee: float) -> None:
    """Both legs bent to ``knee`` with the hip and ankle keeping the torso upright and the soles flat."""
    hip = -0.466 * knee
    for side in ("left", "right"):
        pose[f"{side}_hip_pitch_joint"], pose[f"{side}_knee_joint"] = hip, knee
        pose[f"{side}_ankle_pitch_joint"] = -(hip + knee)


def stance_pose() -> dict[str, float]:
    pose: dict[str, float] = {}
    legs(pose, STANCE["knee"])
    for side, sign in (("left", 1.0), ("right", -1.0)):
        pose[f"{side}_shoulder_pitch_joint"] = STANCE["shoulder_pitch"]
        pose[f"{side}_shoulder_roll_joint"] = 0.2 * sign
        pose[f"{side}_elbow_joint"] = STANCE["elbow"]
    return pose


def wave(t: float) -> dict[str, float]:
    """Right arm raised, waving from the elbow at 1.5 Hz; a gentle squat at 0.5 Hz."""
    pose = stance_pose()
    legs(pose, STANCE["knee"] + 0.15 * math.sin(math.pi * t))
    raise_arm = min(t / 0.8, 1.0)  # lift the arm over the first 0.8 s
    pose["right_shoulder_pitch_joint"] = 0.2 - 1.2 * raise_arm
    pose["right_shoulder_roll_joint"] = -0.2 - 0.9 * raise_arm
    pose["right_elbow_joint"] = 0.6 + raise_arm * 0.5 * math.sin(3 * math.pi * t)
    return pose


def twist(t: float) -> dict[str, float]:
    """Expressive whole body: the waist turns and leans, the arms swing against it, the knees dip."""
    pose = stance_pose()
    phase = 2 * math.pi * 0.4 * t
    legs(pose, STANCE["knee"] + 0.2 * (1 - math.cos(2 * phase)) / 2)
    pose["waist_yaw_joint"] = 0.6 * math.sin(phase)
    pose["waist_roll_joint"] = 0.15 * math.sin(phase)
    pose["waist_pitch_joint"] = 0.1 * (1 - math.cos(2 * phase)) / 2
    for side, sign in (("left", 1.0), ("right", -1.0)):
        pose[f"{side}_shoulder_pitch_joint"] = 0.2 - sign * 0.7 * math.sin(phase)
        pose[f"{side}_shoulder_roll_joint"] = sign * (0.3 + 0.3 * (1 - math.cos(2 * phase)) / 2)
        pose[f"{side}_elbow_joint"] = 0.6 + 0.4 * (1 + sign * math.sin(phase)) / 2
    return pose


def frames_for(motion: Callable[[float], dict[str, float]], seconds: float) -> np.ndarray:
    """Rows of the retargeted-CSV layout, the pelvis placed to keep the soles planted."""
    model = mujoco.MjModel.from_xml_path(str(MJCF))
    data = mujoco.MjData(model)
    joints = model_joint_names(model)
    cols = [model.jnt_qposadr[model.joint(n).id] for n in joints]
    soles = [model.geom(n).id for n in SOLES]
    rows, anchor = [], None
    for t in np.arange(0.0, seconds + 1e-9, 1.0 / FPS):
        pose = motion(float(t))
        data.qpos[:] = 0.0
        data.qpos[3] = 1.0
        data.qpos[cols] = [pose.get(n, 0.0) for n in joints]
        mujoco.mj_kinematics(model, data)
        # the soles' centre, and their lowest point (a capsule's centre line minus its radius)
        centre = np.mean([data.geom_xpos[g] for g in soles], axis=0)
        lowest = min(data.geom_xpos[g][2] - model.geom_size[g][0] for g in soles)
        if anchor is None:
            anchor = np.array([0.0, 0.0])  # the feet start centred under the world origin
        root = np.array([anchor[0] - centre[0], anchor[1] - centre[1], -lowest])
        rows.append(np.concatenate([root, [0.0, 0.0, 0.0, 1.0], data.qpos[cols]]))
    return np.asarray(rows)


CLIPS = {"g1_wave": (wave, 6.0), "g1_twist": (twist, 5.0)}


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for name, (motion, seconds) in CLIPS.items():
            csv = Path(tmp) / f"{name}.csv"
            np.savetxt(csv, frames_for(motion, seconds), delimiter=",", fmt="%.6f")
            clip = clip_from_csv(csv, MJCF, input_fps=FPS, output_fps=FPS)
            clip.save(OUT / f"{name}.npz")
            print(f"{name}: {clip.num_frames} frames, {(OUT / f'{name}.npz').stat().st_size / 1e3:.0f} kB")


if __name__ == "__main__":
    main()
