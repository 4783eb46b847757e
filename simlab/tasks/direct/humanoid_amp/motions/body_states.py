"""The body states of a humanoid motion from its root and joint states, by MuJoCo's forward kinematics.

A motion file may store its root (the model's free-joint body) and joint states in place of the body
states (:mod:`.motion_file`); these functions fill them back. Velocities come in two kinds, as the
two sources of clips make them:

* recorded from the simulator (``scripts/tools/record_motion_clip.py``): every body's velocity is the
  velocity of the tree moving with the root's and the joints' velocities, which forward kinematics
  gives exactly (:func:`body_velocities`);
* made by the kinematic generator (:mod:`.kinematic_clips`): finite differences of the body poses
  (:func:`finite_difference_velocities`), which differ from the former by up to 0.25 m/s in a run.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from simlab.utils.errors import ConfigError

__all__ = ["HumanoidKinematics", "angular_velocities", "finite_difference_velocities"]


class HumanoidKinematics:
    """Forward kinematics of a floating-base model for a clip's joint and body names (any order)."""

    def __init__(self, mjcf: str, dof_names: Sequence[str], body_names: Sequence[str], where: str = "motion") -> None:
        self.model = mujoco.MjModel.from_xml_path(mjcf)
        self.data = mujoco.MjData(self.model)
        model = self.model
        if model.njnt == 0 or model.jnt_type[0] != mujoco.mjtJoint.mjJNT_FREE:
            raise ConfigError(f"{mjcf}: forward kinematics of a motion needs a floating base (a free joint first).")
        self.root_name = model.body(model.jnt_bodyid[0]).name
        hinges = [model.joint(j).name for j in range(1, model.njnt)]
        if sorted(dof_names) != sorted(hinges):
            raise ConfigError(
                f"{where}: its dof_names {sorted(dof_names)} are not the joints of {mjcf} {sorted(hinges)};"
                " its body states are filled by that model's forward kinematics."
            )
        bodies = [model.body(b).name for b in range(1, model.nbody)]
        unknown = [name for name in body_names if name not in bodies]
        if unknown:
            raise ConfigError(f"{where}: body_names {unknown} are not bodies of {mjcf}; its bodies: {bodies}.")
        joints = [model.joint(name).id for name in dof_names]
        self._qpos = model.jnt_qposadr[joints]
        self._dofs = model.jnt_dofadr[joints]
        self._bodies = np.array([model.body(name).id for name in body_names])

    def body_poses(
        self, root_positions: np.ndarray, root_rotations: np.ndarray, dof_positions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Body positions (F, B, 3) and quaternions (F, B, 4, w x y z) of F frames of root poses and joint angles."""
        positions, rotations = [], []
        for f in range(len(dof_positions)):
            self._pose(root_positions[f], root_rotations[f], dof_positions[f])
            positions.append(self.data.xpos[self._bodies].copy())
            rotations.append(self.data.xquat[self._bodies].copy())
        return np.array(positions), np.array(rotations)

    def body_velocities(
        self,
        root_positions: np.ndarray,
        root_rotations: np.ndarray,
        dof_positions: np.ndarray,
        root_linear_velocities: np.ndarray,
        root_angular_velocities: np.ndarray,
        dof_velocities: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray]:
        """World-frame velocities of the body frame origins (F, B, 3) and angular velocities (F, B, 3), for
        the root's origin moving at ``root_linear_velocities`` and turning at ``root_angular_velocities``
        (world frame) and the joints at ``dof_velocities``: what the simulator reports in that state."""
        model, data = self.model, self.data
        linear, angular = [], []
        for f in range(len(dof_positions)):
            self._pose(root_positions[f], root_rotations[f], dof_positions[f])
            data.qvel[:] = 0.0
            data.qvel[0:3] = root_linear_velocities[f]
            # the free joint holds its angular velocity in the root's own frame
            data.qvel[3:6] = data.xmat[model.jnt_bodyid[0]].reshape(3, 3).T @ root_angular_velocities[f]
            data.qvel[self._dofs] = dof_velocities[f]
            mujoco.mj_comPos(model, data)
            mujoco.mj_comVel(model, data)
            # cvel is (angular, linear) at the tree's centre of mass: move the linear part to each origin
            omega = data.cvel[self._bodies, 0:3]
            offset = data.xpos[self._bodies] - data.subtree_com[model.body_rootid[self._bodies]]
            linear.append(data.cvel[self._bodies, 3:6] + np.cross(omega, offset))
            angular.append(omega.copy())
        return np.array(linear), np.array(angular)

    def _pose(self, root_position: np.ndarray, root_rotation: np.ndarray, dof_position: np.ndarray) -> None:
        self.data.qpos[0:3], self.data.qpos[3:7] = root_position, root_rotation  # kinematics normalizes it
        self.data.qpos[self._qpos] = dof_position
        mujoco.mj_kinematics(self.model, self.data)


def finite_difference_velocities(
    positions: np.ndarray, rotations: np.ndarray, fps: float
) -> tuple[np.ndarray, np.ndarray]:
    """Linear (F, B, 3) and world-frame angular velocities (F, B, 3) of body tracks by central
    differences (one-sided at the ends), as the kinematic clip generator makes them."""
    dt = 1.0 / fps
    return np.gradient(positions, dt, axis=0), angular_velocities(rotations, dt)


def angular_velocities(quats: np.ndarray, dt: float) -> np.ndarray:
    """World-frame angular velocities (F, B, 3) of quaternion tracks (F, B, 4): 2 dq/dt q^-1."""
    quats = quats.copy()
    for f in range(1, len(quats)):  # one sign along each track, so differences are small
        flip = (quats[f] * quats[f - 1]).sum(-1) < 0
        quats[f, flip] *= -1
    dq = np.gradient(quats, dt, axis=0)
    conj = quats * np.array([1.0, -1.0, -1.0, -1.0])
    return 2.0 * quat_multiply(dq, conj)[..., 1:]


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products of (..., 4) quaternions (w, x, y, z)."""
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )
