"""Isaac Lab's URDF conversion: ``UrdfConverter`` compiles a URDF with MuJoCo and writes MJCF at its
``usd_path``, which ``UsdFileCfg(usd_path=...)`` spawns (Isaac Lab's convert-then-spawn tutorial)."""

from __future__ import annotations

import os

import pytest

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.utils import configclass
from simlab.utils.errors import ConfigError

URDF = """<robot name="arm">
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="plate"><inertial><mass value="0.1"/>
    <inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.01"/></geometry></collision></link>
  <link name="link"><inertial><mass value="0.5"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><cylinder radius="0.03" length="0.4"/></geometry></collision></link>
  <joint name="weld" type="fixed"><parent link="base"/><child link="plate"/><origin xyz="0 0 0.06"/></joint>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="link"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="10" velocity="5"/></joint>
</robot>
"""


def _cfg(tmp_path, **kwargs) -> sim_utils.UrdfConverterCfg:
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(URDF)
    return sim_utils.UrdfConverterCfg(
        asset_path=str(urdf),
        usd_dir=str(tmp_path / "out"),
        usd_file_name="arm.usd",
        joint_drive=sim_utils.UrdfConverterCfg.JointDriveCfg(
            gains=sim_utils.UrdfConverterCfg.JointDriveCfg.PDGainsCfg(stiffness=100.0, damping=1.0)
        ),
        **kwargs,
    )


def test_urdf_converter_writes_mjcf_that_usd_file_cfg_spawns(tmp_path):
    converter = sim_utils.UrdfConverter(_cfg(tmp_path, fix_base=False, merge_fixed_joints=True))
    assert converter.usd_path == str(tmp_path / "out" / "arm.xml") and os.path.isfile(converter.usd_path)

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        robot = ArticulationCfg(
            prim_path="{ENV_REGEX_NS}/Robot",
            spawn=sim_utils.UsdFileCfg(usd_path=converter.usd_path),
            init_state=ArticulationCfg.InitialStateCfg(pos=(0.0, 0.0, 1.0)),
            actuators={"arm": ImplicitActuatorCfg(joint_names_expr=[".*"], stiffness=100.0, damping=1.0)},
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(SceneCfg(num_envs=2, env_spacing=2.0))
    sim.reset()
    robot = scene["robot"]
    assert robot.joint_names == ["shoulder"]
    assert "plate" not in robot.body_names  # merged into its parent by the fixed joint
    for _ in range(40):  # not fixed: the base falls
        scene.write_data_to_sim()
        sim.step()
        scene.update(0.005)
    assert float(robot.data.root_pos_w[0, 2]) < 0.95


@pytest.mark.parametrize("merge", [True, False])
def test_fixed_base_keeps_its_root_and_merges_fixed_links_if_asked(tmp_path, merge):
    import mujoco

    converter = sim_utils.UrdfConverter(_cfg(tmp_path, fix_base=True, merge_fixed_joints=merge))
    model = mujoco.MjModel.from_xml_path(converter.usd_path)
    bodies = [model.body(b).name for b in range(1, model.nbody)]
    assert model.njnt == 1 and bodies == (["base", "link"] if merge else ["base", "plate", "link"])


def test_missing_urdf_is_one_line(tmp_path):
    with pytest.raises(ConfigError, match="no such file"):
        sim_utils.UrdfConverter(sim_utils.UrdfConverterCfg(asset_path=str(tmp_path / "none.urdf"), fix_base=True))


@pytest.mark.parametrize("merge", [True, False])
def test_urdf_file_cfg_takes_the_converter_settings(tmp_path, merge):
    """Isaac Lab's UrdfFileCfg is a UrdfConverterCfg too: its joint drive is accepted, merge_fixed_joints applies."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(URDF)
    drive = sim_utils.UrdfConverterCfg.JointDriveCfg(
        gains=sim_utils.UrdfConverterCfg.JointDriveCfg.PDGainsCfg(stiffness=100.0, damping=1.0)
    )

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        robot = ArticulationCfg(
            prim_path="{ENV_REGEX_NS}/Robot",
            spawn=sim_utils.UrdfFileCfg(
                asset_path=str(urdf), fix_base=True, merge_fixed_joints=merge, joint_drive=drive
            ),
            actuators={"arm": ImplicitActuatorCfg(joint_names_expr=[".*"], stiffness=100.0, damping=1.0)},
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(SceneCfg(num_envs=1, env_spacing=2.0))
    sim.reset()
    assert scene["robot"].joint_names == ["shoulder"]
    assert ("plate" in scene["robot"].body_names) is not merge
