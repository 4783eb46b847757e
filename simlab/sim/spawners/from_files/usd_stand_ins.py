"""What a ``UsdFileCfg`` naming one of Isaac Lab's Nucleus assets spawns here: simlab's model of it.

simlab reads no USD. Ported configs name robots and props by their Nucleus path
(``f"{ISAACLAB_NUCLEUS_DIR}/Robots/Unitree/Go2/go2.usd"``); for the ones simlab ships, :data:`USD_STAND_INS`
gives the model that spawns instead: an MJCF file of ``simlab/robots/assets`` (robots, the cabinet) or a
MuJoCo primitive (plain props). The ``UsdFileCfg``'s own settings (rigid-body, articulation, mass,
collision and contact-sensor properties) carry over, so a ported ``ArticulationCfg`` keeps its physics
settings; its actuators, initial state and joint names are the config's, which the MJCF's joint names match.

An asset is looked up by its path below the Nucleus ``Isaac`` directory (``ISAAC_NUCLEUS_DIR``): the part
after the last ``/Isaac/`` of the path, so the same asset resolves whatever server or version the path
names (``nucleus://``, ``omniverse://``, the public S3 mirror, a local copy of the tree). Isaac Lab's
own assets live under ``IsaacLab/`` there (``ISAACLAB_NUCLEUS_DIR``). Older Isaac Sim releases kept some
assets elsewhere (``Robots/Ant/`` before ``Robots/IsaacSim/Ant/``); those paths are listed too.

To add a robot: put its MJCF in ``simlab/robots/assets`` and add a row with :func:`mjcf` below.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..spawner_cfg import SpawnerCfg
    from .from_files_cfg import UsdFileCfg

MODELS_DIR = os.path.join(os.path.dirname(__file__), "..", "..", "..", "robots", "assets")
"""simlab's MJCF models (``simlab/robots/assets``), read here as data files."""

DEX_CUBE_SIZE = 0.06
"""Edge length of Isaac Lab's unscaled DexCube [m]."""

BLOCK_SIZE = 0.0468
"""Edge of Isaac Sim's stacking blocks (``Props/Blocks/{blue,red,green,yellow}_block.usd``) [m]: the height
difference of two stacked blocks in Isaac Lab's stack task's checks."""

BLOCK_COLORS = {
    "blue": (0.15, 0.3, 0.85),
    "red": (0.85, 0.15, 0.15),
    "green": (0.15, 0.7, 0.2),
    "yellow": (0.9, 0.8, 0.1),
}

TABLE_SIZE = (1.2, 1.2, 1.05)
"""simlab's stand-in for the Seattle lab table: a box, its top at the prop's origin as Isaac Lab's table
(its lift and stack scenes put the robot's base and the objects at z = 0 on it, the ground at -1.05)."""

STAND_SIZE = (0.2, 0.2, 0.515)
"""simlab's stand-in for Isaac Sim's robot stand (``Props/Mounts/Stand/stand_instanceable.usd``): a box, its
top at the prop's origin. Its height is where Isaac Lab puts it: scaled by 2 under an arm's base, 1.03 m above
the ground in Isaac Lab's arms demo (1.05 m in its diff-IK tutorial); the 20 cm square foot is simlab's own."""

ROUGH_PLANE_SIZE = 30.0
"""Side of simlab's stand-in for Isaac Sim's ``Environments/Terrains/rough_plane.usd`` [m], centred on the
origin (Isaac Lab's ray-caster tutorials place their sensors within 11 m of it)."""

ROUGH_PLANE_BUMPS = 0.1
"""Highest bump of that stand-in above its base at z = 0 [m]; 0.5 m apart, smooth between (bilinear)."""


@dataclass(frozen=True)
class UsdStandIn:
    """One row of the table: the model that spawns for a Nucleus USD file."""

    model: str
    """What spawns: an MJCF file of ``simlab/robots/assets``, or a primitive's description."""
    build: Callable[[UsdFileCfg], SpawnerCfg]
    """Makes the spawner config from the ``UsdFileCfg`` that names the asset."""
    notes: str = ""


