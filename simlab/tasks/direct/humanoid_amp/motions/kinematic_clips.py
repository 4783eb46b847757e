"""Walk, run and dance clips for simlab's humanoid, made by a kinematic gait generator.

Isaac Lab's AMP clips are motion capture that cannot be shipped, so simlab makes its own. Each clip
is a periodic pattern of joint angles (sinusoids of the gait phase: hips swing, knees flex in the
swing phase, ankles keep the feet level, arms swing against the legs, the waist counter-rotates)
and of the torso's orientation. The body poses come from MuJoCo's forward kinematics
(``mj_kinematics``) of ``simlab/robots/assets/humanoid.xml``; the torso is placed so that the lower
foot touches the ground and does not slide (the torso advances by what the stance foot moves back)
and sways sideways over the stance foot, so the forward speed follows from the leg motion.
A slow motion that stands on one foot for long (the dance) is balanced instead (``ClipSpec.support``):
the feet are held level, the hips roll the pelvis over the supporting foot, and that foot stays planted.
Velocities are finite differences.

Every joint and the torso move a little (sway, secondary motion): a clip in which some AMP
observation features never change (a torso pinned upright with zero angular velocity, joints
frozen at one angle) is a distribution a simulated body cannot reach, and the discriminator tells
any policy from it by those features alone (its style reward stays low whatever the gait).
``python scripts/tools/make_motion_clips.py`` writes the clips shipped in this folder.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from .body_states import angular_velocities, quat_multiply
from .motion_file import HUMANOID_XML, write_motion_file

__all__ = ["CLIPS", "HUMANOID_XML", "ClipSpec", "make_clip", "write_clips"]

FOOT_GEOMS = {
    "right_foot": ("right_right_foot", "left_right_foot"),
    "left_foot": ("left_left_foot", "right_left_foot"),
}


@dataclass(frozen=True)
class ClipSpec:
    """A periodic motion: joint angles as a function of the gait phase (radians, 0..2 pi)."""

    name: str
    cadence_hz: float  # gait cycles (two steps) per second
    cycles: int  # cycles in the clip
    torso_pitch: float  # forward lean of the torso [rad]
    joint_angles: Callable[[float], dict[str, float]]
    torso_sway: Callable[[float], tuple[float, float, float]] = lambda phase: (0.0, 0.0, 0.0)
    """The torso's roll, pitch (added to ``torso_pitch``) and yaw [rad] over the gait phase."""
    lateral_sway: float = 0.0  # sideways excursion of the torso over the stance foot [m]
    support: Callable[[float], float] | None = None
    """Quasi-static balance, for slow motions with long single-support phases: the share of the weight
    on the right foot over the gait phase (0..1). The feet are held level (the hips' twist and the
    ankles), both hips roll so that the centre of mass lies over that point between the feet, and the
    stance foot stays planted sideways as well as forward. None: no balancing (the torso sways by
    ``lateral_sway``)."""


def _legs(
    phase: float,
    hip_swing: float,
    hip_bias: float,
    knee_rest: float,
    knee_swing: float,
    lean: float,
    march: bool = False,
) -> dict[str, float]:
    """Both legs: the right leg swings forward while cos(phase) > 0, the left half a cycle later.

    ``march`` lifts the knees in place instead: the thigh moves only in the swing phase, so the
    stance foot stays under the body and the torso does not advance.
    """
    angles = {}
    for side, shift in (("right", 0.0), ("left", math.pi)):
        p = phase + shift
        if march:
            hip = hip_bias - hip_swing * max(0.0, math.cos(p)) ** 2
        else:
            hip = -hip_swing * math.sin(p) + hip_bias  # negative: the thigh swings forward
        knee = -(knee_rest + knee_swing * max(0.0, math.cos(p)) ** 2)  # negative: the knee bends
        angles[f"{side}_thigh:1"] = hip
        angles[f"{side}_shin"] = knee
        angles[f"{side}_foot:0"] = 0.8 * (knee - hip - lean)  # keep the sole roughly level
        angles[f"{side}_thigh:0"] = -0.05 - 0.05 * math.cos(p)  # the swing leg abducts, the stance hip adducts
        angles[f"{side}_thigh:2"] = -0.05 * math.sin(p)  # the hips rotate with the stride
        angles[f"{side}_foot:1"] = 0.06 * math.cos(p)  # the ankle rolls over the sole
    return angles


def _arm_sway(angles: dict[str, float], phase: float, amount: float) -> None:
    """Secondary arm motion: shoulders and elbows follow the swing a little."""
    for side, sign in (("right", 1.0), ("left", -1.0)):
        angles[f"{side}_upper_arm:0"] = angles.get(f"{side}_upper_arm:0", 0.0) + amount * math.cos(phase)
        angles[f"{side}_lower_arm"] = angles.get(f"{side}_lower_arm", 0.0) + amount * sign * math.sin(phase)


