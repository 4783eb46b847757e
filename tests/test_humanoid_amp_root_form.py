"""AMP motion files that store the root and joint states only: the loader fills the body states by
forward kinematics of the humanoid (``motions/body_states.py``), and the writer stores that form only
where it gives the body states back."""

from __future__ import annotations

import os

import mujoco
import numpy as np
import pytest

from simlab.tasks.direct.humanoid_amp.motions import MOTIONS_DIR
from simlab.tasks.direct.humanoid_amp.motions.motion_file import (
    BODY_STATE_KEYS,
    HUMANOID_XML,
    MOTION_KEYS,
    ROOT_KEYS,
    ROOT_VELOCITY_KEYS,
    body_state_errors,
    read_motion_file,
    write_motion_file,
)
from simlab.tasks.direct.humanoid_amp.motions.motion_loader import MotionLoader

SHIPPED = {  # clip: whether its velocities are the simulator's (stored with root velocities)
    "walk_recorded": True,
    "run_recorded": True,
    "walk": False,
    "run": False,
    "dance": False,
}


def _stored_keys(path: str) -> set[str]:
    with np.load(path) as data:
        return set(data.files)


@pytest.mark.parametrize("name", list(SHIPPED))
def test_shipped_clips_store_the_root_and_load_with_every_body_state(name):
    path = os.path.join(MOTIONS_DIR, f"humanoid_{name}.npz")
    stored = _stored_keys(path)
    assert not stored & set(BODY_STATE_KEYS) and set(ROOT_KEYS) <= stored
    assert (set(ROOT_VELOCITY_KEYS) <= stored) == SHIPPED[name]
    clip = read_motion_file(path)
    frames, bodies = len(clip["dof_positions"]), len(clip["body_names"])
    assert set(MOTION_KEYS) <= set(clip) and bodies == 16
    assert [clip[key].shape for key in BODY_STATE_KEYS] == [(frames, bodies, 3), (frames, bodies, 4)] + [
        (frames, bodies, 3)
    ] * 2
    assert all(clip[key].dtype == np.float32 for key in MOTION_KEYS[3:])
    motion = MotionLoader(path, "cpu")  # what the AMP env reads
    assert motion.body_positions.shape == (frames, bodies, 3)


def _origin_velocities(model: mujoco.MjModel, data: mujoco.MjData, bodies: list[int]) -> tuple[np.ndarray, ...]:
    """Body origin velocities by MuJoCo's own mj_objectVelocity (at the body's centre of mass), moved to
    the body's origin: an independent formula from the loader's."""
    linear, angular = [], []
    for body in bodies:
        v = np.zeros(6)
        mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, body, v, 0)
        angular.append(v[:3])
        linear.append(v[3:] + np.cross(v[:3], data.xpos[body] - data.xipos[body]))
    return np.array(linear), np.array(angular)


def test_the_filled_body_states_are_mujocos_kinematics_of_the_same_state(tmp_path):
    """Random states of the humanoid (not a motion: the velocities are no derivatives of the poses) in a
    body and joint order of its own: written in the root form, they read back as MuJoCo computes them."""
    model = mujoco.MjModel.from_xml_path(HUMANOID_XML)
    data = mujoco.MjData(model)
    rng = np.random.default_rng(0)
    dof_names = [model.joint(j).name for j in range(1, model.njnt)][::-1]
    body_names = [model.body(b).name for b in range(1, model.nbody)]
    body_names = body_names[5:] + body_names[:5]  # the root is not first
    bodies = [model.body(name).id for name in body_names]
    frames = {key: [] for key in MOTION_KEYS[3:]}
    for _ in range(6):
        data.qpos[:3] = rng.uniform(-1.0, 1.0, 3) + [0.0, 0.0, 1.3]
        data.qpos[3:7] = rng.normal(size=4) / 2  # not unit: kinematics normalizes it, as the file's reader does
        data.qpos[7:] = rng.uniform(*model.jnt_range[1:].T)
        data.qvel[:] = rng.normal(size=model.nv)
        mujoco.mj_forward(model, data)
        linear, angular = _origin_velocities(model, data, bodies)
        adr = [model.joint(name).id for name in dof_names]
        frames["dof_positions"].append(data.qpos[model.jnt_qposadr[adr]].copy())
        frames["dof_velocities"].append(data.qvel[model.jnt_dofadr[adr]].copy())
        frames["body_positions"].append(data.xpos[bodies].copy())
        frames["body_rotations"].append(data.xquat[bodies].copy())
        frames["body_linear_velocities"].append(linear)
        frames["body_angular_velocities"].append(angular)
    clip = {"fps": 30.0, "dof_names": dof_names, "body_names": body_names}
    clip.update({key: np.array(values) for key, values in frames.items()})
    path = str(tmp_path / "states.npz")
    write_motion_file(path, **clip, body_states=False)
    stored = _stored_keys(path)
    assert set(ROOT_VELOCITY_KEYS) <= stored and not stored & set(BODY_STATE_KEYS)
    back = read_motion_file(path)
    position, velocity = body_state_errors(clip, back)
    assert position < 2e-6 and velocity < 2e-5  # float32 rounding
    assert back["body_names"].tolist() == body_names