def _carried(cfg: UsdFileCfg) -> dict:
    """The ``UsdFileCfg`` settings that mean the same on simlab's model."""
    return dict(
        rigid_props=cfg.rigid_props,
        mass_props=cfg.mass_props,
        collision_props=cfg.collision_props,
        activate_contact_sensors=cfg.activate_contact_sensors,
        visible=cfg.visible,
    )


def mjcf(file: str, notes: str = "") -> UsdStandIn:
    """A row whose model is ``simlab/robots/assets/<file>``."""

    def build(cfg: UsdFileCfg) -> SpawnerCfg:
        from simlab.utils.errors import ConfigError

        from .from_files_cfg import MjcfFileCfg

        if cfg.scale is not None and tuple(cfg.scale) != (1.0, 1.0, 1.0):
            raise ConfigError(
                f"'{cfg.usd_path}' stands in as simlab's MJCF {file}, which is not scaled: leave UsdFileCfg.scale"
                f" unset (got {tuple(cfg.scale)})."
            )
        return MjcfFileCfg(
            asset_path=os.path.normpath(os.path.join(MODELS_DIR, file)),
            articulation_props=cfg.articulation_props,
            joint_drive_props=cfg.joint_drive_props,
            fixed_tendons_props=cfg.fixed_tendons_props,
            visual_material=cfg.visual_material,
            **_carried(cfg),
        )

    return UsdStandIn(model=file, build=build, notes=notes)


def _spawn_prop(prim_path, cfg, translation=None, orientation=None):
    """A primitive whose body is named after its prim, as the rigid body of Isaac Lab's prop is
    (``body_names == ["Object"]``, which Isaac Lab's lift events name)."""
    from ..shapes import spawn_shape
    from .from_files import entity_name

    body = spawn_shape(prim_path, cfg, translation, orientation)
    name = entity_name(prim_path)
    body.name = f"{name}/{name}"
    return body


def _spawn_table(prim_path, cfg, translation=None, orientation=None):
    body = _spawn_prop(prim_path, cfg, translation, orientation)
    body.geoms[0].pos = [0.0, 0.0, -cfg.size[2] / 2]  # the top at the prop's origin
    return body


def _dex_cube(cfg: UsdFileCfg) -> SpawnerCfg:
    from ..shapes import CuboidCfg

    scale = cfg.scale or (1.0, 1.0, 1.0)
    size = tuple(DEX_CUBE_SIZE * s for s in scale)
    return CuboidCfg(func=_spawn_prop, size=size, visual_material=cfg.visual_material, **_carried(cfg))


def _block(color: str) -> Callable[[UsdFileCfg], SpawnerCfg]:
    def build(cfg: UsdFileCfg) -> SpawnerCfg:
        from ..materials import PreviewSurfaceCfg
        from ..shapes import CuboidCfg

        scale = cfg.scale or (1.0, 1.0, 1.0)
        material = cfg.visual_material or PreviewSurfaceCfg(diffuse_color=BLOCK_COLORS[color])
        size = tuple(BLOCK_SIZE * s for s in scale)
        return CuboidCfg(func=_spawn_prop, size=size, visual_material=material, **_carried(cfg))

    return build


def _mount(size: tuple[float, float, float], color: tuple[float, float, float]) -> Callable[[UsdFileCfg], SpawnerCfg]:
    """A static box of ``size`` (scaled by UsdFileCfg.scale), its top at the prop's origin."""

    def build(cfg: UsdFileCfg) -> SpawnerCfg:
        from ..materials import PreviewSurfaceCfg
        from ..shapes import CuboidCfg

        scale = cfg.scale or (1.0, 1.0, 1.0)
        material = cfg.visual_material or PreviewSurfaceCfg(diffuse_color=color)
        return CuboidCfg(func=_spawn_table, size=tuple(t * s for t, s in zip(size, scale)), visual_material=material)

    return build


