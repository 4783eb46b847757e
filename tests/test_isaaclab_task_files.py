"""Isaac Lab's own task files, for every family simlab registers, run after the import mapping.

Each case copies one or more of Isaac Lab's task folders (``source/isaaclab_tasks/isaaclab_tasks/<folder>``
of an Isaac Lab 2.x checkout, every file: env configs, direct env modules, ``mdp``, ``agents``) into a
package of its own, rewrites their import lines by the README's mapping (``isaaclab`` -> ``simlab``,
``isaaclab_assets`` -> ``simlab.robots``, ``isaaclab_tasks`` -> ``simlab.tasks``, ``isaaclab_rl`` ->
``simlab.rl``, the ``isaacsim`` utilities -> theirs), pointing the copied folders' references to
themselves at the copy (so Isaac Lab's base config and ``mdp`` run, not simlab's), builds the env with
two envs on the CPU and steps it 100 times with random actions (uniform in [-1, 1], through
the short episodes' resets) as Isaac Lab's tests do (``torch.inference_mode``).

Isaac Lab's files are not kept in this repository: ``SIMLAB_ISAACLAB_SOURCE`` names the checkout
(the cases were checked against release 2.0's tree; docs/porting.md has the table). Without it the
cases skip; the mapping itself and the table are checked either way.
"""

from __future__ import annotations

import importlib
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym
import pytest
import torch

from simlab.envs.utils.spaces import sample_space

SOURCE = os.environ.get("SIMLAB_ISAACLAB_SOURCE")
TASKS = Path(SOURCE or ".") / "source" / "isaaclab_tasks" / "isaaclab_tasks"

# The README's mapping, most specific first; only import lines change.
IMPORT_MAPPING = [
    (r"\bisaacsim\.core\.utils\.(prims|stage)\b", "simlab.sim.utils"),
    (r"\bisaacsim\.core\.utils\.torch\b", "simlab.utils.torch_utils"),
    (r"\bisaacsim\.util\.debug_draw\._debug_draw\b", "simlab.markers.debug_draw"),
    (r"\bomni\.replicator\.core\b", "simlab.sensors.replicator"),
    (r"^(\s*from\s+)pxr\b", r"\1simlab.sim.pxr"),
    (r"\bisaaclab_assets\.robots\b", "simlab.robots"),
    (r"\bisaaclab_assets\b", "simlab.robots"),
    (r"\bisaaclab_tasks\b", "simlab.tasks"),
    (r"\bisaaclab_rl\b", "simlab.rl"),
    (r"\bisaaclab\b", "simlab"),
]


@dataclass(frozen=True)
class Case:
    family: str  # as in docs/task_families.yaml
    folders: tuple[str, ...]  # under isaaclab_tasks/, copied together
    module: str  # the config's module, under the copy
    cfg: str
    env: str | None = None  # "module:Class" of a direct env (in the copy, or simlab's); None: ManagerBasedRLEnv


