"""Make the G1 tracking clips shipped with simlab (``simlab/tasks/manager_based/tracking/config/g1/motions``).

``g1_wave`` and ``g1_twist`` are joint-angle curves of the 29-DoF G1 on its planted feet (the pelvis
placed, frame by frame, so that the soles rest flat where they started). ``g1_walk`` and ``g1_turn``
are static gaits: foot and centre-of-mass paths (the weight shifted over the stance foot before the
other one swings), the legs solved by inverse kinematics. All go through the retargeted-CSV converter
and are saved with their root in place of the body states, which loading fills by forward kinematics.

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


# -- stepping clips: foot and centre-of-mass paths, legs by inverse kinematics -------------------------

FOOT_Y = 0.1185  # the feet's half spacing in the stance pose [m]
PELVIS_Z = 0.74  # pelvis height while stepping (knees bent) [m]
SHIFT, SWING, STEP_HEIGHT = 0.5, 0.6, 0.05  # weight-shift and swing durations [s], swing apex [m]


def _smooth(s: float) -> float:
    s = min(max(s, 0.0), 1.0)
    return 0.5 - 0.5 * math.cos(math.pi * s)


def _yaw_rot(yaw: float, v: np.ndarray) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]])


def stepping_plan(steps: list[tuple[str, np.ndarray, float]]) -> Callable[[float], dict]:
    """A static gait: for each (swing side, new foot position, new foot yaw), shift the centre of mass
    over the stance foot, swing the foot along an arc to its new place, shift back between the feet.
    Returns t -> {"left"/"right": (foot position, yaw), "com": xy target, "yaw": pelvis yaw}."""
    feet = {"left": (np.array([0.0, FOOT_Y, 0.0]), 0.0), "right": (np.array([0.0, -FOOT_Y, 0.0]), 0.0)}
    keys = [(0.0, dict(feet), "mid", None)]
    t = 0.5  # stand still first
    for side, target, yaw in steps:
        stance = "right" if side == "left" else "left"
        keys.append((t, dict(feet), "mid", None))
        t += SHIFT
        keys.append((t, dict(feet), stance, None))
        start = feet[side]
        feet = {**feet, side: (np.asarray(target, float), yaw)}
        keys.append((t + SWING, dict(feet), stance, (side, start)))
        t += SWING
        keys.append((t + SHIFT, dict(feet), "mid", None))
        t += SHIFT
    keys.append((t + 0.5, dict(feet), "mid", None))

    def com_point(state: dict, where: str) -> np.ndarray:
        if where == "mid":
            return (state["left"][0][:2] + state["right"][0][:2]) / 2
        return state[where][0][:2]

    def at(time: float) -> dict:
        for (t0, f0, w0, _), (t1, f1, w1, swing) in zip(keys, keys[1:]):
            if time <= t1 or (t1 == keys[-1][0]):
                s = _smooth((time - t0) / max(t1 - t0, 1e-9))
                out = {side: f1[side] for side in ("left", "right")}
                if swing is not None:  # the swing foot travels on an arc
                    side, (p0, y0) = swing
                    p1, y1 = f1[side]
                    pos = p0 + (p1 - p0) * s
                    pos = pos + np.array([0.0, 0.0, STEP_HEIGHT * math.sin(math.pi * s)])
                    out[side] = (pos, y0 + (y1 - y0) * s)
                com = com_point(f0, w0) + (com_point(f1, w1) - com_point(f0, w0)) * s
                yaw = (out["left"][1] + out["right"][1]) / 2
                return {**out, "com": com, "yaw": yaw}
        raise AssertionError

    at.duration = keys[-1][0]  # type: ignore[attr-defined]
    return at


def walk_plan() -> Callable[[float], dict]:
    """Four steps forward: a half step, two full ones (0.3 m of foot travel), a closing step; 0.45 m in all."""
    placements = [("left", 0.15), ("right", 0.30), ("left", 0.45), ("right", 0.45)]
    return stepping_plan(
        [(side, np.array([x, FOOT_Y if side == "left" else -FOOT_Y, 0.0]), 0.0) for side, x in placements]
    )


def turn_plan() -> Callable[[float], dict]:
    """Turning in place to the left: 4 steps, the left foot turning out 0.45 rad and the right following."""
    steps, heading = [], 0.0
    for k in range(4):
        side = "left" if k % 2 == 0 else "right"
        if side == "left":
            heading += 0.45
        offset = np.array([0.0, FOOT_Y if side == "left" else -FOOT_Y, 0.0])
        steps.append((side, _yaw_rot(heading, offset), heading))
    return stepping_plan(steps)


def solve_legs(model, data, plan_t: dict, upper: dict[str, float]) -> np.ndarray:
    """qpos with the soles at the plan's foot poses (flat) and the centre of mass over its target."""
    joints = model_joint_names(model)
    start = stance_pose() | upper  # from bent knees: straight legs are a singular start
    data.qpos[:] = 0.0
    data.qpos[7 + np.arange(len(joints))] = [start.get(n, 0.0) for n in joints]
    yaw = plan_t["yaw"]
    data.qpos[3:7] = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]
    data.qpos[:3] = [*plan_t["com"], PELVIS_Z]
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    for _ in range(20):  # move the pelvis until the centre of mass is over its target
        for side in ("left", "right"):
            pos, foot_yaw = plan_t[side]
            body = model.body(f"{side}_ankle_roll_link").id
            target = pos + np.array([0.0, 0.0, ANKLE_HEIGHT])
            target_quat = np.array([math.cos(foot_yaw / 2), 0.0, 0.0, math.sin(foot_yaw / 2)])
            names = [
                f"{side}_{j}_joint" for j in ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")
            ]
            qcols = [model.jnt_qposadr[model.joint(n).id] for n in names]
            dcols = [model.jnt_dofadr[model.joint(n).id] for n in names]
            for _ in range(200):
                mujoco.mj_kinematics(model, data)
                mujoco.mj_comPos(model, data)
                err_rot = np.zeros(3)
                mujoco.mju_subQuat(err_rot, target_quat, data.xquat[body])
                err = np.concatenate([target - data.xpos[body], data.xmat[body].reshape(3, 3) @ err_rot])
                if np.linalg.norm(err) < 1e-7:
                    break
                mujoco.mj_jacBody(model, data, jacp, jacr, body)
                jac = np.vstack([jacp[:, dcols], jacr[:, dcols]])
                step = np.linalg.solve(jac.T @ jac + 1e-4 * np.eye(6), jac.T @ err)
                low, high = model.jnt_range[[model.joint(n).id for n in names]].T
                data.qpos[qcols] = np.clip(data.qpos[qcols] + step, low, high)
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        offset = plan_t["com"] - data.subtree_com[1][:2]
        if np.abs(offset).max() < 1e-4:
            break
        data.qpos[:2] += offset  # then solve the legs again for the moved pelvis
    return data.qpos.copy()