def _ground(cfg: UsdFileCfg) -> SpawnerCfg:
    from .from_files_cfg import GroundPlaneCfg

    return GroundPlaneCfg(visible=cfg.visible)


def _rough_plane(cfg: UsdFileCfg) -> SpawnerCfg:
    from .from_files_cfg import GroundPlaneCfg

    side = ROUGH_PLANE_SIZE
    return GroundPlaneCfg(func=_spawn_rough_plane, size=(side, side), visible=cfg.visible)


def _spawn_rough_plane(prim_path, cfg, translation=None, orientation=None):
    """A height field: seeded random bumps every 0.5 m, bilinear between, on a 0.1 m grid."""
    import mujoco
    import numpy as np

    from ...simulation_context import current_spec
    from .from_files import entity_name

    n, coarse = int(cfg.size[0] / 0.1) + 1, int(cfg.size[0] / 0.5) + 1
    bumps = np.random.default_rng(0).uniform(0.0, 1.0, (coarse, coarse))
    at = np.linspace(0.0, coarse - 1.0, n)
    rows = np.stack([np.interp(at, np.arange(coarse), row) for row in bumps])  # (coarse, n)
    heights = np.stack([np.interp(at, np.arange(coarse), col) for col in rows.T], axis=1)  # (n, n)
    spec, name = current_spec(), entity_name(prim_path)
    spec.add_hfield(
        name=f"{name}/heights",
        size=[cfg.size[0] / 2, cfg.size[1] / 2, ROUGH_PLANE_BUMPS, 0.1],
        nrow=n,
        ncol=n,
        userdata=heights.reshape(-1).tolist(),
    )
    return spec.worldbody.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_HFIELD,
        hfieldname=f"{name}/heights",
        pos=list(translation) if translation is not None else [0.0, 0.0, 0.0],
        friction=cfg.physics_material.friction(),
        rgba=[*cfg.color, 1.0],
    )


_ANT = mjcf("ant.xml", "IsaacGymEnvs' nv_ant, as Isaac Lab's")
_HUMANOID = mjcf("humanoid.xml", "IsaacGymEnvs' nv_humanoid, as Isaac Lab's")
_FRANKA = mjcf("franka_panda.xml")
_ALLEGRO = mjcf("allegro_hand.xml", "docs/dexterous.md")
_SHADOW = mjcf("shadow_hand.xml", "docs/dexterous.md")
_CRAZYFLIE = mjcf("crazyflie.xml")
_G1 = mjcf("unitree_g1.xml")
_H1 = mjcf("unitree_h1.xml")