VELOCITY = ("manager_based/locomotion/velocity",)
CASES = {
    "ant": Case(
        "Ant",
        ("manager_based/classic/ant", "manager_based/classic/humanoid"),
        "manager_based.classic.ant.ant_env_cfg",
        "AntEnvCfg",
    ),
    "ant-direct": Case(
        "Ant", ("direct/ant", "direct/locomotion"), "direct.ant.ant_env", "AntEnvCfg", "direct.ant.ant_env:AntEnv"
    ),
    "humanoid": Case(
        "Humanoid",
        ("manager_based/classic/humanoid",),
        "manager_based.classic.humanoid.humanoid_env_cfg",
        "HumanoidEnvCfg",
    ),
    "humanoid-direct": Case(
        "Humanoid",
        ("direct/humanoid", "direct/locomotion"),
        "direct.humanoid.humanoid_env",
        "HumanoidEnvCfg",
        "direct.humanoid.humanoid_env:HumanoidEnv",
    ),
    "cartpole": Case(
        "Cartpole",
        ("manager_based/classic/cartpole",),
        "manager_based.classic.cartpole.cartpole_env_cfg",
        "CartpoleEnvCfg",
    ),
    "cartpole-direct": Case(
        "Cartpole",
        ("direct/cartpole",),
        "direct.cartpole.cartpole_env",
        "CartpoleEnvCfg",
        "direct.cartpole.cartpole_env:CartpoleEnv",
    ),
    "cartpole-camera-rgb-direct": Case(
        "Cartpole from cameras (direct)",
        ("direct/cartpole",),
        "direct.cartpole.cartpole_camera_env",
        "CartpoleRGBCameraEnvCfg",
        "direct.cartpole.cartpole_camera_env:CartpoleCameraEnv",
    ),
    "cartpole-camera-depth-direct": Case(
        "Cartpole from cameras (direct)",
        ("direct/cartpole",),
        "direct.cartpole.cartpole_camera_env",
        "CartpoleDepthCameraEnvCfg",
        "direct.cartpole.cartpole_camera_env:CartpoleCameraEnv",
    ),
    **{
        f"cartpole-camera-{kind.lower()}": Case(
            "Cartpole from cameras (manager-based)",
            ("manager_based/classic/cartpole",),
            "manager_based.classic.cartpole.cartpole_camera_env_cfg",
            f"Cartpole{kind}CameraEnvCfg",
        )
        for kind in ("RGB", "Depth")
    },
    # the showcase on simlab's direct cartpole (its folder only: it imports direct/cartpole's env)
    **{
        f"cartpole-showcase-{obs.lower()}-{act.lower()}": Case(
            "Cartpole spaces showcase",
            ("direct/cartpole_showcase",),
            "direct.cartpole_showcase.cartpole.cartpole_env_cfg",
            f"{obs}{act}EnvCfg",
            "direct.cartpole_showcase.cartpole.cartpole_env:CartpoleShowcaseEnv",
        )
        for obs in ("Box", "Discrete", "MultiDiscrete", "Dict", "Tuple")
        for act in ("Box", "Discrete", "MultiDiscrete")
    },
    "reach-franka": Case(
        "Reach (Franka)",
        ("manager_based/manipulation/reach",),
        "manager_based.manipulation.reach.config.franka.joint_pos_env_cfg",
        "FrankaReachEnvCfg",
    ),
    "reach-franka-ik-abs": Case(
        "Reach (Franka)",
        ("manager_based/manipulation/reach",),
        "manager_based.manipulation.reach.config.franka.ik_abs_env_cfg",
        "FrankaReachEnvCfg",
    ),
    "reach-franka-ik-rel": Case(
        "Reach (Franka)",
        ("manager_based/manipulation/reach",),
        "manager_based.manipulation.reach.config.franka.ik_rel_env_cfg",
        "FrankaReachEnvCfg",
    ),
    "reach-franka-osc": Case(
        "Reach (Franka)",
        ("manager_based/manipulation/reach",),
        "manager_based.manipulation.reach.config.franka.osc_env_cfg",
        "FrankaReachEnvCfg",
    ),
    "reach-ur10": Case(
        "Reach (UR10)",
        ("manager_based/manipulation/reach",),
        "manager_based.manipulation.reach.config.ur_10.joint_pos_env_cfg",
        "UR10ReachEnvCfg",
    ),
    "lift": Case(
        "Lift a cube (Franka)",
        ("manager_based/manipulation/lift",),
        "manager_based.manipulation.lift.config.franka.joint_pos_env_cfg",
        "FrankaCubeLiftEnvCfg",
    ),
    "lift-ik-abs": Case(
        "Lift a cube (Franka)",
        ("manager_based/manipulation/lift",),
        "manager_based.manipulation.lift.config.franka.ik_abs_env_cfg",
        "FrankaCubeLiftEnvCfg",
    ),
    "lift-ik-rel": Case(
        "Lift a cube (Franka)",
        ("manager_based/manipulation/lift",),
        "manager_based.manipulation.lift.config.franka.ik_rel_env_cfg",
        "FrankaCubeLiftEnvCfg",
    ),
    "stack": Case(
        "Stack cubes (Franka)",
        ("manager_based/manipulation/stack",),
        "manager_based.manipulation.stack.config.franka.stack_joint_pos_env_cfg",
        "FrankaCubeStackEnvCfg",
    ),
    "stack-ik-rel": Case(
        "Stack cubes (Franka)",
        ("manager_based/manipulation/stack",),
        "manager_based.manipulation.stack.config.franka.stack_ik_rel_env_cfg",
        "FrankaCubeStackEnvCfg",
    ),
    "stack-instance-randomize": Case(
        "Stack cubes, randomized instances (Franka)",
        ("manager_based/manipulation/stack",),
        "manager_based.manipulation.stack.config.franka.stack_joint_pos_instance_randomize_env_cfg",
        "FrankaCubeStackInstanceRandomizeEnvCfg",
    ),
    "stack-instance-randomize-ik-rel": Case(
        "Stack cubes, randomized instances (Franka)",
        ("manager_based/manipulation/stack",),
        "manager_based.manipulation.stack.config.franka.stack_ik_rel_instance_randomize_env_cfg",
        "FrankaCubeStackInstanceRandomizeEnvCfg",
    ),
    "cabinet": Case(
        "Open a drawer (Franka)",
        ("manager_based/manipulation/cabinet",),
        "manager_based.manipulation.cabinet.config.franka.joint_pos_env_cfg",
        "FrankaCabinetEnvCfg",
    ),
    "cabinet-ik-abs": Case(
        "Open a drawer (Franka)",
        ("manager_based/manipulation/cabinet",),
        "manager_based.manipulation.cabinet.config.franka.ik_abs_env_cfg",
        "FrankaCabinetEnvCfg",
    ),
    "cabinet-ik-rel": Case(
        "Open a drawer (Franka)",
        ("manager_based/manipulation/cabinet",),
        "manager_based.manipulation.cabinet.config.franka.ik_rel_env_cfg",
        "FrankaCabinetEnvCfg",
    ),
    "cabinet-direct": Case(
        "Open a drawer (Franka)",
        ("direct/franka_cabinet",),
        "direct.franka_cabinet.franka_cabinet_env",
        "FrankaCabinetEnvCfg",
        "direct.franka_cabinet.franka_cabinet_env:FrankaCabinetEnv",
    ),
    "allegro": Case(
        "In-hand cube reorientation (Allegro)",
        ("manager_based/manipulation/inhand",),
        "manager_based.manipulation.inhand.config.allegro_hand.allegro_env_cfg",
        "AllegroCubeEnvCfg",
    ),
    "allegro-novel": Case(
        "In-hand cube reorientation (Allegro)",
        ("manager_based/manipulation/inhand",),
        "manager_based.manipulation.inhand.config.allegro_hand.allegro_env_cfg",
        "AllegroCubeNoVelObsEnvCfg",
    ),
    "allegro-direct": Case(
        "In-hand cube reorientation (Allegro)",
        ("direct/allegro_hand", "direct/inhand_manipulation"),
        "direct.allegro_hand.allegro_hand_env_cfg",
        "AllegroHandEnvCfg",
        "direct.inhand_manipulation.inhand_manipulation_env:InHandManipulationEnv",
    ),
    # Isaac Lab registers its OpenAI variant with inhand_manipulation's env, which the mapping makes simlab's
    "shadow-openai-direct": Case(
        "In-hand cube reorientation (Shadow)",
        ("direct/shadow_hand",),
        "direct.shadow_hand.shadow_hand_env_cfg",
        "ShadowHandOpenAIEnvCfg",
        "simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env:InHandManipulationEnv",
    ),
    # ... and in Isaac Lab's own copy of that env: its critic reads PhysX's incoming joint forces, whose
    # MuJoCo pass nothing in Isaac Lab's files turns on (the backend runs it when they are read)
    "shadow-openai-direct-own-env": Case(
        "In-hand cube reorientation (Shadow)",
        ("direct/shadow_hand", "direct/inhand_manipulation"),
        "direct.shadow_hand.shadow_hand_env_cfg",
        "ShadowHandOpenAIEnvCfg",
        "direct.inhand_manipulation.inhand_manipulation_env:InHandManipulationEnv",
    ),
    "shadow-direct": Case(
        "In-hand cube reorientation (Shadow)",
        ("direct/shadow_hand", "direct/inhand_manipulation"),
        "direct.shadow_hand.shadow_hand_env_cfg",
        "ShadowHandEnvCfg",
        "direct.inhand_manipulation.inhand_manipulation_env:InHandManipulationEnv",
    ),
    **{
        f"velocity-{robot}-{terrain}": Case(
            family,
            VELOCITY,
            f"manager_based.locomotion.velocity.config.{robot}.{terrain}_env_cfg",
            f"{prefix}{terrain.title()}EnvCfg",
        )
        for robot, prefix, family in (
            ("anymal_b", "AnymalB", "Velocity (ANYmal-B)"),
            ("anymal_c", "AnymalC", "Velocity (ANYmal-C)"),
            ("anymal_d", "AnymalD", "Velocity (ANYmal-D)"),
            ("a1", "UnitreeA1", "Velocity (Unitree A1)"),
            ("go1", "UnitreeGo1", "Velocity (Unitree Go1)"),
            ("go2", "UnitreeGo2", "Velocity (Unitree Go2)"),
            ("h1", "H1", "Velocity (Unitree H1)"),
            ("g1", "G1", "Velocity (Unitree G1)"),
            ("cassie", "Cassie", "Velocity (Agility Cassie)"),
        )
        for terrain in ("flat", "rough")
    },
    "velocity-spot-flat": Case(
        "Velocity (Boston Dynamics Spot)",
        VELOCITY,
        "manager_based.locomotion.velocity.config.spot.flat_env_cfg",
        "SpotFlatEnvCfg",
    ),
    "velocity-anymal_c-direct-flat": Case(
        "Velocity, direct workflow (ANYmal-C)",
        ("direct/anymal_c",),
        "direct.anymal_c.anymal_c_env_cfg",
        "AnymalCFlatEnvCfg",
        "direct.anymal_c.anymal_c_env:AnymalCEnv",
    ),
    "velocity-anymal_c-direct-rough": Case(
        "Velocity, direct workflow (ANYmal-C)",
        ("direct/anymal_c",),
        "direct.anymal_c.anymal_c_env_cfg",
        "AnymalCRoughEnvCfg",
        "direct.anymal_c.anymal_c_env:AnymalCEnv",
    ),
    "navigation": Case(
        "Navigation (ANYmal-C)",
        ("manager_based/navigation",),
        "manager_based.navigation.config.anymal_c.navigation_env_cfg",
        "NavigationEnvCfg",
    ),
    "quadcopter": Case(
        "Quadcopter",
        ("direct/quadcopter",),
        "direct.quadcopter.quadcopter_env",
        "QuadcopterEnvCfg",
        "direct.quadcopter.quadcopter_env:QuadcopterEnv",
    ),
    "cart-double-pendulum": Case(
        "Cart double pendulum",
        ("direct/cart_double_pendulum",),
        "direct.cart_double_pendulum.cart_double_pendulum_env",
        "CartDoublePendulumEnvCfg",
        "direct.cart_double_pendulum.cart_double_pendulum_env:CartDoublePendulumEnv",
    ),
    **{
        f"humanoid-amp-{motion.lower()}": Case(
            "Humanoid motion imitation (AMP)",
            ("direct/humanoid_amp",),
            "direct.humanoid_amp.humanoid_amp_env_cfg",
            f"HumanoidAmp{motion}EnvCfg",
            "direct.humanoid_amp.humanoid_amp_env:HumanoidAmpEnv",
        )
        for motion in ("Dance", "Run", "Walk")
    },
    "shadow-hand-over": Case(
        "Shadow hand over",
        ("direct/shadow_hand_over",),
        "direct.shadow_hand_over.shadow_hand_over_env_cfg",
        "ShadowHandOverEnvCfg",
        "direct.shadow_hand_over.shadow_hand_over_env:ShadowHandOverEnv",
    ),
}

