"""Checks of the MJCF robot models in simlab/robots/assets.

Each model must compile alone, hold exactly one root body (the robot) and nothing else (no
actuators, ground or lights), use radians, expose Isaac Lab's joint and body names in MuJoCo's
depth-first order, have the expected masses, and simulate stably above a ground plane at the
tasks' physics step (1/120 s, as in Isaac Lab's classic tasks).
"""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

ASSETS = Path(__file__).resolve().parents[1] / "simlab" / "robots" / "assets"
DT = 1.0 / 120.0  # sim.dt of Isaac Lab's cartpole / humanoid / ant / cart-double-pendulum tasks

CARTPOLE_JOINTS = ["slider_to_cart", "cart_to_pole"]
CART_DOUBLE_PENDULUM_JOINTS = ["slider_to_cart", "cart_to_pole", "pole_to_pendulum"]
ANT_JOINTS = [
    "front_left_leg",
    "front_left_foot",
    "front_right_leg",
    "front_right_foot",
    "left_back_leg",
    "left_back_foot",
    "right_back_leg",
    "right_back_foot",
]
ANT_BODIES = ["torso"] + ANT_JOINTS  # each joint is named after the body it moves
HUMANOID_JOINTS = [
    "lower_waist:0",
    "lower_waist:1",
    "pelvis",
    "right_thigh:0",
    "right_thigh:1",
    "right_thigh:2",
    "right_shin",
    "right_foot:0",
    "right_foot:1",
    "left_thigh:0",
    "left_thigh:1",
    "left_thigh:2",
    "left_shin",
    "left_foot:0",
    "left_foot:1",
    "right_upper_arm:0",
    "right_upper_arm:2",
    "right_lower_arm",
    "left_upper_arm:0",
    "left_upper_arm:2",
    "left_lower_arm",
]
HUMANOID_BODIES = [
    "torso",
    "head",
    "lower_waist",
    "pelvis",
    "right_thigh",
    "right_shin",
    "right_foot",
    "left_thigh",
    "left_shin",
    "left_foot",
    "right_upper_arm",
    "right_lower_arm",
    "right_hand",
    "left_upper_arm",
    "left_lower_arm",
    "left_hand",
]
# Isaac Lab's HumanoidEnvCfg.joint_gears, by joint name.
HUMANOID_GEARS = {
    "lower_waist:0": 67.5,
    "lower_waist:1": 67.5,
    "pelvis": 67.5,
    "right_thigh:0": 45.0,
    "right_thigh:1": 135.0,
    "right_thigh:2": 45.0,
    "right_shin": 90.0,
    "right_foot:0": 22.5,
    "right_foot:1": 22.5,
    "left_thigh:0": 45.0,
    "left_thigh:1": 135.0,
    "left_thigh:2": 45.0,
    "left_shin": 90.0,
    "left_foot:0": 22.5,
    "left_foot:1": 22.5,
    "right_upper_arm:0": 67.5,
    "right_upper_arm:2": 67.5,
    "right_lower_arm": 45.0,
    "left_upper_arm:0": 67.5,
    "left_upper_arm:2": 67.5,
    "left_lower_arm": 45.0,
}

GO2_JOINTS = [f"{leg}_{part}_joint" for leg in ("FL", "FR", "RL", "RR") for part in ("hip", "thigh", "calf")]
ANYMAL_C_JOINTS = [f"{leg}_{part}" for leg in ("LF", "LH", "RF", "RH") for part in ("HAA", "HFE", "KFE")]

MODELS = {
    # file: (root body, free base?, hinge/slide joints in depth-first order)
    "cartpole.xml": ("slider", False, CARTPOLE_JOINTS),
    "cart_double_pendulum.xml": ("slider", False, CART_DOUBLE_PENDULUM_JOINTS),
    "ant.xml": ("torso", True, ANT_JOINTS),
    "humanoid.xml": ("torso", True, HUMANOID_JOINTS),
    "unitree_go2.xml": ("base", True, GO2_JOINTS),
    "anybotics_anymal_c.xml": ("base", True, ANYMAL_C_JOINTS),
}

PREFIX = "robot/"


def load(name: str) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(ASSETS / name))


def body_mass(model: mujoco.MjModel, name: str) -> float:
    return float(model.body_mass[model.body(name).id])


