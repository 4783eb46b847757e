"""Raw backend physics against the same stepping through the scene and articulation layer.

Both variants run on one compiled model and one backend. *raw* writes random controls straight
into the backend's ``ctrl`` tensor and steps; *scene* does what user code does every physics step:
``set_joint_effort_target``, ``scene.write_data_to_sim()``, ``sim.step()``, ``scene.update(dt)``.
The ratio scene / raw is what the framework layer keeps of the physics throughput.
"""

from __future__ import annotations

import torch

import simlab.sim as sim_utils
from simlab.assets import AssetBaseCfg
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.utils import configclass

from .cli import ROBOTS
from .timing import gpu_memory_mb, interleaved, reset_gpu_memory_peak


def robot_cfg(name: str):
    """The articulation config of a benchmark robot (one of ``ROBOTS``), and whether it needs a floor."""
    if name == "cartpole":
        from simlab.robots.cartpole import CARTPOLE_CFG

        return CARTPOLE_CFG, False
    if name == "humanoid":
        from simlab.robots.humanoid import HUMANOID_CFG

        return HUMANOID_CFG, True
    if name == "ant":
        from simlab.robots.ant import ANT_CFG

        return ANT_CFG, True
    raise ValueError(f"Unknown benchmark robot '{name}'; available: {', '.join(ROBOTS)}")


def build_scene(robot: str, num_envs: int, device: str) -> tuple[sim_utils.SimulationContext, InteractiveScene]:
    cfg, needs_ground = robot_cfg(robot)

    @configclass
    class BenchSceneCfg(InteractiveSceneCfg):
        robot = cfg.replace(prim_path="{ENV_REGEX_NS}/Robot")
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg()) if needs_ground else None

    sim_cfg = sim_utils.SimulationCfg(dt=1 / 120, device=device)
    sim_cfg.mujoco.disable_contacts = not needs_ground
    sim_utils.SimulationContext.clear_instance()
    sim = sim_utils.SimulationContext(sim_cfg)
    scene = InteractiveScene(BenchSceneCfg(num_envs=num_envs, env_spacing=4.0))
    sim.reset()
    return sim, scene


def bench_physics(robot: str, num_envs: int, device: str, steps: int = 200, rounds: int = 3) -> dict:
    reset_gpu_memory_peak(device)
    sim, scene = build_scene(robot, num_envs, device)
    articulation = scene["robot"]
    physics = sim.physics
    ctrl = physics.data("ctrl")
    dt = sim.get_physics_dt()
    n_joints = articulation.num_joints

    def raw() -> None:
        ctrl.copy_(torch.rand_like(ctrl) * 2 - 1)
        physics.step(1, forward=False)  # mj_step alone

    def framework() -> None:
        articulation.set_joint_effort_target(torch.rand(num_envs, n_joints, device=sim.device) * 2 - 1)
        scene.write_data_to_sim()
        sim.step()
        scene.update(dt)

    for fn in (raw, framework):  # warm up: graph capture, kernel compilation, caches
        for _ in range(10):
            fn()
    seconds = interleaved({"raw": raw, "scene": framework}, steps, device, rounds)
    result = {
        "bench": "physics",
        "robot": robot,
        "device": str(sim.device),
        "num_envs": num_envs,
        "raw_steps_per_s": num_envs / seconds["raw"],
        "scene_steps_per_s": num_envs / seconds["scene"],
        "raw_ms_per_step": seconds["raw"] * 1e3,
        "scene_ms_per_step": seconds["scene"] * 1e3,
        "ratio": seconds["raw"] / seconds["scene"],
        "gpu_memory_mb": gpu_memory_mb(sim.device, physics),
    }
    sim_utils.SimulationContext.clear_instance()
    return result