STOPS = {
    "direct/shadow_hand/shadow_hand_vision_env.py": "In-hand cube reorientation from cameras (Shadow)",
}
"""Isaac Lab's files (or variants) of registered families that do not run, by file (docs/porting.md says why)."""


def port_line(line: str, package: str, folders: tuple[str, ...]) -> str:
    if not re.match(r"\s*(from|import)\s+(isaac(lab|sim)|pxr\b|omni\.replicator\b)", line):
        return line
    for folder in folders:  # the copied folders' own modules: the copy
        dotted = folder.replace("/", ".")
        line = re.sub(rf"\bisaaclab_tasks\.{re.escape(dotted)}\b", f"{package}.{dotted}", line)
    for pattern, replacement in IMPORT_MAPPING:
        line = re.sub(pattern, replacement, line)
    return line


def port_folders(tasks: Path, folders: tuple[str, ...], dest: Path, package: str) -> None:
    """Copy ``folders`` of Isaac Lab's ``isaaclab_tasks`` to ``dest/package``, their imports mapped."""
    for folder in folders:
        for path in sorted((tasks / folder).rglob("*")):
            if path.is_dir() or "__pycache__" in path.parts:
                continue
            target = dest / package / path.relative_to(tasks)
            target.parent.mkdir(parents=True, exist_ok=True)
            if path.suffix == ".py":
                lines = path.read_text().splitlines(keepends=True)
                target.write_text("".join(port_line(line, package, folders) for line in lines))
            else:
                target.write_bytes(path.read_bytes())
    for directory in [dest / package, *(p for p in (dest / package).rglob("*") if p.is_dir())]:
        (directory / "__init__.py").touch(exist_ok=True)  # the folders between: plain packages