def stepping_frames(plan: Callable[[float], dict], upper: Callable[[float], dict[str, float]]) -> np.ndarray:
    model = mujoco.MjModel.from_xml_path(str(MJCF))
    data = mujoco.MjData(model)
    rows = []
    for t in np.arange(0.0, plan.duration + 1e-9, 1.0 / FPS):  # type: ignore[attr-defined]
        qpos = solve_legs(model, data, plan(float(t)), upper(float(t)))
        quat = qpos[3:7]
        rows.append(np.concatenate([qpos[:3], [quat[1], quat[2], quat[3], quat[0]], qpos[7:]]))
    return np.asarray(rows)


def arms_swing(t: float) -> dict[str, float]:
    pose = {k: v for k, v in stance_pose().items() if "shoulder" in k or "elbow" in k}
    return pose


def _ankle_height() -> float:
    """Height of the ankle-roll body above the ground when its soles rest flat."""
    model = mujoco.MjModel.from_xml_path(str(MJCF))
    geom = model.geom("left_sole_inner")
    return float(model.geom_size[geom.id][0] - model.geom_pos[geom.id][2])


ANKLE_HEIGHT = _ankle_height()


CLIPS = {"g1_wave": (wave, 6.0), "g1_twist": (twist, 5.0)}
STEPPING = {"g1_walk": walk_plan, "g1_turn": turn_plan}


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for name, (motion, seconds) in CLIPS.items():
            csv = Path(tmp) / f"{name}.csv"
            np.savetxt(csv, frames_for(motion, seconds), delimiter=",", fmt="%.6f")
            clip = clip_from_csv(csv, MJCF, input_fps=FPS, output_fps=FPS)
            clip.save(OUT / f"{name}.npz", body_states=False)
            print(f"{name}: {clip.num_frames} frames, {(OUT / f'{name}.npz').stat().st_size / 1e3:.0f} kB")
        for name, plan in STEPPING.items():
            csv = Path(tmp) / f"{name}.csv"
            np.savetxt(csv, stepping_frames(plan(), arms_swing), delimiter=",", fmt="%.6f")
            clip = clip_from_csv(csv, MJCF, input_fps=FPS, output_fps=FPS)
            clip.save(OUT / f"{name}.npz", body_states=False)
            print(f"{name}: {clip.num_frames} frames, {(OUT / f'{name}.npz').stat().st_size / 1e3:.0f} kB")


if __name__ == "__main__":
    main()