def test_a_generated_clip_round_trips_by_finite_differences(tmp_path):
    """Velocities that are finite differences of the poses are stored without root velocities and
    rebuilt the same way; the reader then computes them from the filled poses."""
    from simlab.tasks.direct.humanoid_amp.motions.kinematic_clips import CLIPS, make_clip

    clip, _ = make_clip(CLIPS["walk"], fps=30.0)
    path = str(tmp_path / "walk.npz")
    write_motion_file(path, **clip, body_states=False)
    assert not _stored_keys(path) & {*ROOT_VELOCITY_KEYS, *BODY_STATE_KEYS}
    position, velocity = body_state_errors(clip, read_motion_file(path))
    assert position < 1e-6 and velocity < 2e-5
    assert os.path.getsize(path) * 4 < _full_size(tmp_path, clip)


def _full_size(tmp_path, clip: dict) -> int:
    path = str(tmp_path / "full.npz")
    write_motion_file(path, **clip)
    return os.path.getsize(path)


def test_root_form_errors_say_what_is_wrong(tmp_path):
    path = os.path.join(MOTIONS_DIR, "humanoid_walk_recorded.npz")
    with np.load(path) as data:
        stored = {key: data[key] for key in data.files}
    full = read_motion_file(path)

    def attempt(name: str, **arrays) -> str:
        bad = str(tmp_path / f"{name}.npz")
        np.savez(bad, **arrays)
        with pytest.raises(ValueError) as e:
            read_motion_file(bad)
        assert "\n" not in str(e.value)
        return str(e.value)

    assert "all four body arrays or none" in attempt("partial", **stored, body_positions=full["body_positions"])
    alone = {k: v for k, v in stored.items() if k != "root_angular_velocities"}
    assert "root_linear_velocities alone" in attempt("alone", **alone)
    no_root = {k: v for k, v in stored.items() if k != "root_rotations"}
    assert "lacks ['root_rotations']" in attempt("no_root", **no_root)
    renamed = {**stored, "dof_names": np.array(["knee", *stored["dof_names"][1:]])}
    assert "are not the joints of" in attempt("renamed", **renamed)
    short = {**stored, "root_positions": stored["root_positions"][:-1]}
    assert "root_positions has shape" in attempt("short", **short)

    # a clip whose body states are not the kinematics of its root and joints keeps them
    moved = {**full, "body_positions": full["body_positions"].copy()}
    moved["body_positions"][:, 1:] += 0.01  # every body but the root (the torso, first), 1 cm off
    with pytest.raises(ValueError, match="write it with body_states=True") as e:
        write_motion_file(str(tmp_path / "moved.npz"), **moved, body_states=False)
    assert "\n" not in str(e.value)
    write_motion_file(str(tmp_path / "moved.npz"), **moved)  # Isaac Lab's form: stored as given
    np.testing.assert_array_equal(
        read_motion_file(str(tmp_path / "moved.npz"))["body_positions"], moved["body_positions"]
    )
