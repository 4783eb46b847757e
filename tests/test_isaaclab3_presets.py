"""Isaac Lab 3.0's presets inside task configs (issue 42.2): ``PresetCfg`` / ``preset`` slots, chosen by
``presets=``, ``physics=`` and ``env.<path>=``; MuJoCo Warp's physics configs set MuJoCo's options, other
backends' load and are refused when chosen. Isaac Lab 3.0's cartpole configs keep their physics presets
(tests/ported3/isaaclab3_cartpole) and step."""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import gymnasium as gym
import mujoco
import pytest
import torch

from simlab.cli.isaaclab3 import apply_selectors
from simlab.cli.session import load_configs
from simlab.sim import SimulationCfg, SimulationContext
from simlab.sim.physics import MJWarpSolverCfg, NewtonCfg, PhysxCfg
from simlab.tasks.utils import PresetCfg, parse_env_cfg, preset
from simlab.tasks.utils.presets import select_presets
from simlab.utils import configclass
from simlab.utils.errors import ConfigError

PORTED3 = Path(__file__).parent / "ported3"
TASK = "simlab/Test-Isaac3-Cartpole-Presets-v0"


@pytest.fixture
def ported3():
    sys.path.insert(0, str(PORTED3))
    if TASK not in gym.registry:
        gym.register(
            id=TASK,
            entry_point="simlab.v3.envs:ManagerBasedRLEnv",
            kwargs={"env_cfg_entry_point": "isaaclab3_cartpole.cartpole_manager_env_cfg:CartpoleEnvCfg"},
        )
    yield
    gym.registry.pop(TASK, None)
    sys.path.remove(str(PORTED3))
    for name in [m for m in sys.modules if m.split(".")[0].startswith("isaaclab3_")]:
        del sys.modules[name]


@configclass
class _PhysicsCfg(PresetCfg):
    default: PhysxCfg = PhysxCfg(bounce_threshold_velocity=0.2)
    newton_mjwarp: NewtonCfg = NewtonCfg(solver_cfg=MJWarpSolverCfg(iterations=7, cone="elliptic", impratio=10))


@configclass
class _Cfg:
    sim: SimulationCfg = SimulationCfg(physics=_PhysicsCfg())
    armature = preset(default=0.0, newton_mjwarp=0.01, stiff=0.1)
    camera = preset(default=None, large=(256, 256))


def test_presets_choose_by_name_path_and_physics_and_fall_back_to_default():
    cfg, _, rest = select_presets(_Cfg(), None)
    assert isinstance(cfg.sim.physics, PhysxCfg) and cfg.armature == 0.0 and cfg.camera is None
    assert rest == []
    cfg, _, _ = select_presets(_Cfg(), None, ["large"], physics="mujoco")
    # physics=mujoco takes 3.0's MuJoCo Warp slots (newton_mjwarp) everywhere they are offered
    assert cfg.sim.physics.solver_cfg.iterations == 7 and cfg.armature == 0.01 and cfg.camera == (256, 256)
    cfg, _, rest = select_presets(_Cfg(), None, [], overrides=["env.armature=stiff", "env.decimation=3"])
    assert cfg.armature == 0.1 and isinstance(cfg.sim.physics, PhysxCfg) and rest == ["env.decimation=3"]


@pytest.mark.parametrize(
    ("names", "overrides", "message"),
    [
        (["nope"], [], "presets=nope: not a preset of this task (its presets are large, newton_mjwarp, stiff)"),
        (["large", "stiff"], [], None),  # different slots: no conflict
        (
            [],
            ["env.armature=heavy"],
            "armature=heavy: not a preset there; its presets are default, newton_mjwarp, stiff",
        ),
        ([], ["env.sim.physics=default"], "The preset default chooses PhysX (Isaac Sim) at sim.physics"),
    ],
)
def test_preset_names_that_cannot_be_honoured_are_refused(names, overrides, message):
    if message is None:
        select_presets(_Cfg(), None, names, overrides=overrides)
        return
    with pytest.raises(ConfigError, match=re.escape(message)):
        select_presets(_Cfg(), None, names, overrides=overrides)