STEPS = 100


def random_actions(space, num_envs: int = 2):
    """Actions of ``space`` for ``num_envs`` envs: uniform in [-1, 1] for a Box (as Isaac Lab's environment
    tests act), a sample of the others (the showcase's Discrete and MultiDiscrete ones)."""
    if isinstance(space, gym.spaces.Box):
        return 2 * torch.rand(num_envs, *space.shape) - 1
    return sample_space(space, "cpu", batch_size=num_envs)


def _tensors(value) -> list[torch.Tensor]:
    """The tensors of an observation: groups, agents, Dict and Tuple spaces' parts."""
    if isinstance(value, torch.Tensor):
        return [value]
    return [t for item in (value.values() if isinstance(value, dict) else value) for t in _tensors(item)]


def test_the_mapping_rewrites_imports_only_and_keeps_copied_folders_local():
    folders = ("direct/ant", "direct/locomotion")
    assert (
        port_line("from isaaclab_tasks.direct.locomotion.locomotion_env import LocomotionEnv\n", "pkg", folders)
        == "from pkg.direct.locomotion.locomotion_env import LocomotionEnv\n"
    )
    assert (
        port_line("import isaaclab_tasks.manager_based.classic.humanoid.mdp as mdp\n", "pkg", folders)
        == "import simlab.tasks.manager_based.classic.humanoid.mdp as mdp\n"
    )
    assert (
        port_line("from isaaclab_assets.robots.ant import ANT_CFG\n", "p", ())
        == "from simlab.robots.ant import ANT_CFG\n"
    )
    assert (
        port_line("from isaacsim.core.utils.torch.rotations import compute_rot\n", "p", ())
        == "from simlab.utils.torch_utils.rotations import compute_rot\n"
    )
    assert port_line("from pxr import UsdGeom\n", "p", ()) == "from simlab.sim.pxr import UsdGeom\n"
    assert port_line("import omni.replicator.core as rep\n", "p", ()) == "import simlab.sensors.replicator as rep\n"
    text = 'entry_point="isaaclab_tasks.direct.ant:AntEnv"\n'
    assert port_line(text, "p", folders) == text


