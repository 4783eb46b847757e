"""Isaac Lab's simulation helpers: build_simulation_context, settings, and the prim/stage helpers."""

from __future__ import annotations

import mujoco
import pytest
import torch

import simlab.sim as sim_utils
from simlab.sim import SimulationContext


def test_build_simulation_context_makes_and_clears_a_simulation():
    with sim_utils.build_simulation_context(
        device="cpu", dt=0.005, gravity_enabled=False, add_ground_plane=True
    ) as sim:
        assert SimulationContext.instance() is sim
        assert sim.get_physics_dt() == 0.005 and sim.cfg.gravity == (0.0, 0.0, 0.0)
        cube = sim_utils.CuboidCfg(size=(0.2, 0.2, 0.2), rigid_props=sim_utils.RigidBodyPropertiesCfg())
        cube.func("/World/Cube", cube, translation=(0.0, 0.0, 1.0))
        sim.reset()
        for _ in range(10):
            sim.step()
        sim.forward()
        # no gravity: the free cube stays where it was put
        body = mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_BODY, "Cube/body")
        assert body > 0
        assert torch.allclose(sim.physics.data("xpos")[0, body, 2].float(), torch.tensor(1.0), atol=1e-6)
    assert SimulationContext.instance() is None


def test_build_simulation_context_takes_a_cfg_and_adds_ground_and_light():
    cfg = sim_utils.SimulationCfg(dt=0.01, device="cpu")
    with sim_utils.build_simulation_context(sim_cfg=cfg, add_ground_plane=True, add_lighting=True) as sim:
        assert sim.cfg is cfg
        assert sim_utils.is_prim_path_valid("/World/defaultGroundPlane")
        assert sim_utils.is_prim_path_valid("/World/defaultDomeLight")
        assert len(sim.spec.lights) == 1


def test_isaac_lab_material_and_physx_settings_load_and_the_material_sets_friction():
    """Isaac Lab's task configs write ``self.sim.physx.*`` and ``self.sim.physics_material.*`` in
    ``__post_init__``: both exist; the material is the friction of geoms spawned without their own,
    and by default MuJoCo's own (the compiled model is the same as with none)."""
    frictions = []
    for material in ("default", None, 0.3):
        cfg = sim_utils.SimulationCfg(dt=0.01, device="cpu")
        cfg.physx.bounce_threshold_velocity = 0.2  # PhysX's: accepted, not used
        cfg.physx.gpu_max_rigid_patch_count = 10 * 2**15
        if material is None:
            cfg.physics_material = None
        elif material != "default":
            cfg.physics_material.static_friction = material
        with sim_utils.build_simulation_context(sim_cfg=cfg) as sim:
            box = sim_utils.CuboidCfg(size=(0.1, 0.1, 0.1))
            box.func("/World/Box", box)
            rubber = sim_utils.CuboidCfg(size=(0.1, 0.1, 0.1), physics_material=sim_utils.RigidBodyMaterialCfg(2.0))
            rubber.func("/World/Rubber", rubber, translation=(0.5, 0.0, 0.0))
            sim.reset()
            frictions.append(sim.model.geom_friction.copy())
    default, none, set_to = frictions
    assert (default == none).all() and default[0].tolist() == [1.0, 0.005, 0.0001]
    assert set_to[0, 0] == 0.3 and set_to[1, 0] == 2.0  # a geom's own material is kept


def test_an_explicit_device_overrides_the_cfg():
    cfg = sim_utils.SimulationCfg(dt=0.002, gravity=(0.0, 0.0, -1.0), device="auto")
    with sim_utils.build_simulation_context(sim_cfg=cfg, device="cpu", gravity_enabled=True, dt=0.5) as sim:
        assert sim.cfg.device == "cpu" and sim.cfg.dt == 0.002 and sim.cfg.gravity == (0.0, 0.0, -1.0)
        assert sim.stage is sim_utils.get_current_stage()