def test_a_value_given_to_the_preset_instance_wins_over_the_class_default():
    """``MyPresets(default=...)`` or an attribute set on the instance is what resolves; a class attribute
    reassigned after the instance was made (3.0's robot modules do) still counts when the instance kept
    its default."""
    from simlab.utils.presets import resolve_presets

    @configclass
    class Armature(PresetCfg):
        default: float = 0.0
        stiff: float = 0.1

    assert resolve_presets({"a": Armature(default=5.0)})[0] == {"a": 5.0}
    given = Armature()
    given.stiff = 0.7
    assert resolve_presets({"a": given}, [["stiff"]])[0] == {"a": 0.7}
    kept = Armature()
    Armature.stiff = 0.3
    assert resolve_presets({"a": kept}, [["stiff"]])[0] == {"a": 0.3}


def test_two_names_choosing_one_slot_differently_are_refused():
    with pytest.raises(ConfigError, match="presets newton_mjwarp and stiff both choose armature"):
        select_presets(_Cfg(), None, ["newton_mjwarp", "stiff"])


def test_a_mujoco_warp_physics_config_sets_the_models_options_and_a_physx_one_is_held_unused():
    sim = SimulationContext(SimulationCfg(device="cpu", physics=_PhysicsCfg().newton_mjwarp))
    sim.reset()
    opt = sim.model.opt
    assert (opt.iterations, opt.cone, opt.impratio) == (7, mujoco.mjtCone.mjCONE_ELLIPTIC, 10.0)
    assert opt.integrator == mujoco.mjtIntegrator.mjINT_EULER  # MJWarpSolverCfg's default, as 3.0 runs it
    SimulationContext.clear_instance()
    sim = SimulationContext(SimulationCfg(device="cpu", physics=_PhysicsCfg()))  # the preset's default: PhysX
    assert isinstance(sim.cfg.physics, PhysxCfg) and sim.cfg.mujoco.iterations == 100  # simlab's own
    with pytest.raises(ConfigError, match=r"NewtonCfg\(num_substeps=0\): give an int >= 1"):
        SimulationContext(SimulationCfg(device="cpu", physics=NewtonCfg(num_substeps=0)))


def _falling_box(cfg: SimulationCfg, steps: int) -> torch.Tensor:
    import simlab.sim as sim_utils
    from simlab.assets import RigidObject, RigidObjectCfg

    SimulationContext.clear_instance()
    sim = SimulationContext(cfg)
    box = RigidObject(
        RigidObjectCfg(
            prim_path="/World/envs/env_.*/Box",
            spawn=sim_utils.CuboidCfg(
                size=(0.2, 0.2, 0.2),
                rigid_props=sim_utils.RigidBodyPropertiesCfg(),
                mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
            ),
            init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 0.5)),
        )
    )
    sim.reset()
    box.write_root_velocity_to_sim(torch.tensor([[1.0, 0.0, 0.0, 0.0, 2.0, 1.0]]))  # thrown, tumbling
    for _ in range(steps):
        sim.step()
    box.update(cfg.dt)
    return box.data.root_state_w.clone()


def test_newton_substeps_are_mujoco_steps_of_dt_over_n():
    """``NewtonCfg(num_substeps=2)`` with ``sim.dt=0.02``: each physics step is two MuJoCo steps of 0.01 s,
    the same simulation as ``sim.dt=0.01`` stepped twice as often (a tumbling box thrown in the air)."""
    substeps = SimulationCfg(device="cpu", dt=0.02, physics=NewtonCfg(num_substeps=2, solver_cfg=MJWarpSolverCfg()))
    state = _falling_box(substeps, 30)
    assert SimulationContext.instance().model.opt.timestep == pytest.approx(0.01)
    plain = SimulationCfg(device="cpu", dt=0.01, physics=NewtonCfg(solver_cfg=MJWarpSolverCfg()))
    assert torch.equal(state, _falling_box(plain, 60))
    # 60 MuJoCo steps of h = 0.01 s (semi-implicit Euler: the fall is g h^2 n (n + 1) / 2; 30 steps of 0.02 s
    # would have fallen 3 cm further)
    h, n = 0.01, 60
    assert state[0, 0] == pytest.approx(0.6, abs=1e-4)
    assert state[0, 2] == pytest.approx(0.5 - 9.81 * h * h * n * (n + 1) / 2, abs=1e-3)