def _gait_sway(roll: float, pitch: float, yaw: float) -> Callable[[float], tuple[float, float, float]]:
    """A torso that rolls over the stance leg and yaws with the stride once per cycle and pitches
    twice per cycle (at each heel strike)."""
    return lambda phase: (-roll * math.cos(phase), pitch * math.cos(2 * phase), yaw * math.sin(phase))


def _walk(phase: float) -> dict[str, float]:
    angles = _legs(phase, hip_swing=0.40, hip_bias=-0.10, knee_rest=0.10, knee_swing=0.90, lean=0.05)
    angles["right_upper_arm:2"] = -0.35 * math.sin(phase)  # arms swing against the legs
    angles["left_upper_arm:2"] = 0.35 * math.sin(phase)
    angles["right_upper_arm:0"] = angles["left_upper_arm:0"] = 0.35  # arms closer to the body
    angles["right_lower_arm"] = angles["left_lower_arm"] = -0.40
    angles["lower_waist:0"] = 0.10 * math.sin(phase)  # the waist counter-rotates
    angles["lower_waist:1"] = 0.04 * math.cos(2 * phase)
    angles["pelvis"] = 0.05 * math.cos(phase)
    _arm_sway(angles, phase, 0.08)
    return angles


def _run(phase: float) -> dict[str, float]:
    angles = _legs(phase, hip_swing=0.70, hip_bias=-0.25, knee_rest=0.30, knee_swing=1.50, lean=0.15)
    angles["right_upper_arm:2"] = -0.60 * math.sin(phase)
    angles["left_upper_arm:2"] = 0.60 * math.sin(phase)
    angles["right_upper_arm:0"] = angles["left_upper_arm:0"] = 0.40
    angles["right_lower_arm"] = angles["left_lower_arm"] = -1.20  # elbows bent
    angles["lower_waist:0"] = 0.20 * math.sin(phase)
    angles["lower_waist:1"] = 0.10 + 0.06 * math.cos(2 * phase)  # leaning into the run
    angles["pelvis"] = 0.08 * math.cos(phase)
    _arm_sway(angles, phase, 0.12)
    return angles


def _march_support(phase: float) -> float:
    """The weight on the right foot in ``_legs(march=True)``: all of it while the left knee is up
    (cos(phase) < 0), none while the right one is, moving across as the feet pass each other."""
    c = math.cos(phase)
    return 0.5 - 0.5 * c / (abs(c) + 0.1)  # 0.9 / 0.1 at abs(c) = 0.8, where the lifted foot is 8 cm up


def _dance(phase: float) -> dict[str, float]:
    # marching in place with high knees, the torso twisting, the arms raised and waving
    angles = _legs(phase, hip_swing=0.90, hip_bias=-0.05, knee_rest=0.10, knee_swing=1.30, lean=0.0, march=True)
    angles["lower_waist:0"] = 0.45 * math.sin(phase)
    angles["pelvis"] = 0.20 * math.sin(phase)
    angles["right_upper_arm:0"] = -0.90 + 0.40 * math.sin(2 * phase)
    angles["left_upper_arm:0"] = -0.90 - 0.40 * math.sin(2 * phase)
    angles["right_upper_arm:2"] = 0.50 * math.cos(phase)
    angles["left_upper_arm:2"] = -0.50 * math.cos(phase)
    angles["right_lower_arm"] = -0.80 + 0.50 * math.sin(2 * phase)
    angles["left_lower_arm"] = -0.80 - 0.50 * math.sin(2 * phase)
    angles["lower_waist:1"] = 0.08 * math.cos(2 * phase)
    return angles


CLIPS = {
    "walk": ClipSpec(
        "walk", 0.9, 4, torso_pitch=0.05, joint_angles=_walk, torso_sway=_gait_sway(0.05, 0.02, 0.06), lateral_sway=0.03
    ),
    "run": ClipSpec(
        "run", 1.4, 6, torso_pitch=0.15, joint_angles=_run, torso_sway=_gait_sway(0.06, 0.04, 0.10), lateral_sway=0.02
    ),
    "dance": ClipSpec(
        "dance",
        0.75,
        3,
        torso_pitch=0.0,
        joint_angles=_dance,
        torso_sway=_gait_sway(0.10, 0.03, 0.15),
        support=_march_support,  # a slow march stands on one foot for half a second at a time
    ),
}
"""The shipped clips: cadence in gait cycles per second (two steps each)."""