USD_STAND_INS: dict[str, UsdStandIn] = {
    # Isaac Lab's robots (ISAACLAB_NUCLEUS_DIR = ISAAC_NUCLEUS_DIR/IsaacLab)
    "IsaacLab/Robots/Unitree/Go2/go2.usd": mjcf("unitree_go2.xml"),
    "IsaacLab/Robots/Unitree/H1/h1.usd": _H1,
    "IsaacLab/Robots/Unitree/H1/h1_minimal.usd": mjcf("unitree_h1.xml", "the same model as h1.usd"),
    "IsaacLab/Robots/Unitree/G1/g1.usd": _G1,
    "IsaacLab/Robots/Unitree/G1/g1_minimal.usd": mjcf("unitree_g1.xml", "the same model as g1.usd"),
    "Robots/Unitree/G1/g1.usd": mjcf("unitree_g1_29dof.xml", "Isaac Lab's G1_29DOF_CFG (locomanipulation)"),
    "IsaacLab/Robots/Unitree/Go1/go1.usd": mjcf("unitree_go1.xml"),
    "IsaacLab/Robots/Unitree/A1/a1.usd": mjcf("unitree_a1.xml"),
    "IsaacLab/Robots/ANYbotics/ANYmal-B/anymal_b.usd": mjcf("anybotics_anymal_b.xml"),
    "IsaacLab/Robots/ANYbotics/ANYmal-C/anymal_c.usd": mjcf("anybotics_anymal_c.xml"),
    "IsaacLab/Robots/ANYbotics/ANYmal-D/anymal_d.usd": mjcf("anybotics_anymal_d.xml"),
    "IsaacLab/Robots/ANYbotics/ANYmal-D/anymal_d_minimal.usd": mjcf(
        "anybotics_anymal_d.xml", "the same model as anymal_d.usd"
    ),
    "IsaacLab/Robots/Agility/Cassie/cassie.usd": mjcf(
        "agility_cassie.xml", "the achilles rods as equality constraints; docs/locomotion.md"
    ),
    "IsaacLab/Robots/FrankaEmika/panda_instanceable.usd": _FRANKA,
    "IsaacLab/Robots/UniversalRobots/UR10/ur10_instanceable.usd": mjcf("universal_robots_ur10.xml"),
    "IsaacLab/Robots/Flexiv/Rizon4s/rizon4s.usd": mjcf("flexiv_rizon4s.xml"),
    "IsaacLab/Robots/Classic/Cartpole/cartpole.usd": mjcf("cartpole.xml"),
    "IsaacLab/Robots/Classic/CartDoublePendulum/cart_double_pendulum.usd": mjcf("cart_double_pendulum.xml"),
    "IsaacLab/Robots/Classic/Humanoid28/humanoid_28.usd": mjcf(
        "humanoid_28.xml", "IsaacGymEnvs' AMP humanoid, as Isaac Lab's"
    ),
    # Isaac Sim's robots that Isaac Lab uses (ISAAC_NUCLEUS_DIR)
    "Robots/IsaacSim/Ant/ant_instanceable.usd": _ANT,
    "Robots/Ant/ant_instanceable.usd": _ANT,
    "Robots/IsaacSim/Humanoid/humanoid_instanceable.usd": _HUMANOID,
    "Robots/Humanoid/humanoid_instanceable.usd": _HUMANOID,
    "Robots/Franka/franka_instanceable.usd": _FRANKA,
    "Robots/ANYbotics/anymal_instanceable.usd": mjcf(
        "anybotics_anymal_c.xml", "Isaac Sim's older ANYmal-C file (ANYMAL_C_CFG's other path, Isaac Lab's tests)"
    ),
    "Robots/BostonDynamics/spot/spot.usd": mjcf("boston_dynamics_spot.xml"),
    "Robots/UniversalRobots/ur10e/ur10e.usd": mjcf("universal_robots_ur10e.xml"),
    "Robots/OpenArm/openarm_unimanual/openarm_unimanual.usd": mjcf("enactic_openarm.xml"),
    "Robots/OpenArm/openarm_bimanual/openarm_bimanual.usd": mjcf("enactic_openarm_bimanual.xml"),
    "Robots/Agility/Digit/digit_v4.usd": mjcf(
        "agility_digit.xml", "the leg rods as equality constraints; docs/locomotion.md"
    ),
    "Robots/Bitcraze/Crazyflie/cf2x.usd": _CRAZYFLIE,
    "Robots/Crazyflie/cf2x.usd": _CRAZYFLIE,
    "Robots/WonikRobotics/AllegroHand/allegro_hand_instanceable.usd": _ALLEGRO,
    "Robots/AllegroHand/allegro_hand_instanceable.usd": _ALLEGRO,
    "Robots/ShadowRobot/ShadowHand/shadow_hand_instanceable.usd": _SHADOW,
    "Robots/ShadowHand/shadow_hand_instanceable.usd": _SHADOW,
    # props
    "Props/Sektion_Cabinet/sektion_cabinet_instanceable.usd": mjcf("sektion_cabinet.xml", "Isaac Lab's joint names"),
    "Props/Blocks/DexCube/dex_cube_instanceable.usd": UsdStandIn(
        "a 6 cm box", _dex_cube, "scaled by UsdFileCfg.scale; dynamic when rigid_props are given"
    ),
    **{
        f"Props/Blocks/{color}_block.usd": UsdStandIn(
            f"a {BLOCK_SIZE * 100:.2f} cm {color} box",
            _block(color),
            "scaled by UsdFileCfg.scale; the stack task's cubes",
        )
        for color in BLOCK_COLORS
    },
    "Props/Mounts/SeattleLabTable/table_instanceable.usd": UsdStandIn(
        "a 1.2 x 1.2 x 1.05 m box",
        _mount(TABLE_SIZE, (0.55, 0.45, 0.35)),
        "static; its top at the prop's origin, as the table's",
    ),
    "Props/Mounts/Stand/stand_instanceable.usd": UsdStandIn(
        "a 0.2 x 0.2 x 0.515 m box",
        _mount(STAND_SIZE, (0.3, 0.3, 0.32)),
        "static; scaled by UsdFileCfg.scale; its top at the prop's origin (the arm's base); the diff-IK tutorial's",
    ),
    "Environments/Grid/default_environment.usd": UsdStandIn(
        "sim_utils.GroundPlaneCfg()", _ground, "Isaac Lab's GroundPlaneCfg.usd_path"
    ),
    "Environments/Terrains/rough_plane.usd": UsdStandIn(
        f"a {ROUGH_PLANE_SIZE:.0f} x {ROUGH_PLANE_SIZE:.0f} m height field",
        _rough_plane,
        f"simlab's own bumps (seeded, up to {ROUGH_PLANE_BUMPS * 100:.0f} cm), not Isaac Sim's mesh; static",
    ),
}
"""Nucleus path below ``ISAAC_NUCLEUS_DIR`` -> simlab's model of that asset (docs/porting.md lists it)."""