def _args(*selectors: str) -> argparse.Namespace:
    args = argparse.Namespace(task=TASK, library="rsl_rl", algorithm=None, agent=None, num_envs=None, device="cpu")
    apply_selectors(args, dict(word.split("=", 1) for word in selectors))
    return args


def test_the_3_0_cartpole_keeps_its_physics_presets_and_steps(ported3):
    """Isaac Lab 3.0's manager-based cartpole with its CartpolePhysicsCfg: the default (newton_mjwarp) sets
    MuJoCo's options from 3.0's solver settings; physics=mujoco takes the same slot; PhysX is refused."""
    from isaaclab3_cartpole.cartpole_direct_env_cfg import CartpoleEnvCfg as DirectCfg
    from isaaclab3_cartpole.cartpole_direct_env_cfg import CartpolePhysicsCfg

    env_cfg, _ = load_configs(_args("physics=mujoco"), ["env.scene.num_envs=4"], with_agent=False)
    assert isinstance(env_cfg.sim.physics, NewtonCfg) and env_cfg.sim.engine == "mujoco"
    assert env_cfg.sim.physics == CartpolePhysicsCfg().newton_mjwarp
    env = gym.make(TASK, cfg=env_cfg)
    try:
        opt = env.unwrapped.sim.model.opt
        assert opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST  # 3.0's newton_mjwarp preset says so
        assert env.unwrapped.sim.cfg.mujoco.njmax == 5 and env.unwrapped.sim.cfg.mujoco.nconmax == 3
        env.reset(seed=0)
        for _ in range(5):
            obs, reward, *_ = env.step(torch.ones(4, 1))
        assert torch.isfinite(obs["policy"]).all() and reward.shape == (4,)
    finally:
        env.close()
    for words in (["physics=isaacsim_physx"], ["presets=physx"]):
        with pytest.raises(ConfigError, match="physx: simlab simulates with MuJoCo"):
            load_configs(_args(*words), [], with_agent=False)
    cfg = parse_env_cfg(TASK, device="cpu", num_envs=2, overrides=["env.sim.physics=newton_mjwarp"])
    assert cfg.sim.physics.solver_cfg.njmax == 5
    with pytest.raises(ConfigError, match="The preset newton_kamino chooses Newton's Kamino solver at sim.physics"):
        parse_env_cfg(TASK, device="cpu", overrides=["presets=newton_kamino"])
    # the direct cartpole holds the same preset in SimulationCfg(physics=...): unresolved, its default applies
    direct = DirectCfg()
    assert isinstance(direct.sim.physics, PresetCfg)
    from isaaclab3_cartpole.cartpole_direct_env import CartpoleEnv

    direct.scene.num_envs, direct.sim.device = 2, "cpu"
    env = CartpoleEnv(direct)
    try:
        assert env.sim.cfg.mujoco.njmax == 5 and isinstance(env.cfg.sim.physics, NewtonCfg)
        env.reset()
        env.step(torch.zeros(2, 1))
    finally:
        env.close()


def test_building_a_3_0_env_leaves_the_callers_config_and_its_presets_as_they_were(ported3):
    """The env resolves its presets (and converts quaternions) in a copy: the config the user passed keeps
    its preset slots, so it can build another env, with other presets, afterwards."""
    from isaaclab3_cartpole.cartpole_direct_env import CartpoleEnv
    from isaaclab3_cartpole.cartpole_direct_env_cfg import CartpoleEnvCfg

    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
    physics = cfg.sim.physics
    env = CartpoleEnv(cfg)
    try:
        assert isinstance(env.cfg.sim.physics, NewtonCfg) and env.cfg is not cfg
    finally:
        env.close()
    assert cfg.sim.physics is physics and isinstance(physics, PresetCfg)
