"""Motion clips for the tracking tasks: the npz format, and the converter from retargeted CSV.

A clip is one ``.npz`` file (NumPy arrays only, read with ``allow_pickle=False``) holding, for T frames
at ``fps`` frames per second, the robot's joint and body states in the world frame:

====================  ===============  ==========================================================
key                   shape            meaning
====================  ===============  ==========================================================
``fps``               ()               frame rate [Hz]
``joint_names``       (J,)             joint names, the column order of ``joint_pos``/``joint_vel``
``body_names``        (B,)             body names, the order of the body arrays
``joint_pos``         (T, J)           joint angles [rad]
``joint_vel``         (T, J)           joint speeds [rad/s]
``body_pos_w``        (T, B, 3)        body origins in the world [m]
``body_quat_w``       (T, B, 4)        body orientations, quaternions (w, x, y, z)
``body_lin_vel_w``    (T, B, 3)        body origins' velocities in the world [m/s]
``body_ang_vel_w``    (T, B, 3)        body angular velocities in the world [rad/s]
====================  ===============  ==========================================================

The body states (``body_names`` and the four ``body_*`` arrays) are optional, all or none: a clip
without them stores its root (the floating base, body 0) instead, ``root_pos_w`` (T, 3) and
``root_quat_w`` (T, 4), and :meth:`MotionClip.load` fills them as the converter does, by forward
kinematics of the robot's MJCF (the ``mjcf`` argument) and central differences. The bodies are then
the model's, in its order, without the world. ``save(path, body_states=False)`` writes this form: a
tenth of the bytes, for clips made by the converter (the shipped ones).

The retargeted-CSV layout (as the widely shared G1 retargets of LAFAN1 use) has one frame per row,
comma-separated: the root (pelvis) position x, y, z [m], the root quaternion x, y, z, w, then one
angle per joint in the robot model's joint order. :func:`clip_from_csv` reads it, resamples it to the
wanted frame rate (linear for positions and angles, slerp for the root orientation), fills the body
states by forward kinematics of the robot's MJCF model, and the velocities by central differences.
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass, fields
from pathlib import Path

import mujoco
import numpy as np

from simlab.utils.errors import ConfigError

ROOT_COLUMNS = 7  # position xyz, quaternion xyzw


@dataclass
class MotionClip:
    fps: float
    joint_names: list[str]
    body_names: list[str]
    joint_pos: np.ndarray
    joint_vel: np.ndarray
    body_pos_w: np.ndarray
    body_quat_w: np.ndarray
    body_lin_vel_w: np.ndarray
    body_ang_vel_w: np.ndarray

    @property
    def num_frames(self) -> int:
        return self.joint_pos.shape[0]

    @property
    def duration(self) -> float:
        return (self.num_frames - 1) / self.fps

    def save(self, path: str | Path, body_states: bool = True) -> None:
        """Write the clip; ``body_states=False`` writes the root (body 0) in place of the body states, for
        a clip whose bodies are its robot model's in the converter's order (:func:`body_states`)."""
        arrays = {f.name: getattr(self, f.name) for f in fields(self)}
        arrays["joint_names"] = np.array(self.joint_names, dtype=str)
        arrays["body_names"] = np.array(self.body_names, dtype=str)
        if not body_states:
            arrays = {k: v for k, v in arrays.items() if k not in BODY_KEYS}
            arrays["root_pos_w"], arrays["root_quat_w"] = self.body_pos_w[:, 0], self.body_quat_w[:, 0]
        np.savez_compressed(path, **{k: np.asarray(v) for k, v in arrays.items()})

    @classmethod
    def load(cls, path: str | Path, mjcf: str | Path | None = None) -> MotionClip:
        """Read a clip (a path, or a shipped clip's name: ``g1_walk``), checking its keys, shapes and
        values; data only (no pickled objects). A clip without body states gets them by forward
        kinematics of the robot in ``mjcf``."""
        path = resolve_clip(path)
        if not zipfile.is_zipfile(path):  # np.load would call a text file pickled data
            raise ConfigError(
                f"Motion clip {path}: not an .npz file; a retargeted CSV becomes one with"
                " scripts/tools/csv_to_npz.py or clip_from_csv (docs/humanoids.md, 'From retargeted CSV')."
            )
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {key: data[key] for key in data.files}
        except (OSError, ValueError) as err:
            raise ConfigError(f"Motion clip {path}: not a readable npz of arrays ({err}).") from None
        stored = [k for k in BODY_KEYS if k in arrays]
        if stored and len(stored) < len(BODY_KEYS):
            raise ConfigError(
                f"Motion clip {path}: has {stored} but not {[k for k in BODY_KEYS if k not in arrays]}; a clip"
                f" stores all of {list(BODY_KEYS)} or none (then root_pos_w and root_quat_w, and forward"
                " kinematics fills them)."
            )
        missing = sorted({"fps", "joint_names", *_JOINT_SHAPES, *(() if stored else _ROOT_SHAPES)} - arrays.keys())
        if missing:
            raise ConfigError(f"Motion clip {path}: missing {missing}; the format is in {__name__}.")
        if not stored:
            if mjcf is None:
                raise ConfigError(
                    f"Motion clip {path} stores the root and no body states; loading it needs the robot's MJCF"
                    " to fill them by forward kinematics: MotionClip.load(path, mjcf=...)."
                )
            arrays.update(_filled_body_states(arrays, mjcf, str(path)))
        clip = cls(
            fps=float(arrays["fps"]),
            joint_names=[str(n) for n in arrays["joint_names"]],
            body_names=[str(n) for n in arrays["body_names"]],
            **{k: arrays[k].astype(np.float32) for k in _STATE_SHAPES},
        )
        clip.check(str(path))
        return clip

    def check(self, where: str = "motion clip") -> None:
        sizes = {"T": self.num_frames, "J": len(self.joint_names), "B": len(self.body_names)}
        _check_arrays({k: getattr(self, k) for k in _STATE_SHAPES}, _STATE_SHAPES, sizes, where)
        if not self.fps > 0 or self.num_frames < 2:
            raise ConfigError(
                f"{where}: needs fps > 0 and at least 2 frames (fps {self.fps}, {self.num_frames} frames)."
            )


def _check_arrays(arrays: dict[str, np.ndarray], shapes: dict[str, tuple], sizes: dict[str, int], where: str) -> None:
    for key, shape in shapes.items():
        want = tuple(sizes.get(d, d) for d in shape)
        got = arrays[key].shape
        if got != want:
            raise ConfigError(f"{where}: {key} has shape {got}, expected {want} (T frames, J joints, B bodies).")
        bad = np.argwhere(~np.isfinite(arrays[key]))
        if len(bad):
            raise ConfigError(f"{where}: {key} is not finite at frame {bad[0][0]}.")


def shipped_clips() -> list[str]:
    """The clips shipped with the tracking tasks (``config/<robot>/motions/*.npz``), as paths."""
    return sorted(str(p) for p in (Path(__file__).parent / "config").glob("*/motions/*.npz"))


def resolve_clip(path: str | Path) -> str:
    """``path`` where it is a file, else the shipped clip of that name (``g1_walk`` or ``g1_walk.npz``),
    so that a run's ``motion_file`` override means the same clip on every machine."""
    if Path(path).is_file():
        return str(path)
    by_name = {Path(clip).stem: clip for clip in shipped_clips()}
    name = Path(path).name.removesuffix(".npz")
    if str(path).removesuffix(".npz") == name and name in by_name:
        return by_name[name]
    folders = sorted({str(Path(clip).parent) for clip in by_name.values()})
    raise ConfigError(
        f"Motion clip {path}: no such file. Give the path of an .npz clip or a shipped one's name"
        f" ({', '.join(by_name) or 'none'}, in {', '.join(folders) or 'no folder'})."
    )


_JOINT_SHAPES = {"joint_pos": ("T", "J"), "joint_vel": ("T", "J")}
_BODY_SHAPES = {
    "body_pos_w": ("T", "B", 3),
    "body_quat_w": ("T", "B", 4),
    "body_lin_vel_w": ("T", "B", 3),
    "body_ang_vel_w": ("T", "B", 3),
}
_STATE_SHAPES = {**_JOINT_SHAPES, **_BODY_SHAPES}
_ROOT_SHAPES = {"root_pos_w": ("T", 3), "root_quat_w": ("T", 4)}
BODY_KEYS = ("body_names", *_BODY_SHAPES)  # stored all together, or none


def _filled_body_states(arrays: dict[str, np.ndarray], mjcf: str | Path, where: str) -> dict[str, np.ndarray]:
    """The body arrays of a clip stored without them, from its root and joint angles."""
    sizes = {"T": len(arrays["joint_pos"]), "J": len(arrays["joint_names"])}
    _check_arrays(arrays, {**_JOINT_SHAPES, **_ROOT_SHAPES}, sizes, where)
    if (np.linalg.norm(arrays["root_quat_w"], axis=1) < 1e-9).any():
        raise ConfigError(f"{where}: root_quat_w has a zero quaternion.")
    model = floating_base_model(mjcf)
    joints = [str(n) for n in arrays["joint_names"]]
    if sorted(joints) != sorted(model_joint_names(model)):
        raise ConfigError(
            f"{where}: the clip's joints {sorted(joints)} are not those of {mjcf} {sorted(model_joint_names(model))};"
            " its body states are filled by that model's forward kinematics."
        )
    names, *states = body_states(
        model, joints, arrays["root_pos_w"], arrays["root_quat_w"], arrays["joint_pos"], float(arrays["fps"])
    )
    return {"body_names": np.array(names), **dict(zip(_BODY_SHAPES, states))}


def read_retargeted_csv(path: str | Path, joint_names: list[str]) -> np.ndarray:
    """The CSV's frames as a (T, 7 + J) array; one-line errors name the row (1-based) that is wrong."""
    width = ROOT_COLUMNS + len(joint_names)
    rows: list[list[float]] = []
    counts: dict[int, int] = {}
    lines = Path(path).read_text().splitlines()
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        cells = line.split(",")
        counts.setdefault(len(cells), number)
        values = []
        for column, cell in enumerate(cells):
            try:
                value = float(cell)
            except ValueError:
                text = cell.strip()
                hint = " (columns are separated by commas)" if any(sep in text for sep in ";\t ") else ""
                if number == 1 and not hint:
                    hint = " (the layout has no header row: remove it)"
                text = text if len(text) <= 40 else text[:37] + "..."
                raise ConfigError(
                    f"{path}: row {number}, column {column + 1}: {text!r} is not a number{hint}."
                ) from None
            if not np.isfinite(value):
                name = _column_name(column, joint_names)
                raise ConfigError(f"{path}: row {number}, column {column + 1} ({name}) is {cell.strip()}.")
            values.append(value)
        rows.append(values)
    if not rows:
        raise ConfigError(f"{path}: no frames.")
    if len(counts) == 1 and width not in counts:
        # every row has the same wrong width: the clip is for another joint set
        (found,) = counts
        raise ConfigError(
            f"{path}: {found - ROOT_COLUMNS} joint columns per row, but the robot has {len(joint_names)} joints"
            f" (a row is {ROOT_COLUMNS} root columns, position xyz and quaternion xyzw, then one angle per joint)."
        )
    for values, number in zip(rows, [n for n, line in enumerate(lines, start=1) if line.strip()]):
        if len(values) != width:
            raise ConfigError(
                f"{path}: row {number} has {len(values)} columns, expected {width}"
                f" ({ROOT_COLUMNS} root + {len(joint_names)} joints)."
            )
    return np.asarray(rows, dtype=np.float64)


def _column_name(column: int, joint_names: list[str]) -> str:
    root = ["root x", "root y", "root z", "root qx", "root qy", "root qz", "root qw"]
    return (
        root[column]
        if column < ROOT_COLUMNS
        else joint_names[column - ROOT_COLUMNS]
        if column - ROOT_COLUMNS < len(joint_names)
        else "extra"
    )


def model_joint_names(model: mujoco.MjModel) -> list[str]:
    """The hinge and slide joints of ``model`` in its order (the CSV's joint column order)."""
    moving = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    return [model.joint(j).name for j in range(model.njnt) if int(model.jnt_type[j]) in moving]


def floating_base_model(mjcf_path: str | Path) -> mujoco.MjModel:
    model = mujoco.MjModel.from_xml_path(str(mjcf_path))
    if model.njnt == 0 or model.jnt_type[0] != mujoco.mjtJoint.mjJNT_FREE:
        raise ConfigError(f"{mjcf_path}: the robot needs a floating base (a free joint first) for a motion clip.")
    return model


def clip_from_csv(
    csv_path: str | Path, mjcf_path: str | Path, input_fps: float, output_fps: float = 50.0
) -> MotionClip:
    """A clip from a retargeted CSV of the robot in ``mjcf_path`` (a floating base, then hinge joints)."""
    model = floating_base_model(mjcf_path)
    joints = model_joint_names(model)
    frames = read_retargeted_csv(csv_path, joints)
    if len(frames) < 2:
        raise ConfigError(f"{csv_path}: needs at least 2 frames, has {len(frames)}.")
    _check_frames(frames, model, joints, str(csv_path))
    root_pos, root_quat, joint_pos = _resample(frames, input_fps, output_fps)
    bodies, body_pos, body_quat, body_lin_vel, body_ang_vel = body_states(
        model, joints, root_pos, root_quat, joint_pos, output_fps
    )
    clip = MotionClip(
        fps=output_fps,
        joint_names=joints,
        body_names=bodies,
        joint_pos=joint_pos.astype(np.float32),
        joint_vel=np.gradient(joint_pos, 1.0 / output_fps, axis=0).astype(np.float32),
        body_pos_w=body_pos.astype(np.float32),
        body_quat_w=body_quat.astype(np.float32),
        body_lin_vel_w=body_lin_vel.astype(np.float32),
        body_ang_vel_w=body_ang_vel.astype(np.float32),
    )
    clip.check(str(csv_path))
    return clip


def body_states(
    model: mujoco.MjModel,
    joint_names: list[str],
    root_pos: np.ndarray,
    root_quat: np.ndarray,
    joint_pos: np.ndarray,
    fps: float,
) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The bodies of ``model`` (a floating base first) with their world positions, quaternions, and linear
    and angular velocities by central differences, for T frames of the root pose (position, quaternion
    w x y z) and joint angles (columns named ``joint_names``) at ``fps``; float64 arrays."""
    data = mujoco.MjData(model)
    qpos_cols = [model.jnt_qposadr[model.joint(name).id] for name in joint_names]
    bodies = [model.body(b).name for b in range(1, model.nbody)]
    body_pos = np.zeros((len(joint_pos), len(bodies), 3))
    body_quat = np.zeros((len(joint_pos), len(bodies), 4))
    for t in range(len(joint_pos)):
        data.qpos[:3], data.qpos[3:7] = root_pos[t], root_quat[t]
        data.qpos[qpos_cols] = joint_pos[t]
        mujoco.mj_kinematics(model, data)
        body_pos[t], body_quat[t] = data.xpos[1:], data.xquat[1:]
    dt = 1.0 / fps
    return bodies, body_pos, body_quat, np.gradient(body_pos, dt, axis=0), _angular_velocity(body_quat, dt)


ANGLE_SLACK = 1.0  # rad beyond a joint's range that a retarget may overshoot; more is another unit (degrees)


def _check_frames(frames: np.ndarray, model: mujoco.MjModel, joints: list[str], where: str) -> None:
    """Refuse what would turn into a wrong clip without an error: a zero root quaternion (NaN poses) and
    joint angles far outside the joint's range (a CSV in degrees)."""
    zero = np.flatnonzero(np.linalg.norm(frames[:, 3:ROOT_COLUMNS], axis=1) < 1e-9)
    if len(zero):
        raise ConfigError(f"{where}: frame {zero[0] + 1}: the root quaternion (columns 4-7, x y z w) is zero.")
    for column, name in enumerate(joints):
        joint = model.joint(name)
        if not model.jnt_limited[joint.id]:
            continue
        low, high = model.jnt_range[joint.id]
        angles = frames[:, ROOT_COLUMNS + column]
        far = np.flatnonzero((angles < low - ANGLE_SLACK) | (angles > high + ANGLE_SLACK))
        if len(far):
            raise ConfigError(
                f"{where}: frame {far[0] + 1}, column {ROOT_COLUMNS + column + 1} ({name}) is"
                f" {angles[far[0]]:g} rad, far outside the joint's range [{low:.3g}, {high:.3g}] rad"
                " (angles are radians)."
            )


def _resample(frames: np.ndarray, input_fps: float, output_fps: float) -> tuple[np.ndarray, ...]:
    """Root positions, root quaternions (w, x, y, z) and joint angles at ``output_fps``."""
    if not (input_fps > 0 and output_fps > 0):
        raise ConfigError(f"Frame rates must be positive (input_fps {input_fps}, output_fps {output_fps}).")
    quat = frames[:, [6, 3, 4, 5]]  # xyzw -> wxyz
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    quat[1:] *= np.sign(np.sum(quat[1:] * quat[:-1], axis=1, keepdims=True) + 1e-12).cumprod(axis=0)  # one hemisphere
    times = np.arange(len(frames)) / input_fps
    new_times = np.arange(0.0, times[-1] + 1e-9, 1.0 / output_fps)
    index = np.clip(np.searchsorted(times, new_times, side="right") - 1, 0, len(frames) - 2)
    blend = ((new_times - times[index]) * input_fps)[:, None]
    lerp = lambda a: a[index] * (1 - blend) + a[index + 1] * blend  # noqa: E731
    return lerp(frames[:, :3]), _slerp(quat[index], quat[index + 1], blend), lerp(frames[:, ROOT_COLUMNS:])


def _slerp(q0: np.ndarray, q1: np.ndarray, blend: np.ndarray) -> np.ndarray:
    dot = np.clip(np.sum(q0 * q1, axis=1, keepdims=True), -1.0, 1.0)
    angle = np.arccos(np.abs(dot))
    q1 = np.where(dot < 0, -q1, q1)
    small = angle < 1e-6
    sin = np.where(small, 1.0, np.sin(angle))
    w0 = np.where(small, 1 - blend, np.sin((1 - blend) * angle) / sin)
    w1 = np.where(small, blend, np.sin(blend * angle) / sin)
    q = w0 * q0 + w1 * q1
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _angular_velocity(quat: np.ndarray, dt: float) -> np.ndarray:
    """World-frame angular velocities of (T, B, 4) orientations by central differences."""
    omega = np.zeros(quat.shape[:-1] + (3,))
    for t in range(len(quat)):
        a, b = max(t - 1, 0), min(t + 1, len(quat) - 1)
        for body in range(quat.shape[1]):
            rel = np.zeros(4)
            neg = np.zeros(4)
            mujoco.mju_negQuat(neg, quat[a, body])
            mujoco.mju_mulQuat(rel, quat[b, body], neg)  # world-frame rotation from a to b
            rotvec = np.zeros(3)
            mujoco.mju_quat2Vel(rotvec, rel, (b - a) * dt)
            omega[t, body] = rotvec
    return omega