def test_the_porting_table_lists_every_case_and_stop():
    """docs/porting.md's table of Isaac Lab's task files names each case here and each family that stops."""
    page = (Path(__file__).parent.parent / "docs" / "porting.md").read_text()
    section = page.split("## Isaac Lab's own task files", 1)[1].split("\n## ", 1)[0]
    for name, case in CASES.items():
        assert f"`{name}`" in section, f"docs/porting.md: no row names case {name}"
        assert f"| {case.family} |" in section, case.family
    for path, family in STOPS.items():
        assert f"| {family} |" in section and f"`{path}`" in section, path


def test_the_porting_table_has_a_row_for_every_registered_family_of_isaac_labs():
    """Every family of docs/task_families.yaml that simlab registers and Isaac Lab has files for (its ids
    listed, no ``why_not``) says in docs/porting.md's table whether Isaac Lab's files run, and where."""
    import yaml

    docs = Path(__file__).parent.parent / "docs"
    section = (docs / "porting.md").read_text().split("### Isaac Lab's task files, family by family", 1)[1]
    section = section.split("\n## ", 1)[0]
    families = yaml.safe_load((docs / "task_families.yaml").read_text())
    missing = [
        f["family"] for f in families if f["isaaclab"] and "why_not" not in f and f"| {f['family']} |" not in section
    ]
    assert not missing, f"docs/porting.md: no row for {missing}"


