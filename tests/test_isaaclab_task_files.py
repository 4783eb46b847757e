"""Isaac Lab's own task files, for every family simlab registers, run after the import mapping.

Each case copies one or more of Isaac Lab's task folders (``source/isaaclab_tasks/isaaclab_tasks/<folder>``
of an Isaac Lab 2.x checkout, every file: env configs, direct env modules, ``mdp``, ``agents``) into a
package of its own, rewrites their import lines by the README's mapping (``isaaclab`` -> ``simlab``,
``isaaclab_assets`` -> ``simlab.robots``, ``isaaclab_tasks`` -> ``simlab.tasks``, ``isaaclab_rl`` ->
``simlab.rl``, the ``isaacsim`` utilities -> theirs), pointing the copied folders' references to
themselves at the copy (so Isaac Lab's base config and ``mdp`` run, not simlab's), builds the env with
two envs on the CPU and steps it as Isaac Lab's tests do (``torch.inference_mode``).

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

import pytest
import torch

SOURCE = os.environ.get("SIMLAB_ISAACLAB_SOURCE")
TASKS = Path(SOURCE or ".") / "source" / "isaaclab_tasks" / "isaaclab_tasks"

# The README's mapping, most specific first; only import lines change.
IMPORT_MAPPING = [
    (r"\bisaacsim\.core\.utils\.(prims|stage)\b", "simlab.sim.utils"),
    (r"\bisaacsim\.core\.utils\.torch\b", "simlab.utils.torch_utils"),
    (r"\bisaacsim\.util\.debug_draw\._debug_draw\b", "simlab.markers.debug_draw"),
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
    env: str | None = None  # "module:Class" of a direct env; None: ManagerBasedRLEnv


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
    "shadow-hand-over": Case(
        "Shadow hand over",
        ("direct/shadow_hand_over",),
        "direct.shadow_hand_over.shadow_hand_over_env_cfg",
        "ShadowHandOverEnvCfg",
        "direct.shadow_hand_over.shadow_hand_over_env:ShadowHandOverEnv",
    ),
}

STOPS = {
    "direct/franka_cabinet/franka_cabinet_env.py": "Open a drawer (Franka)",
    "direct/humanoid_amp/humanoid_amp_env_cfg.py": "Humanoid motion imitation (AMP)",
    "direct/shadow_hand/shadow_hand_env_cfg.py": "In-hand cube reorientation (Shadow)",  # its OpenAI variant
}
"""Isaac Lab's files (or variants) of registered families that do not run, by file (docs/porting.md says why)."""


def port_line(line: str, package: str, folders: tuple[str, ...]) -> str:
    if not re.match(r"\s*(from|import)\s+isaac(lab|sim)", line):
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
            env = getattr(importlib.import_module(f"{package}.{module}"), cls)(cfg)
        try:
            env.reset()
            agents = getattr(env.cfg, "possible_agents", None)
            with torch.inference_mode():  # as Isaac Lab's own environment tests step
                for _ in range(3):
                    if agents:
                        actions = {a: torch.zeros(2, env.action_spaces[a].shape[0]) for a in agents}
                    else:
                        actions = torch.zeros(2, env.single_action_space.shape[0])
                    obs, reward, *_ = env.step(actions)
            for value in [*(obs.values() if isinstance(obs, dict) else [obs])]:
                for tensor in value.values() if isinstance(value, dict) else [value]:
                    assert torch.isfinite(tensor).all()
            for tensor in reward.values() if isinstance(reward, dict) else [reward]:
                assert torch.isfinite(tensor).all()
        finally:
            env.close()
    finally:
        sys.path.remove(str(tmp_path))
        for module in [m for m in sys.modules if m == package or m.startswith(package + ".")]:
            del sys.modules[module]