def test_settings_are_stored_and_read_back():
    with sim_utils.build_simulation_context(device="cpu") as sim:
        assert sim.get_setting("/isaaclab/has_gui") is False
        assert sim.get_setting("/not/set") is None
        sim.set_setting("/isaaclab/render/rtx_sensors", True)
        assert sim.get_setting("/isaaclab/render/rtx_sensors") is True
        with pytest.raises(ValueError, match="'/'-separated"):
            sim.set_setting("no_slash", 1)


def test_stage_helpers_work_on_the_spec():
    with pytest.raises(RuntimeError, match="No stage"):
        sim_utils.get_current_stage()
    with sim_utils.build_simulation_context(device="cpu"):
        stage = sim_utils.get_current_stage()
        assert isinstance(stage, mujoco.MjSpec) and sim_utils.get_stage_up_axis() == "Z"
        assert sim_utils.create_prim("/World/Objects", "Xform") == "/World/Objects"
        sphere = sim_utils.SphereCfg(radius=0.1)
        sphere.func("/World/Objects/Ball", sphere)
        assert sim_utils.is_prim_path_valid("/World/Objects")
        assert sim_utils.is_prim_path_valid("/World/Objects/Ball")
        assert not sim_utils.is_prim_path_valid("/World/Objects/Bat")
        sim_utils.clear_stage()
        assert not sim_utils.is_prim_path_valid("/World/Objects/Ball")
        assert sim_utils.get_current_stage() is not stage
        with pytest.raises(NotImplementedError, match="CuboidCfg"):
            sim_utils.create_prim("/World/Box", "Cube")
        with pytest.raises(NotImplementedError, match="translation only"):
            sim_utils.create_prim("/World/Group", "Xform", orientation=(0.0, 0.0, 0.0, 1.0))
    sim_utils.create_new_stage()
    assert SimulationContext.instance() is None


@pytest.mark.parametrize("name", ["get_prim_at_path", "bind_visual_material", "find_matching_prim_paths", "clone"])
def test_usd_only_helpers_say_what_to_use(name):
    helper = getattr(sim_utils, name)
    assert helper is getattr(sim_utils.utils, name)
    with pytest.raises(NotImplementedError, match="no USD. Instead: "):
        helper("/World/Robot")


@pytest.mark.parametrize(
    ("group", "pattern"), [("/World/Origin{}", "/World/Origin.*"), ("/World/envs/env_{}", "/World/envs/env_.*")]
)
def test_assets_under_translated_xform_groups_get_one_world_each(group, pattern):
    """Isaac Lab's tutorials spawn ``/World/Origin.*/Robot`` under groups made with create_prim (its
    tests make ``/World/envs/env_<i>`` groups without a scene)."""
    from simlab.assets import RigidObject, RigidObjectCfg

    with sim_utils.build_simulation_context(device="cpu", dt=0.01) as sim:
        origins = [(1.0, 0.0, 0.0), (-1.0, 2.0, 0.0), (0.0, -2.0, 0.0)]
        for i, origin in enumerate(origins):
            sim_utils.create_prim(group.format(i), "Xform", translation=origin)
        sim_utils.create_prim("/World/Elsewhere", "Xform", translation=(9.0, 9.0, 0.0))  # not matched
        ground = sim_utils.GroundPlaneCfg()
        ground.func("/World/defaultGroundPlane", ground)
        cone = sim_utils.ConeCfg(radius=0.1, height=0.2, rigid_props=sim_utils.RigidBodyPropertiesCfg())
        init = RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 0.3))
        ball = RigidObject(RigidObjectCfg(prim_path=f"{pattern}/Ball", spawn=cone, init_state=init))
        sim.reset()
        assert ball.num_instances == 3
        expected = torch.tensor(origins) + torch.tensor([0.0, 0.0, 0.3])
        torch.testing.assert_close(ball.data.root_pos_w, expected)  # spawned in each group
        for _ in range(50):
            sim.step()
            ball.update(sim.get_physics_dt())
        # each cone falls in its own world and comes to rest on its base (centre at half its height)
        torch.testing.assert_close(ball.data.root_pos_w[:, 2], torch.full((3,), 0.1), atol=5e-3, rtol=0)