def joint_names(model: mujoco.MjModel, types=None) -> list[str]:
    types = None if types is None else {int(t) for t in types}
    return [model.joint(i).name for i in range(model.njnt) if types is None or int(model.jnt_type[i]) in types]


def in_scene(name: str, height: float) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The robot attached (names prefixed 'robot/') above a ground plane, as a scene would build it."""
    child = mujoco.MjSpec.from_file(str(ASSETS / name))
    root = MODELS[name][0]
    spec = mujoco.MjSpec()
    spec.option.timestep = DT
    spec.worldbody.add_geom(name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[20, 20, 0.1])
    frame = spec.worldbody.add_frame(pos=[0, 0, height])
    frame.attach_body(child.body(root), PREFIX, "")
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def set_joint(model, data, name: str, value: float) -> None:
    data.qpos[model.jnt_qposadr[model.joint(PREFIX + name).id]] = value


def run(model, data, nstep: int, record_body: str | None = None) -> np.ndarray:
    heights = []
    for _ in range(nstep):
        mujoco.mj_step(model, data)
        assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel)), "simulation diverged"
        if record_body is not None:
            heights.append(data.xpos[model.body(PREFIX + record_body).id][2])
    assert data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number == 0
    return np.asarray(heights)


# ----------------------------------------------------------------------------------------------
# structure
# ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(MODELS))
def test_structure(name):
    root, free, joints = MODELS[name]
    spec = mujoco.MjSpec.from_file(str(ASSETS / name))
    assert not spec.compiler.degree, "use <compiler angle='radian'/>"
    children = spec.worldbody.bodies
    assert [b.name for b in children] == [root], "exactly one root body under <worldbody>"
    assert len(spec.worldbody.geoms) == 0 and len(spec.worldbody.sites) == 0
    assert len(spec.lights) == 0, "lights belong to the scene"

    model = load(name)
    assert model.nu == 0, "no actuators: simlab adds them from the config"
    assert model.nlight == 0
    assert not np.any(model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE), "no ground in a robot file"
    assert model.body(1).name == root and model.body_parentid[1] == 0

    hinge_slide = (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)
    assert joint_names(model, hinge_slide) == joints
    if free:
        assert model.njnt == len(joints) + 1
        assert model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE and model.joint(0).name == "root"
        assert model.jnt_bodyid[0] == model.body(root).id
    else:
        assert model.njnt == len(joints)
        assert model.body(root).dofnum[0] == 0, "fixed base"
    # every geom is named (contact sensors and debugging refer to them)
    assert all(model.geom(i).name for i in range(model.ngeom))
    # joint ranges in radians: nothing wider than 1.5 turns (ANYmal's HFE/KFE: +-3 pi, as in its URDF)
    for i in range(model.njnt):
        if model.jnt_limited[i] and model.jnt_type[i] == mujoco.mjtJoint.mjJNT_HINGE:
            lo, hi = model.jnt_range[i]
            assert -3 * math.pi - 1e-3 <= lo < hi <= 3 * math.pi + 1e-3


def test_cartpole_facts():
    model = load("cartpole.xml")
    assert [model.body(i).name for i in range(1, model.nbody)] == ["slider", "cart", "pole"]
    assert body_mass(model, "cart") == pytest.approx(1.0)
    assert body_mass(model, "pole") == pytest.approx(1.0)
    slider = model.joint("slider_to_cart")
    assert slider.type[0] == mujoco.mjtJoint.mjJNT_SLIDE
    assert slider.limited[0] and np.allclose(slider.range, [-4.0, 4.0])
    pole = model.joint("cart_to_pole")
    assert pole.type[0] == mujoco.mjtJoint.mjJNT_HINGE and not pole.limited[0]
    # the pole turns in the vertical plane that holds the rail
    rail_axis = slider.axis
    assert abs(np.dot(pole.axis, rail_axis)) < 1e-9 and abs(pole.axis[2]) < 1e-9
    # no damping/friction in the model (the config's actuator adds damping 10 on the slider)
    assert np.all(model.dof_damping == 0) and np.all(model.dof_frictionloss == 0)
    # rail ~8 m long along the slide axis
    rail = model.geom("rail")
    assert 2 * rail.size[int(np.argmax(np.abs(rail_axis)))] == pytest.approx(8.0)
    # no contacts at all
    assert np.all(model.geom_contype == 0) and np.all(model.geom_conaffinity == 0)
    # pole points up at angle 0 and is about 1 m long
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    pole_geom = model.geom("pole").id
    top = data.geom_xpos[pole_geom] + data.geom_xmat[pole_geom].reshape(3, 3) @ [
        0,
        0,
        model.geom_size[pole_geom][2],
    ]
    hinge = data.xanchor[pole.id]
    assert top[2] - hinge[2] == pytest.approx(0.97, abs=0.05)


def test_cart_double_pendulum_facts():
    model = load("cart_double_pendulum.xml")
    assert [model.body(i).name for i in range(1, model.nbody)] == ["slider", "cart", "pole", "pendulum"]
    for body in ("cart", "pole", "pendulum"):
        assert body_mass(model, body) == pytest.approx(1.0)
    assert np.allclose(model.joint("slider_to_cart").range, [-4.0, 4.0])
    assert not model.joint("cart_to_pole").limited[0] and not model.joint("pole_to_pendulum").limited[0]
    assert np.all(model.dof_damping == 0)
    assert np.all(model.geom_contype == 0) and np.all(model.geom_conaffinity == 0)
    # the pendulum hangs from the top of the pole and points up at angle 0
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    pole_anchor = data.xanchor[model.joint("cart_to_pole").id]
    pend_anchor = data.xanchor[model.joint("pole_to_pendulum").id]
    assert pend_anchor[2] - pole_anchor[2] == pytest.approx(0.94, abs=0.05)
    assert data.xipos[model.body("pendulum").id][2] > pend_anchor[2] + 0.4


def test_ant_facts():
    model = load("ant.xml")
    assert [model.body(i).name for i in range(1, model.nbody)] == ANT_BODIES
    # nv_ant.xml geometry at density 5: torso 0.48 kg with its aux capsules, ~0.91 kg in all
    assert body_mass(model, "torso") == pytest.approx(0.484, abs=0.01)
    assert model.body_mass.sum() == pytest.approx(0.911, abs=0.02)
    for leg in ("front_left", "front_right", "left_back", "right_back"):
        hip = model.joint(f"{leg}_leg")
        assert np.allclose(hip.range, [-math.radians(40), math.radians(40)], atol=1e-5)
        assert np.allclose(hip.axis, [0, 0, 1])
    # ANT_CFG's default foot angles (+-45 deg) lie inside the ankle limits
    defaults = {
        "front_left_foot": 0.785398,
        "front_right_foot": -0.785398,
        "left_back_foot": -0.785398,
        "right_back_foot": 0.785398,
    }
    for name, q in defaults.items():
        lo, hi = model.joint(name).range
        assert lo < q < hi and hi - lo == pytest.approx(math.radians(70), abs=1e-5)
    # legs touch the ground but not each other
    assert np.all(model.geom_contype == 1) and np.all(model.geom_conaffinity == 0)


def test_humanoid_facts():
    model = load("humanoid.xml")
    assert [model.body(i).name for i in range(1, model.nbody)] == HUMANOID_BODIES
    # MuJoCo's humanoid is ~40 kg; nv_humanoid (Isaac Lab's) at density 1000 is 40.8 kg
    assert 38.0 < model.body_mass.sum() < 44.0
    assert 5.0 < body_mass(model, "torso") < 7.0
    assert set(HUMANOID_GEARS) == set(HUMANOID_JOINTS)
    # a few ranges of Isaac Lab's humanoid (radians)
    expected = {
        "lower_waist:0": (-0.7854, 0.7854),
        "lower_waist:1": (-1.3090, 0.5236),
        "pelvis": (-0.6109, 0.6109),
        "right_thigh:0": (-0.7854, 0.2618),
        "right_thigh:1": (-2.0944, 0.7854),
        "right_thigh:2": (-1.0472, 0.6109),
        "left_shin": (-2.7925, 0.0349),
        "left_foot:1": (-0.8727, 0.8727),
        "right_upper_arm:2": (-1.5708, 1.2217),
        "left_lower_arm": (-1.5708, 0.8727),
    }
    for name, rng in expected.items():
        assert np.allclose(model.joint(name).range, rng, atol=1e-4), name
    for i in range(1, model.njnt):
        assert model.jnt_limited[i], model.joint(i).name
    # all geoms collide with the ground and each other (Isaac Lab enables self-collisions)
    assert np.all(model.geom_contype == 1) and np.all(model.geom_conaffinity == 1)


# ----------------------------------------------------------------------------------------------
# simulation above a ground plane
# ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(MODELS))
def test_stable_above_ground(name):
    height = {
        "cartpole.xml": 2.0,
        "cart_double_pendulum.xml": 2.0,
        "ant.xml": 0.5,
        "humanoid.xml": 1.34,
        "unitree_go2.xml": 0.5,  # above its straight legs
        "anybotics_anymal_c.xml": 0.7,
    }[name]
    model, data = in_scene(name, height)
    assert model.nu == 0
    if name.startswith("cart"):
        set_joint(model, data, "cart_to_pole", 0.3)
    run(model, data, 500)


def test_cartpole_falls_and_never_touches():
    model, data = in_scene("cartpole.xml", 2.0)
    set_joint(model, data, "cart_to_pole", 0.1)
    run(model, data, 240)
    # the unactuated pole falls over (past horizontal, it is unlimited) ...
    assert abs(data.qpos[model.jnt_qposadr[model.joint(PREFIX + "cart_to_pole").id]]) > math.pi / 2
    # ... and nothing ever collides
    assert data.ncon == 0


def test_humanoid_falls_with_zero_controls():
    model, data = in_scene("humanoid.xml", 1.34)
    heights = run(model, data, int(3.0 / DT), record_body="torso")
    assert heights[0] > 1.3
    assert heights.min() < 0.8, "the humanoid should collapse without actuation"
    # it lies on the ground: contacts with the plane, torso not below the ground
    ground = model.geom("ground").id
    assert any(ground in (c.geom1, c.geom2) for c in data.contact[: data.ncon])
    assert heights[-1] > 0.05


def test_humanoid_feet_touch_ground():
    model, data = in_scene("humanoid.xml", 1.34)
    ground = model.geom("ground").id
    foot_bodies = {model.body(PREFIX + b).id for b in ("right_foot", "left_foot")}
    touched = False
    for _ in range(30):  # the feet hang ~5 cm above the ground: they land within a quarter second
        mujoco.mj_step(model, data)
        for c in data.contact[: data.ncon]:
            other = c.geom2 if c.geom1 == ground else c.geom1 if c.geom2 == ground else None
            if other is not None and model.geom_bodyid[other] in foot_bodies:
                touched = True
    assert touched


def test_ant_rests_on_its_legs():
    model, data = in_scene("ant.xml", 0.5)
    # ANT_CFG's default joint positions
    for name, q in {
        "front_left_foot": 0.785398,
        "front_right_foot": -0.785398,
        "left_back_foot": -0.785398,
        "right_back_foot": 0.785398,
    }.items():
        set_joint(model, data, name, q)
    heights = run(model, data, int(3.0 / DT), record_body="torso")
    assert heights[-1] > 0.2, "the torso should rest on the legs"
    assert abs(heights[-1] - heights[-30]) < 0.01, "the ant should have settled"
    # only leg/foot geoms touch the ground, never the torso sphere, and no self-contacts
    ground = model.geom("ground").id
    torso_sphere = model.geom(PREFIX + "torso_geom").id
    for c in data.contact[: data.ncon]:
        assert ground in (c.geom1, c.geom2)
        assert torso_sphere not in (c.geom1, c.geom2)
    assert data.ncon >= 3


@pytest.mark.parametrize(
    "config",
    ["anymal:ANYMAL_C_CFG", "unitree:UNITREE_GO2_CFG", "ant:ANT_CFG", "humanoid:HUMANOID_CFG", "cartpole:CARTPOLE_CFG"],
)
def test_robot_configs_carry_articulation_props_as_isaac_labs_do(config):
    """Ported task configs edit them (``robot.spawn.articulation_props.solver_position_iteration_count = 32``)."""
    import importlib

    module, name = config.split(":")
    cfg = getattr(importlib.import_module(f"simlab.robots.{module}"), name).copy()
    cfg.spawn.articulation_props.solver_position_iteration_count = 32
    assert cfg.spawn.articulation_props.fix_root_link is None  # the model's own base, floating or fixed
