"""Spawners that read robot files (MJCF, URDF) and the ground plane.

A robot file holds one root body under its ``<worldbody>``. It is attached to the scene's spec
under the name prefix ``<Name>/`` (``Name`` is the last element of the prim path, so
``{ENV_REGEX_NS}/Robot`` gives joints ``Robot/<joint>``). A root body without a free joint is a
fixed base; it becomes a MuJoCo mocap body so that writing its root pose still moves it.
"""

from __future__ import annotations

import os
import re
from typing import TYPE_CHECKING

import mujoco

from simlab.utils.assets import refuse_remote_path
from simlab.utils.errors import ConfigError

from ...simulation_context import current_spec

if TYPE_CHECKING:
    from ..spawner_cfg import RigidObjectSpawnerCfg
    from .from_files_cfg import GroundPlaneCfg, MjcfFileCfg, UrdfFileCfg


def entity_name(prim_path: str) -> str:
    """The name an entity gets in the model: the last element of its prim path."""
    name = prim_path.rstrip("/").split("/")[-1]
    if not name or any(c in name for c in "*.[]()"):
        raise ValueError(f"Prim path '{prim_path}' must end in a plain name, e.g. '{{ENV_REGEX_NS}}/Robot'")
    return name


def has_free_joint(body: mujoco.MjsBody) -> bool:
    return any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in body.joints)


def attach_root_body(
    child: mujoco.MjSpec, prim_path: str, translation=None, orientation=None, fix_root: bool | None = None
) -> mujoco.MjsBody:
    """Attach the single root body of ``child`` to the current spec, named ``<Name>/...``."""
    spec = current_spec()
    roots = child.worldbody.bodies
    if len(roots) != 1:
        names = [b.name for b in roots]
        raise ValueError(f"A robot file must hold exactly one root body under <worldbody>, found {names}")
    root = roots[0]
    if fix_root:
        for joint in [j for j in root.joints if j.type == mujoco.mjtJoint.mjJNT_FREE]:
            child.delete(joint)
    frame = spec.worldbody.add_frame(
        pos=list(translation) if translation is not None else [0.0, 0.0, 0.0],
        quat=list(orientation) if orientation is not None else [1.0, 0.0, 0.0, 0.0],
    )
    name = entity_name(prim_path)
    try:
        body = frame.attach_body(root, f"{name}/", "")
    except ValueError as err:
        raise ValueError(f"Cannot add '{prim_path}' to the scene (is the name '{name}' used twice?): {err}") from err
    if not has_free_joint(body):
        body.mocap = True  # a fixed base that root-pose writes can still place
    return body


def _local_file(path: str, kind: str) -> str:
    """The absolute path of a local robot file; a Nucleus/USD path gets an error naming what to use."""
    refuse_remote_path(path)
    full = os.path.expanduser(path)
    if not os.path.isfile(full):
        raise FileNotFoundError(f"{kind} file not found: '{full}'")
    return full


def spawn_from_mjcf(prim_path: str, cfg: MjcfFileCfg, translation=None, orientation=None) -> mujoco.MjsBody:
    path = _local_file(cfg.asset_path, "MJCF")
    child = mujoco.MjSpec.from_file(path)
    # Actuators come from the asset's config (ArticulationCfg.actuators), not from the file.
    if cfg.drop_actuators:
        for actuator in list(child.actuators):
            child.delete(actuator)
    fix = cfg.articulation_props.fix_root_link if cfg.articulation_props is not None else None
    root = attach_root_body(child, prim_path, translation, orientation, fix)
    if cfg.rigid_props is not None and cfg.rigid_props.disable_gravity:
        _compensate_gravity(root)
    _integrate_gyroscopic_forces(cfg)
    return root


def _compensate_gravity(root: mujoco.MjsBody) -> None:
    """Isaac Lab's ``disable_gravity``: MuJoCo's gravity compensation cancels gravity on every body."""
    for body in [root, *root.find_all(mujoco.mjtObj.mjOBJ_BODY)]:
        body.gravcomp = 1.0