def test_usd_stage_calls_on_the_stage_say_what_to_use():
    with sim_utils.build_simulation_context(device="cpu", add_ground_plane=True) as sim:
        stage = sim_utils.get_current_stage()
        # the one USD query a spec answers: was something spawned at this path?
        assert sim.stage.GetPrimAtPath("/World/defaultGroundPlane").IsValid()
        assert not stage.GetPrimAtPath("/World/defaultDomeLight").IsValid()
        assert stage.GetPrimAtPath("/World/defaultGroundPlane").GetName() == "defaultGroundPlane"
        with pytest.raises(AttributeError, match="not a USD prim: it has no 'GetAttribute'.*MjSpec API"):
            stage.GetPrimAtPath("/World/defaultGroundPlane").GetAttribute("size")
        for usd_call in ("DefinePrim", "Traverse", "GetDefaultPrim"):
            with pytest.raises(AttributeError, match=f"not a USD stage: it has no '{usd_call}'.*MjSpec API"):
                getattr(stage, usd_call)
        assert not hasattr(stage, "Traverse")  # still an AttributeError for hasattr
        with pytest.raises(AttributeError, match="has no attribute 'no_such_field'"):
            stage.no_such_field  # noqa: B018
        sim.reset()  # the spec itself compiles as before
        assert sim.model.ngeom >= 1


def test_clear_all_callbacks_forgets_setup_and_render_callbacks():
    with sim_utils.build_simulation_context(device="cpu") as sim:
        calls = []
        sim.add_render_callback(lambda: calls.append("render"))
        sim.add_reset_callback(lambda s: calls.append("reset"))
        sim.add_clear_callback(lambda: calls.append("clear"))
        sim.clear_all_callbacks()
        sim.reset()
        sim.run_render_callbacks()
        assert calls == []
    assert calls == ["clear"], "what releases resources still runs when the simulation is cleared"


