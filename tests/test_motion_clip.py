"""Motion clips: the npz format and the converter from retargeted CSV (forward kinematics fills the
body states), with one-line errors that name the row."""

from __future__ import annotations

import math
import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import load_script

from simlab.robots.unitree import ASSETS_DIR
from simlab.tasks.manager_based.tracking.motion_clip import MotionClip, clip_from_csv, resolve_clip, shipped_clips
from simlab.utils.errors import ConfigError

G1_29DOF = f"{ASSETS_DIR}/unitree_g1_29dof.xml"
CSV_TO_NPZ = os.path.join(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "tools", "csv_to_npz.py"
)
JOINTS = 29


def write_csv(path, frames: np.ndarray) -> None:
    path.write_text("\n".join(",".join(f"{v:.9f}" for v in row) for row in frames) + "\n")


def walking_frames(fps: float, seconds: float) -> np.ndarray:
    """The pelvis moving forward at 0.5 m/s and turning at 0.5 rad/s, the knees bending at 1 Hz."""
    t = np.arange(int(seconds * fps) + 1) / fps
    yaw = 0.5 * t
    frames = np.zeros((len(t), 7 + JOINTS))
    frames[:, 0], frames[:, 2] = 0.5 * t, 0.75
    frames[:, 5], frames[:, 6] = np.sin(yaw / 2), np.cos(yaw / 2)  # quaternion x, y, z, w about z
    frames[:, 7 + 3] = 0.3 + 0.2 * np.sin(2 * math.pi * t)  # left_knee_joint (the 4th joint)
    return frames


def test_csv_to_clip_by_forward_kinematics(tmp_path):
    write_csv(tmp_path / "walk.csv", walking_frames(30.0, 2.0))
    clip = clip_from_csv(tmp_path / "walk.csv", G1_29DOF, input_fps=30.0, output_fps=50.0)
    assert clip.fps == 50.0 and clip.num_frames == 101 and clip.duration == pytest.approx(2.0)
    assert clip.joint_names[3] == "left_knee_joint" and len(clip.joint_names) == JOINTS
    assert clip.body_names[0] == "pelvis" and len(clip.body_names) == 30
    t = np.arange(101) / 50.0
    # resampled joints, and their speeds by differences (1 Hz sine: within 2 % inside the clip)
    np.testing.assert_allclose(clip.joint_pos[:, 3], 0.3 + 0.2 * np.sin(2 * math.pi * t), atol=5e-3)
    np.testing.assert_allclose(clip.joint_vel[5:-5, 3], 0.4 * math.pi * np.cos(2 * math.pi * t[5:-5]), atol=0.05)
    # the pelvis is the root: its state is the CSV's
    pelvis = 0
    np.testing.assert_allclose(clip.body_pos_w[:, pelvis], np.stack([0.5 * t, 0 * t, 0.75 + 0 * t], 1), atol=1e-5)
    np.testing.assert_allclose(clip.body_quat_w[:, pelvis, 0], np.cos(0.25 * t), atol=1e-5)
    np.testing.assert_allclose(clip.body_lin_vel_w[1:-1, pelvis], [[0.5, 0, 0]] * 99, atol=1e-4)
    np.testing.assert_allclose(clip.body_ang_vel_w[:, :, 2], 0.5, atol=1e-3)  # every body turns with it
    # a foot follows the forward kinematics: in the pelvis's heading frame it sits where the knee puts
    # it, the same at t = 0 s and t = 1 s (same knee angle, the pelvis moved and turned)
    foot = clip.body_names.index("left_ankle_roll_link")
    offset = clip.body_pos_w[:, foot] - clip.body_pos_w[:, pelvis]
    yaw = 0.5 * t
    local_x = np.cos(yaw) * offset[:, 0] + np.sin(yaw) * offset[:, 1]
    local_y = -np.sin(yaw) * offset[:, 0] + np.cos(yaw) * offset[:, 1]
    local = np.stack([local_x, local_y, offset[:, 2]], 1)
    np.testing.assert_allclose(local[0], local[50], atol=1e-4)
    assert not np.allclose(local[0], local[12], atol=1e-3), "and moves when the knee bends"
    assert local[0, 1] > 0.05 and -0.8 < local[0, 2] < -0.7, "the left foot, below the pelvis"