def nucleus_key(usd_path: str) -> str:
    """The part of ``usd_path`` after its last ``/Isaac/`` (or the path itself when it has none)."""
    path = str(usd_path).replace("\\", "/")
    marker = "/Isaac/"
    return path[path.rindex(marker) + len(marker) :] if marker in path else path


def stand_in(cfg: UsdFileCfg) -> SpawnerCfg | None:
    """The spawner config standing in for the USD file ``cfg`` names, or None when simlab has none.

    A local MJCF file (``.xml``, what ``sim_utils.UrdfConverter`` writes) spawns as itself."""
    row = USD_STAND_INS.get(nucleus_key(cfg.usd_path))
    if row is not None and cfg.variants:
        from simlab.utils.errors import ConfigError

        raise ConfigError(
            f"'{cfg.usd_path}' stands in as {row.model}, which has one form: USD variants ({cfg.variants}) select"
            " parts of Isaac Lab's USD file; leave UsdFileCfg.variants unset."
        )
    if row is None and str(cfg.usd_path).endswith(".xml") and os.path.isfile(os.path.expanduser(cfg.usd_path)):
        row = mjcf(os.path.abspath(os.path.expanduser(cfg.usd_path)))
    return row.build(cfg) if row is not None else None


def unknown_usd_message(usd_path: str) -> str:
    """One line: the path is not one simlab stands in for, what to use, and what is available."""
    available = ", ".join(sorted({key.rsplit("/", 1)[-1] for key in USD_STAND_INS}))
    # the whole paths of the stand-ins in the same folder or of the same file name: a file name alone is
    # ambiguous (two g1.usd), and a file beside the one given is likely the one meant
    folder, _, name = nucleus_key(usd_path).lower().rpartition("/")
    near = [
        key for key in USD_STAND_INS if key.lower().rpartition("/")[0] == folder or key.lower().endswith(f"/{name}")
    ]
    hint = f" Near it, below ISAAC_NUCLEUS_DIR: {', '.join(near)}." if near else ""
    return (
        f"'{usd_path}': simlab reads MJCF and URDF, not USD; use sim_utils.MjcfFileCfg(asset_path=...) or"
        f" sim_utils.UrdfFileCfg(asset_path=...), or a Nucleus path simlab stands in for (docs/porting.md):"
        f" {available}.{hint}"
    )