def test_run_tests_runs_the_calling_file_with_pytest(tmp_path):
    import subprocess
    import sys

    test_file = tmp_path / "test_small.py"
    test_file.write_text(
        "from simlab.app import run_tests\n\ndef test_one():\n    assert 1 + 1 == 2\n\n"
        "def test_two():\n    assert False\n\nif __name__ == '__main__':\n    run_tests(['-q'])\n"
    )
    done = subprocess.run([sys.executable, str(test_file)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1 and "1 failed, 1 passed" in done.stdout, done.stdout[-1000:]


def test_physics_and_render_step_callbacks_follow_the_render_interval():
    from simlab.envs import ManagerBasedRLEnv
    from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg

    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = 2, "cpu", 0
    cfg.decimation, cfg.sim.render_interval = 2, 3
    env = ManagerBasedRLEnv(cfg)
    try:
        assert env.sim.render_mode == SimulationContext.RenderMode.PARTIAL_RENDERING
        physics_dts, render_dts = [], []
        env.sim.add_physics_callback("physics", physics_dts.append)
        env.sim.add_render_callback("render", lambda event: render_dts.append(event.payload["dt"]))
        assert env.sim.has_step_callbacks
        env.reset()
        for _ in range(5):  # 10 physics steps: a render step after the 3rd, 6th and 9th
            env.step(torch.zeros(2, 1))
        assert physics_dts == [cfg.sim.dt] * 10
        assert render_dts == pytest.approx([3 * cfg.sim.dt] * 3)
        env.sim.remove_physics_callback("physics")
        env.sim.remove_render_callback("render")
        assert not env.sim.has_step_callbacks
        env.step(torch.zeros(2, 1))
        assert len(physics_dts) == 10 and len(render_dts) == 3
    finally:
        env.close()


def test_lights_take_isaac_lab_settings():
    """Exposure doubles the brightness per stop, a colour temperature tints, sphere and disk lights
    shine from where they are put."""
    with sim_utils.build_simulation_context(device="cpu") as sim:
        for name, cfg, pos, rot in [
            ("dim", sim_utils.DistantLightCfg(intensity=600.0), None, None),
            ("bright", sim_utils.DistantLightCfg(intensity=600.0, exposure=1.0), None, None),
            ("warm", sim_utils.DistantLightCfg(intensity=600.0, enable_color_temperature=True,
                                               color_temperature=2500.0), None, None),
            ("bulb", sim_utils.SphereLightCfg(intensity=900.0, radius=0.1), (1.0, 2.0, 3.0), None),
            ("spot", sim_utils.DiskLightCfg(intensity=900.0), (0.0, 0.0, 2.0), (0.0, 1.0, 0.0, 0.0)),  # turned over
        ]:  # fmt: skip
            cfg.func(f"/World/{name}", cfg, translation=pos, orientation=rot)
        sim.reset()
        model = sim.model
        light = {model.light(i).name: i for i in range(model.nlight)}
        diffuse = model.light_diffuse
        assert diffuse[light["bright"]].tolist() == pytest.approx((2 * diffuse[light["dim"]]).tolist())
        red, _, blue = diffuse[light["warm"]]
        assert red > 2 * blue  # 2500 K is orange
        assert model.light_type[light["bulb"]] == mujoco.mjtLightType.mjLIGHT_POINT
        assert model.light_pos[light["bulb"]].tolist() == pytest.approx([1.0, 2.0, 3.0])
        assert model.light_type[light["spot"]] == mujoco.mjtLightType.mjLIGHT_SPOT
        assert model.light_dir[light["spot"]].tolist() == pytest.approx([0.0, 0.0, 1.0])  # -z turned over: up


def test_a_visible_dome_light_is_the_sky():
    """The first dome light visible to primary rays gives the model a skybox: a gradient from its colour
    overhead to a darker shade; a dome hidden from them adds none."""
    sky = mujoco.mjtTexture.mjTEXTURE_SKYBOX
    with sim_utils.build_simulation_context(device="cpu") as sim:
        hidden = sim_utils.DomeLightCfg(color=(0.9, 0.1, 0.1), visible_in_primary_ray=False)
        hidden.func("/World/hidden", hidden)
        for name, colour in (("blue", (0.2, 0.4, 0.8)), ("green", (0.1, 0.9, 0.1))):
            cfg = sim_utils.DomeLightCfg(color=colour)
            cfg.func(f"/World/{name}", cfg)
        sim.reset()
        (texture,) = [sim.model.texture(i) for i in range(sim.model.ntex) if sim.model.tex_type[i] == sky]
        assert texture.name == "/World/blue/sky"
        pixels = sim.model.tex_data[texture.adr[0] : texture.adr[0] + texture.width[0] * texture.height[0] * 3]
        red, green, blue = pixels.reshape(-1, 3).astype(int).T
        assert (blue >= red).all() and (green >= red).all() and blue.max() > 150
    with sim_utils.build_simulation_context(device="cpu") as sim:
        hidden.func("/World/hidden", hidden)
        sim.reset()
        assert sky not in sim.model.tex_type


def test_clear_empties_the_stage_for_a_new_scene():
    with sim_utils.build_simulation_context(device="cpu", add_ground_plane=True) as sim:
        sim.reset()
        assert sim.is_playing() and sim_utils.is_prim_path_valid("/World/defaultGroundPlane")
        sim.clear()
        assert sim.is_stopped() and not sim_utils.is_prim_path_valid("/World/defaultGroundPlane")
        box = sim_utils.CuboidCfg(size=(0.1, 0.1, 0.1))
        box.func("/World/Box", box)  # spawning works again, on the empty stage
        sim.reset()
        assert sim.model.ngeom == 1