def test_clip_round_trip(tmp_path):
    write_csv(tmp_path / "walk.csv", walking_frames(50.0, 1.0))
    clip = clip_from_csv(tmp_path / "walk.csv", G1_29DOF, input_fps=50.0, output_fps=50.0)
    clip.save(tmp_path / "walk.npz")
    again = MotionClip.load(tmp_path / "walk.npz")
    assert again.joint_names == clip.joint_names and again.body_names == clip.body_names
    np.testing.assert_array_equal(again.body_quat_w, clip.body_quat_w)


def test_joint_count_mismatch(tmp_path):
    write_csv(tmp_path / "g1_23dof.csv", walking_frames(30.0, 0.5)[:, : 7 + 23])
    with pytest.raises(ConfigError, match=r"23 joint columns per row, but the robot has 29 joints"):
        clip_from_csv(tmp_path / "g1_23dof.csv", G1_29DOF, input_fps=30.0)


def test_a_short_row_is_named(tmp_path):
    lines = [",".join(["0"] * 36)] * 5
    lines[2] = ",".join(["0"] * 35)
    (tmp_path / "cut.csv").write_text("\n".join(lines))
    with pytest.raises(ConfigError, match=r"row 3 has 35 columns, expected 36 \(7 root \+ 29 joints\)"):
        clip_from_csv(tmp_path / "cut.csv", G1_29DOF, input_fps=30.0)


def test_nan_and_text_are_named_by_row_and_column(tmp_path):
    frames = walking_frames(30.0, 0.5)
    frames[4, 7 + 3] = np.nan
    write_csv(tmp_path / "nan.csv", frames)
    with pytest.raises(ConfigError, match=r"row 5, column 11 \(left_knee_joint\) is nan"):
        clip_from_csv(tmp_path / "nan.csv", G1_29DOF, input_fps=30.0)
    (tmp_path / "text.csv").write_text(",".join(["0"] * 35 + ["knee"]))
    with pytest.raises(ConfigError, match=r"row 1, column 36: 'knee' is not a number \(the layout has no header"):
        clip_from_csv(tmp_path / "text.csv", G1_29DOF, input_fps=30.0)
    write_csv(tmp_path / "late.csv", walking_frames(30.0, 0.5))
    (tmp_path / "late.csv").write_text((tmp_path / "late.csv").read_text() + ",".join(["0"] * 35 + ["knee"]))
    with pytest.raises(ConfigError, match=r"row 17, column 36: 'knee' is not a number\.$"):
        clip_from_csv(tmp_path / "late.csv", G1_29DOF, input_fps=30.0)  # a header only on the first row


def test_frames_that_would_make_a_wrong_clip_are_refused(tmp_path):
    frames = walking_frames(30.0, 0.5)
    frames[2, 3:7] = 0.0  # gave NaN poses, reported as "body_pos_w is not finite"
    write_csv(tmp_path / "zero.csv", frames)
    with pytest.raises(ConfigError, match=r"frame 3: the root quaternion \(columns 4-7, x y z w\) is zero"):
        clip_from_csv(tmp_path / "zero.csv", G1_29DOF, input_fps=30.0)
    frames = walking_frames(30.0, 0.5)
    frames[:, 7 + 3] = np.degrees(frames[:, 7 + 3])  # the knee in degrees made a clip
    write_csv(tmp_path / "degrees.csv", frames)
    with pytest.raises(ConfigError, match=r"frame 1, column 11 \(left_knee_joint\) is 17.18.* rad, far outside"):
        clip_from_csv(tmp_path / "degrees.csv", G1_29DOF, input_fps=30.0)
    (tmp_path / "semicolons.csv").write_text(";".join(["0.5"] * 36) + "\n")
    with pytest.raises(ConfigError, match=r"column 1: '0.5;0.5;.{29}\.\.\.' is not a number \(columns are separated"):
        clip_from_csv(tmp_path / "semicolons.csv", G1_29DOF, input_fps=30.0)