@pytest.mark.skipif(not SOURCE, reason="SIMLAB_ISAACLAB_SOURCE (an Isaac Lab 2.x checkout) is not set")
@pytest.mark.parametrize("name", sorted(CASES))
def test_isaac_labs_task_files_run_after_the_import_mapping(name, tmp_path):
    case = CASES[name]
    package = "isaaclab_port_" + re.sub(r"\W", "_", name)
    port_folders(TASKS, case.folders, tmp_path, package)
    sys.path.insert(0, str(tmp_path))
    try:
        cfg = getattr(importlib.import_module(f"{package}.{case.module}"), case.cfg)()
        assert Path(sys.modules[type(cfg).__module__].__file__).is_relative_to(tmp_path)  # Isaac Lab's file
        for agents in sorted(tmp_path.rglob("agents/*.py")):  # the learning libraries' configs build too
            module = importlib.import_module(".".join(agents.relative_to(tmp_path).with_suffix("").parts))
            for value in vars(module).values():
                if (
                    isinstance(value, type)
                    and value.__module__ == module.__name__
                    and hasattr(value, "__dataclass_fields__")
                ):
                    value()
        cfg.scene.num_envs, cfg.sim.device, cfg.seed = 2, "cpu", 0
        if case.env is None:
            from simlab.envs import ManagerBasedRLEnv

            env = ManagerBasedRLEnv(cfg)
        else:
            module, cls = case.env.split(":")
            module = module if module.startswith("simlab.") else f"{package}.{module}"
            env = getattr(importlib.import_module(module), cls)(cfg)
        try:
            env.reset()
            agents = getattr(env.cfg, "possible_agents", None)
            torch.manual_seed(0)
            with torch.inference_mode():  # as Isaac Lab's own environment tests step
                for step in range(STEPS):  # long enough for the short episodes' resets
                    if agents:
                        actions = {a: random_actions(env.action_spaces[a]) for a in agents}
                    else:
                        actions = random_actions(env.single_action_space)
                    obs, reward, *_ = env.step(actions)
                    for tensor in _tensors(obs) + _tensors(reward):
                        assert torch.isfinite(tensor).all(), f"step {step}"
        finally:
            env.close()
    finally:
        sys.path.remove(str(tmp_path))
        for module in [m for m in sys.modules if m == package or m.startswith(package + ".")]:
            del sys.modules[module]