def _integrate_gyroscopic_forces(cfg: RigidObjectSpawnerCfg) -> None:
    """Isaac Lab's ``enable_gyroscopic_forces``: the scene integrates with MuJoCo's ``implicit`` integrator.

    The default ``implicitfast`` leaves the gyroscopic term (w x Iw) explicit. For a light body spun
    fast (a Crazyflie, 1e-5 kg m^2, at hundreds of rad/s in 10 ms steps) that explicit term feeds
    itself: the spin runs away to thousands of rad/s where a 10x finer step stays at a few hundred.
    ``implicit`` takes the term's derivative into the step, as PhysX does when the flag is set.
    Other integrators the user chose (euler, rk4) are kept.
    """
    if cfg.rigid_props is None or not cfg.rigid_props.enable_gyroscopic_forces:
        return
    option = current_spec().option
    if option.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST:
        option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICIT


def spawn_from_urdf(prim_path: str, cfg: UrdfFileCfg, translation=None, orientation=None) -> mujoco.MjsBody:
    path = _local_file(cfg.asset_path, "URDF")
    child = mujoco.MjSpec.from_file(path)
    if cfg.merge_fixed_joints:
        child = fuse_static_bodies(child, path)
    if not cfg.fix_base:
        child.worldbody.bodies[0].add_freejoint()
    root = attach_root_body(child, prim_path, translation, orientation)
    _integrate_gyroscopic_forces(cfg)
    return root


_FUSE_KEEP = "simlab_fuse_keep"


def fuse_static_bodies(child: mujoco.MjSpec, path: str) -> mujoco.MjSpec:
    """Isaac Lab's ``merge_fixed_joints``: links joined by fixed joints become one body (MuJoCo's
    ``fusestatic``, which acts when a model compiles, not when it is attached: so compile it alone)."""
    base = os.path.dirname(path)
    child.meshdir = os.path.join(base, child.meshdir) if child.meshdir else base
    child.texturedir = os.path.join(base, child.texturedir) if child.texturedir else base
    child.compiler.fusestatic = True
    root = child.worldbody.bodies[0] if len(child.worldbody.bodies) == 1 else None
    keep = root is not None and not root.joints  # fusestatic would merge a jointless root into the world
    if keep:
        root.add_freejoint(name=_FUSE_KEEP)
    del root  # a handle into the spec must not outlive it
    child.compile()
    # the placeholder joint is cut from the text (deleting spec elements leaves Python handles to freed memory)
    fused = mujoco.MjSpec.from_string(re.sub(rf'\s*<joint name="{_FUSE_KEEP}" type="free"/>', "", child.to_xml()))
    fused.compiler.fusestatic = False  # done: a later compile must not merge the (jointless) root into the world
    return fused


GROUND_PLANE_MATERIAL = "ground_plane_grid"
"""The last part of the material name of a ground :func:`spawn_ground_plane` made: renders of several
envs know the ground every env's world holds by it (and draw it once)."""


def spawn_ground_plane(prim_path: str, cfg: GroundPlaneCfg, translation=None, orientation=None) -> mujoco.MjsGeom:
    """An infinite plane at z = 0 (plus ``translation``) with a checker texture."""
    spec = current_spec()
    name = entity_name(prim_path)
    tex = spec.add_texture(
        name=f"{name}/checker",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        rgb1=[c * 1.0 for c in cfg.color],
        rgb2=[c * 0.8 for c in cfg.color],
        width=256,
        height=256,
    )
    material = spec.add_material(
        name=f"{name}/{GROUND_PLANE_MATERIAL}", texrepeat=[1.0, 1.0], texuniform=True, reflectance=0.05
    )
    material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex.name
    return spec.worldbody.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[cfg.size[0] / 2, cfg.size[1] / 2, 0.1],
        pos=list(translation) if translation is not None else [0.0, 0.0, 0.0],
        friction=cfg.physics_material.friction(),
        material=material.name,
    )


def spawn_from_usd(prim_path, cfg, translation=None, orientation=None):
    """USD is not read: a Nucleus path of a robot or prop simlab ships spawns simlab's model of it
    (``usd_stand_ins.USD_STAND_INS``); any other path raises, listing what is available."""
    from .usd_stand_ins import stand_in, unknown_usd_message

    spawn = stand_in(cfg)
    if spawn is None:
        raise ConfigError(f"{prim_path}: {unknown_usd_message(cfg.usd_path)}")
    return spawn.func(prim_path, spawn, translation, orientation)