class _Payload:
    def __init__(self, path):
        self.path = path

    def __reduce__(self):
        return (open, (self.path, "w"))


def test_a_clip_is_data_only(tmp_path):
    """The attack: an npz whose object array would create a file when unpickled is refused unread."""
    target = tmp_path / "pwned"
    arrays = {"fps": np.array(50.0), "joint_pos": np.array([_Payload(str(target))], dtype=object)}
    with open(tmp_path / "evil.npz", "wb") as f:
        np.savez(f, **arrays)
    with pytest.raises(ConfigError, match="not a readable npz of arrays"):
        MotionClip.load(tmp_path / "evil.npz")
    assert not target.exists()


def test_a_missing_clip_or_a_csv_says_what_motion_file_takes(tmp_path):
    with pytest.raises(
        ConfigError, match=r"g1_walkk: no such file.*shipped one's name \(g1_turn, .*g1_walk, .*motions\)"
    ):
        MotionClip.load("g1_walkk")
    write_csv(tmp_path / "walk.csv", walking_frames(50.0, 0.5))
    with pytest.raises(ConfigError, match=r"walk\.csv: not an \.npz file; a retargeted CSV .*clip_from_csv"):
        MotionClip.load(tmp_path / "walk.csv")  # np.load called it pickled data


def test_a_shipped_clip_is_named_by_its_name(tmp_path, monkeypatch):
    """``motion_file=g1_walk`` is the shipped walk on every machine (a run's override, replayed elsewhere);
    only a bare name is looked up: a path that is not a file stays an error, and a file of that name wins."""
    walk = next(clip for clip in shipped_clips() if clip.endswith("g1_walk.npz"))
    assert resolve_clip("g1_walk") == resolve_clip("g1_walk.npz") == walk
    assert MotionClip.load("g1_walk", mjcf=G1_29DOF).num_frames == MotionClip.load(walk, mjcf=G1_29DOF).num_frames
    with pytest.raises(ConfigError, match="no such file"):
        resolve_clip(tmp_path / "g1_walk")
    with pytest.raises(ConfigError, match="no such file"):
        resolve_clip("../g1_walk")
    own = tmp_path / "g1_walk.npz"
    own.write_bytes(b"")
    monkeypatch.chdir(tmp_path)
    assert resolve_clip("g1_walk.npz") == "g1_walk.npz"


def test_missing_keys_and_bad_shapes(tmp_path):
    np.savez(tmp_path / "partial.npz", fps=np.array(50.0))
    with pytest.raises(
        ConfigError, match=r"missing \['joint_names', 'joint_pos', 'joint_vel', 'root_pos_w', 'root_quat_w'\]"
    ):
        MotionClip.load(tmp_path / "partial.npz")
    write_csv(tmp_path / "walk.csv", walking_frames(50.0, 0.5))
    clip = clip_from_csv(tmp_path / "walk.csv", G1_29DOF, input_fps=50.0)
    clip.body_pos_w = clip.body_pos_w[:, :5]
    clip.save(tmp_path / "bad.npz")
    with pytest.raises(ConfigError, match=r"body_pos_w has shape \(26, 5, 3\), expected \(26, 30, 3\)"):
        MotionClip.load(tmp_path / "bad.npz")


def test_csv_to_npz_script_converts_and_keeps_what_the_user_had(tmp_path):
    """mjlab's csv_to_npz.py flags: the clip the tracking env loads; bad input is one line, exit 2."""
    script = load_script(CSV_TO_NPZ)
    write_csv(tmp_path / "walk.csv", walking_frames(30.0, 1.0))
    out = script.main(
        ["--input-file", str(tmp_path / "walk.csv"), "--input-fps", "30", "--output-name", str(tmp_path / "walk")]
    )
    assert out == str(tmp_path / "walk.npz")
    clip = MotionClip.load(out)
    assert clip.fps == 50.0 and clip.num_frames == 51 and len(clip.joint_names) == JOINTS
    before = (tmp_path / "walk.npz").read_bytes()
    write_csv(tmp_path / "short.csv", walking_frames(30.0, 1.0)[:, :-6])
    for argv, message in (
        (["--input_file", str(tmp_path / "walk.csv"), "--output_name", out], "exists; pass --force"),
        (["--input_file", str(tmp_path / "short.csv"), "--output_name", out, "--force"], "23 joint columns per row"),
        (["--input_file", str(tmp_path / "nope.csv"), "--output_name", out], "no such file"),
    ):
        with pytest.raises(ConfigError, match=message):
            script.main(argv)
    assert (tmp_path / "walk.npz").read_bytes() == before  # no refusal touched the clip
    argv = ["--input_file", str(tmp_path / "short.csv"), "--output_name", str(tmp_path / "short")]
    done = subprocess.run([sys.executable, CSV_TO_NPZ, *argv], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stderr.startswith("csv_to_npz.py: error: ") and done.stderr.count("\n") == 1
    assert not (tmp_path / "short.npz").exists()


def test_a_clip_without_body_states_gets_the_converters_by_forward_kinematics(tmp_path):
    """Saved with the root in place of the body states, a converted clip loads as it was converted
    (float32 storage of the root and angles: within 1e-6 m, 1e-6, 1e-5 m/s and rad/s); a full clip
    loads as stored, without the model."""
    write_csv(tmp_path / "walk.csv", walking_frames(30.0, 2.0))
    clip = clip_from_csv(tmp_path / "walk.csv", G1_29DOF, input_fps=30.0, output_fps=50.0)
    clip.save(tmp_path / "full.npz")
    clip.save(tmp_path / "root.npz", body_states=False)
    with np.load(tmp_path / "root.npz") as stored:
        assert not {"body_names", "body_pos_w", "body_quat_w"} & set(stored.files)
        assert stored["root_pos_w"].shape == (101, 3) and stored["root_quat_w"].shape == (101, 4)
    assert (tmp_path / "root.npz").stat().st_size < (tmp_path / "full.npz").stat().st_size / 4
    filled = MotionClip.load(tmp_path / "root.npz", mjcf=G1_29DOF)
    assert filled.body_names == clip.body_names and filled.joint_names == clip.joint_names
    np.testing.assert_array_equal(filled.joint_pos, clip.joint_pos)
    np.testing.assert_array_equal(filled.joint_vel, clip.joint_vel)
    for key, tolerance in (
        ("body_pos_w", 1e-6),
        ("body_quat_w", 1e-6),
        ("body_lin_vel_w", 1e-5),
        ("body_ang_vel_w", 1e-5),
    ):
        np.testing.assert_allclose(getattr(filled, key), getattr(clip, key), atol=tolerance, rtol=0, err_msg=key)
    full = MotionClip.load(tmp_path / "full.npz")
    for key in ("body_pos_w", "body_quat_w", "body_lin_vel_w", "body_ang_vel_w"):
        np.testing.assert_array_equal(getattr(full, key), getattr(clip, key))


def test_body_states_are_all_or_none_and_filling_them_needs_the_robots_model(tmp_path):
    write_csv(tmp_path / "walk.csv", walking_frames(50.0, 0.5))
    clip_from_csv(tmp_path / "walk.csv", G1_29DOF, input_fps=50.0).save(tmp_path / "full.npz")
    with np.load(tmp_path / "full.npz") as full:
        arrays = {k: full[k] for k in full.files if k not in ("body_lin_vel_w", "body_ang_vel_w")}
    np.savez(tmp_path / "some.npz", **arrays)
    with pytest.raises(
        ConfigError,
        match=r"has \['body_names', 'body_pos_w', 'body_quat_w'\] but not"
        r" \['body_lin_vel_w', 'body_ang_vel_w'\]; a clip stores all of",
    ):
        MotionClip.load(tmp_path / "some.npz", mjcf=G1_29DOF)
    MotionClip.load(tmp_path / "full.npz").save(tmp_path / "root.npz", body_states=False)
    with pytest.raises(ConfigError, match=r"stores the root and no body states; .*MotionClip.load\(path, mjcf=...\)"):
        MotionClip.load(tmp_path / "root.npz")
    with pytest.raises(ConfigError, match=r"the clip's joints .* are not those of .*unitree_h1.xml"):
        MotionClip.load(tmp_path / "root.npz", mjcf=f"{ASSETS_DIR}/unitree_h1.xml")


# Body states stored in the shipped clips before they were saved without them (the full format, made by
# clip_from_csv), where a body moves fastest: position, quaternion (w x y z), linear and angular velocity.
STORED_BODY_STATES = {
    ("g1_turn", 198, "left_hip_pitch_link"): (
        (-0.032422, -0.029061, 0.637300),
        (0.951419, 0.048565, -0.212191, 0.217756),
        (0.210425, -0.398025, 0.000000),
        (-0.097345, 0.201520, 0.000000),
    ),
    ("g1_turn", 71, "left_hip_yaw_link"): (
        (0.045256, 0.018750, 0.536198),
        (0.922213, 0.170405, -0.324023, 0.124479),
        (-0.142360, 0.037675, -0.101776),
        (-0.397853, 0.708421, 1.144158),
    ),
    ("g1_twist", 13, "left_wrist_yaw_link"): (
        (0.044014, 0.325043, 0.786166),
        (0.873188, 0.161948, 0.380704, 0.257644),
        (-0.087349, 0.369465, 0.290643),
        (1.200607, -0.362731, 1.029492),
    ),
    ("g1_twist", 10, "right_shoulder_roll_link"): (
        (0.005793, -0.151323, 1.033791),
        (0.942330, -0.181501, 0.252338, 0.124088),
        (0.254359, -0.005271, -0.088541),
        (-0.718196, 1.649078, 1.349585),
    ),
    ("g1_walk", 225, "left_ankle_pitch_link"): (
        (0.300000, 0.113998, 0.103971),
        (0.991606, 0.129295, 0.000000, 0.000000),
        (0.783966, 0.000587, 0.000155),
        (-0.034425, -0.000014, -0.000001),
    ),
    ("g1_walk", 232, "left_knee_link"): (
        (0.438132, 0.041584, 0.367485),
        (0.990419, 0.122855, 0.062581, 0.007763),
        (-0.232151, 0.004254, -0.155451),
        (-0.096730, -2.655920, -0.669472),
    ),
    ("g1_wave", 19, "right_wrist_yaw_link"): (
        (0.222473, -0.289469, 0.887229),
        (0.951396, -0.292442, 0.052650, -0.080939),
        (0.332314, 0.080451, 0.881383),
        (-1.328924, -3.409780, 1.308194),
    ),
    ("g1_wave", 50, "right_elbow_link"): (
        (0.083905, -0.286386, 1.042090),
        (0.851283, -0.400332, -0.220254, -0.257954),
        (-0.000375, 0.000000, 0.049025),
        (-2.883491, -2.559583, 2.660643),
    ),
}


@pytest.mark.parametrize("name", ["g1_turn", "g1_twist", "g1_walk", "g1_wave"])
def test_shipped_clips_body_states_are_those_they_stored(name):
    """The shipped clips store their root and joints; forward kinematics gives back the body states they
    stored before (to 1e-5 m, 1e-5 in quaternions, 1e-4 m/s and rad/s; the values above have 6 decimals)."""
    with np.load(resolve_clip(name)) as stored:
        assert "root_pos_w" in stored.files and "body_pos_w" not in stored.files
    clip = MotionClip.load(name, mjcf=G1_29DOF)
    assert clip.body_names[0] == "pelvis" and len(clip.body_names) == 30
    for (clip_name, frame, body), values in STORED_BODY_STATES.items():
        if clip_name != name:
            continue
        b = clip.body_names.index(body)
        pos, quat, lin_vel, ang_vel = values
        np.testing.assert_allclose(clip.body_pos_w[frame, b], pos, atol=1e-5, rtol=0)
        np.testing.assert_allclose(clip.body_quat_w[frame, b], quat, atol=1e-5, rtol=0)
        np.testing.assert_allclose(clip.body_lin_vel_w[frame, b], lin_vel, atol=1e-4, rtol=0)
        np.testing.assert_allclose(clip.body_ang_vel_w[frame, b], ang_vel, atol=1e-4, rtol=0)