@pytest.mark.skipif(not SOURCE, reason="SIMLAB_ISAACLAB_SOURCE (an Isaac Lab 2.x checkout) is not set")
def test_isaac_labs_amp_motions_fit_simlabs_28_joint_humanoid(tmp_path):
    """Posed by a frame of Isaac Lab's walk clip (its joint angles, its pelvis pose), HUMANOID_28_CFG's
    bodies are where the clip has them: the model's skeleton is the clip's."""
    import numpy as np

    package = "isaaclab_port_amp_kinematics"
    port_folders(TASKS, ("direct/humanoid_amp",), tmp_path, package)
    sys.path.insert(0, str(tmp_path))
    try:
        cfg = importlib.import_module(f"{package}.direct.humanoid_amp.humanoid_amp_env_cfg").HumanoidAmpWalkEnvCfg()
        cfg.scene.num_envs, cfg.sim.device, cfg.seed = 2, "cpu", 0
        env = importlib.import_module(f"{package}.direct.humanoid_amp.humanoid_amp_env").HumanoidAmpEnv(cfg)
        try:
            env.reset()
            clip, robot = env._motion_loader, env.robot
            dof_pos, _, body_pos, body_rot, _, _ = clip.sample(num_samples=2, times=np.array([0.3, 1.1]))
            pelvis = clip.get_body_index(["pelvis"])[0]
            root = robot.data.default_root_state.clone()
            root[:, :3], root[:, 3:7], root[:, 7:] = body_pos[:, pelvis] + env.scene.env_origins, body_rot[:, pelvis], 0
            robot.write_root_state_to_sim(root)
            robot.write_joint_state_to_sim(dof_pos[:, env.motion_dof_indexes], torch.zeros_like(robot.data.joint_vel))
            ours = robot.data.body_pos_w - env.scene.env_origins[:, None]
            error = (ours - body_pos[:, clip.get_body_index(robot.data.body_names)]).norm(dim=-1).max(dim=0).values
            errors = dict(zip(robot.data.body_names, error.tolist()))
            # the pelvis's children sit exactly; further out, the clip's three-angle joints fit within 3 cm
            assert max(errors[b] for b in ("pelvis", "torso", "right_thigh", "left_thigh")) < 1e-4, errors
            assert max(errors.values()) < 0.03, errors
        finally:
            env.close()
    finally:
        sys.path.remove(str(tmp_path))
        for module in [m for m in sys.modules if m == package or m.startswith(package + ".")]:
            del sys.modules[module]


@pytest.mark.skipif(not SOURCE, reason="SIMLAB_ISAACLAB_SOURCE (an Isaac Lab 2.x checkout) is not set")
def test_isaac_labs_franka_cabinet_reads_the_grasp_frame_simlabs_env_reads(tmp_path):
    """Isaac Lab's direct cabinet env takes the hand and finger poses from the stage (``pxr`` ->
    ``simlab.sim.pxr``); the grasp frame it makes of them is the one simlab's env makes from the bodies."""
    from simlab.sim import SimulationContext
    from simlab.tasks.direct.franka_cabinet.franka_cabinet_env import FrankaCabinetEnv, FrankaCabinetEnvCfg

    package = "isaaclab_port_cabinet_grasp"
    port_folders(TASKS, ("direct/franka_cabinet",), tmp_path, package)
    sys.path.insert(0, str(tmp_path))
    try:
        module = importlib.import_module(f"{package}.direct.franka_cabinet.franka_cabinet_env")
        cfg = module.FrankaCabinetEnvCfg()
        cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
        env = module.FrankaCabinetEnv(cfg)
        theirs = env.robot_local_grasp_pos.clone(), env.robot_local_grasp_rot.clone()
        env.close()
    finally:
        sys.path.remove(str(tmp_path))
        for name in [m for m in sys.modules if m == package or m.startswith(package + ".")]:
            del sys.modules[name]
    SimulationContext.clear_instance()
    cfg = FrankaCabinetEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
    env = FrankaCabinetEnv(cfg)
    try:
        torch.testing.assert_close(theirs[0], env.robot_local_grasp_pos, atol=1e-5, rtol=0)
        torch.testing.assert_close(theirs[1], env.robot_local_grasp_rot, atol=1e-5, rtol=0)
    finally:
        env.close()