def _torso_quat(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """The quaternion (w, x, y, z) of intrinsic z-y-x (yaw, pitch, roll) rotations."""
    half = np.array([roll, pitch, yaw]) / 2
    qx = np.array([math.cos(half[0]), math.sin(half[0]), 0.0, 0.0])
    qy = np.array([math.cos(half[1]), 0.0, math.sin(half[1]), 0.0])
    qz = np.array([math.cos(half[2]), 0.0, 0.0, math.sin(half[2])])
    return quat_multiply(qz, quat_multiply(qy, qx))


def _lowest_point(model: mujoco.MjModel, data: mujoco.MjData, geom_names: tuple[str, ...]) -> np.ndarray:
    """The lowest point (3,) of the capsules ``geom_names`` in the current pose."""
    best = None
    for name in geom_names:
        g = model.geom(name).id
        axis = data.geom_xmat[g].reshape(3, 3)[:, 2] * model.geom_size[g, 1]
        for end in (data.geom_xpos[g] + axis, data.geom_xpos[g] - axis):
            point = end - np.array([0.0, 0.0, model.geom_size[g, 0]])
            if best is None or point[2] < best[2]:
                best = point
    return best


def _centre_of_mass(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """The whole body's centre of mass (3,) in the current pose (after ``mj_kinematics``)."""
    return (model.body_mass[:, None] * data.xipos).sum(0) / model.body_mass.sum()


FOOT_LEVELLERS = {
    "right_foot": ("right_thigh:2", "right_foot:0", "right_foot:1"),
    "left_foot": ("left_thigh:2", "left_foot:0", "left_foot:1"),
}
"""The joints that turn each foot about the vertical, across and along it: the hip's twist and the ankle."""


def _level_feet(model: mujoco.MjModel, data: mujoco.MjData, level: dict[str, np.ndarray]) -> None:
    """Turn both feet to the world orientations ``level`` (their orientations in the upright zero pose:
    flat, pointing forward) with the hips' twist and the ankles, whatever the torso's sway: a foot on the
    ground then stays planted, turning neither with the torso nor about its contact point."""
    feet = [
        (foot, model.body(foot).id, [model.joint(name).id for name in joints])
        for foot, joints in FOOT_LEVELLERS.items()
    ]
    jacr, error = np.zeros((3, model.nv)), np.zeros(3)
    for _ in range(4):  # Newton steps on the rotation error; converges in 2-3 for the sways used here
        mujoco.mj_kinematics(model, data)
        for foot, body, joint_ids in feet:
            mujoco.mju_subQuat(error, level[foot], data.xquat[body])  # rotation taking the foot to level
            mujoco.mj_jacBody(model, data, None, jacr, body)
            step = np.linalg.lstsq(
                jacr[:, model.jnt_dofadr[joint_ids]], data.xmat[body].reshape(3, 3) @ error, rcond=None
            )[0]
            adr = model.jnt_qposadr[joint_ids]
            data.qpos[adr] = np.clip(data.qpos[adr] + step, *model.jnt_range[joint_ids].T)
    mujoco.mj_kinematics(model, data)


def _balance_by_hip_roll(
    model: mujoco.MjModel, data: mujoco.MjData, level: dict[str, np.ndarray], right_share: float, theta: float
) -> float:
    """Roll both legs at the hips until the centre of mass is over the point that carries ``right_share``
    of the weight on the right foot, the feet held level; returns the roll angle (``theta``: a guess).

    Tilting both legs by the same angle moves the pelvis sideways over feet that keep their place;
    the angle is found by the secant method on the sideways offset (a few cm to 0.1 m).
    """
    right_adr, left_adr = (model.jnt_qposadr[model.joint(name).id] for name in ("right_thigh:0", "left_thigh:0"))
    base = data.qpos.copy()

    def offset(theta: float) -> float:
        data.qpos[:] = base
        # right_thigh:0 turns about +x, left_thigh:0 about -x: the same world tilt takes opposite signs
        data.qpos[right_adr] += theta
        data.qpos[left_adr] -= theta
        _level_feet(model, data, level)
        right, left = (_sole_middle(data, foot) for foot in ("right_foot", "left_foot"))
        support_y = right_share * right[1] + (1.0 - right_share) * left[1]
        return float(_centre_of_mass(model, data)[1] - support_y)

    # within +-0.26 rad both hips stay inside their abduction range
    a, b = theta, theta + 0.02
    fa, fb = offset(a), offset(b)
    for _ in range(8):
        if abs(fb) < 1e-4 or fb == fa:
            break
        a, b, fa = b, float(np.clip(b - fb * (b - a) / (fb - fa), -0.26, 0.26)), fb
        fb = offset(b)
    return b  # the last angle evaluated: data holds its pose


def _sole_middle(data: mujoco.MjData, foot: str) -> np.ndarray:
    """The middle of a foot's sole (its capsules' centres): smooth in the pose, as the lowest point is not."""
    return np.mean([data.geom(g).xpos for g in FOOT_GEOMS[foot]], axis=0)


def make_clip(spec: ClipSpec, fps: float = 60.0, xml_path: str = HUMANOID_XML) -> tuple[dict, dict]:
    """The clip of ``spec`` as motion-file arrays, and its measured forward speed and cadence."""
    model = mujoco.MjModel.from_xml_path(xml_path)
    data = mujoco.MjData(model)
    joints = [model.joint(j) for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
    dof_names = [j.name for j in joints]
    body_names = [model.body(b).name for b in range(1, model.nbody)]
    frames_per_cycle = round(fps / spec.cadence_hz)
    cadence = fps / frames_per_cycle  # a whole number of frames per cycle, so the clip loops
    num_frames = spec.cycles * frames_per_cycle + 1

    dof_positions = np.zeros((num_frames, len(joints)))
    body_positions = np.zeros((num_frames, len(body_names), 3))
    body_rotations = np.zeros((num_frames, len(body_names), 4))
    mujoco.mj_kinematics(model, data)  # the upright zero pose: its feet are level
    level = {foot: data.xquat[model.body(foot).id].copy() for foot in FOOT_LEVELLERS}
    root_x, root_y, hip_roll, previous_stance, previous_feet = 0.0, 0.0, 0.0, None, {}
    for f in range(num_frames):
        phase = 2 * math.pi * f / frames_per_cycle
        angles = spec.joint_angles(phase)
        unknown = set(angles) - set(dof_names)
        if unknown:
            raise ValueError(f"Clip '{spec.name}' sets unknown joints {sorted(unknown)}; joints: {dof_names}")
        data.qpos[:] = 0.0
        roll, pitch, yaw = spec.torso_sway(phase)
        data.qpos[3:7] = _torso_quat(roll, spec.torso_pitch + pitch, yaw)
        for j, joint in enumerate(joints):
            low, high = model.jnt_range[joint.id]
            angle = float(np.clip(angles.get(joint.name, 0.0), low, high))
            data.qpos[model.jnt_qposadr[joint.id]] = angle
            dof_positions[f, j] = angle
        mujoco.mj_kinematics(model, data)
        if spec.support is not None:
            hip_roll = _balance_by_hip_roll(model, data, level, spec.support(phase), hip_roll)
            dof_positions[f] = [data.qpos[model.jnt_qposadr[joint.id]] for joint in joints]
        feet = {name: _lowest_point(model, data, geoms) for name, geoms in FOOT_GEOMS.items()}
        stance = min(feet, key=lambda name: feet[name][2])
        # the torso advances by what the stance foot (the lower one) moved back since the last frame;
        # balanced, it also moves sideways by what that foot moved sideways, and the foot is held by its
        # sole's middle (a level foot's lowest point jumps between heel and toe)
        anchors = {name: _sole_middle(data, name) for name in feet} if spec.support is not None else feet
        if previous_stance is not None:
            root_x -= anchors[previous_stance][0] - previous_feet[previous_stance][0]
            if spec.support is not None:
                root_y -= anchors[previous_stance][1] - previous_feet[previous_stance][1]
        previous_stance, previous_feet = stance, anchors
        # lower foot on the ground; the torso shifts sideways over the stance foot (the left one at phase 0)
        offset = np.array([root_x, root_y + spec.lateral_sway * math.cos(phase), -feet[stance][2]])
        body_positions[f] = data.xpos[1:] + offset
        body_rotations[f] = data.xquat[1:]

    dt = 1.0 / fps
    clip = {
        "fps": fps,
        "dof_names": dof_names,
        "body_names": body_names,
        "dof_positions": dof_positions,
        "dof_velocities": np.gradient(dof_positions, dt, axis=0),
        "body_positions": body_positions,
        "body_rotations": body_rotations,
        "body_linear_velocities": np.gradient(body_positions, dt, axis=0),
        "body_angular_velocities": angular_velocities(body_rotations, dt),
    }
    torso = body_names.index("torso")
    duration = dt * (num_frames - 1)
    stats = {
        "duration_s": duration,
        "cadence_hz": cadence,
        "forward_speed_m_s": (body_positions[-1, torso, 0] - body_positions[0, torso, 0]) / duration,
        "mean_torso_height_m": float(body_positions[:, torso, 2].mean()),
    }
    return clip, stats


def write_clips(folder: str, names: list[str] | None = None, fps: float = 60.0) -> dict[str, dict]:
    """Write ``humanoid_<name>.npz`` for each clip into ``folder``; returns each clip's stats."""
    all_stats = {}
    for name in names or list(CLIPS):
        if name not in CLIPS:
            raise ValueError(f"Unknown clip '{name}'. Clips: {list(CLIPS)}")
        clip, stats = make_clip(CLIPS[name], fps)
        # the root and joints only: the loader fills the body states (finite differences of FK poses)
        write_motion_file(os.path.join(folder, f"humanoid_{name}.npz"), **clip, body_states=False)
        all_stats[name] = stats
    return all_stats
