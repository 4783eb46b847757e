"""Cost of one height scan (Isaac Lab's locomotion scanner: 187 rays per env) on ROUGH_TERRAINS_CFG.

The ant stands on its env origin in each of ``--num_envs`` envs; the scan is cast with the
device's caster (vertical rays against the geoms of their bin: ``mj_ray`` on the CPU, a Warp kernel
on the GPU) and against every target geom (``mj_ray`` on the full target model, ``mujoco_warp.rays``),
in alternating rounds, next to one physics step of all envs for scale.

    simlab bench raycast --num_envs 64
    simlab bench raycast --device cuda:0 --num_envs 4096
"""

from __future__ import annotations

import argparse
import statistics
import time

import torch

import simlab.sim as sim_utils
from simlab.robots.ant import ANT_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import RayCasterCfg, patterns
from simlab.sensors.ray_caster.ray_targets import _mjbatch_rays, _WarpCaster
from simlab.terrains import ROUGH_TERRAINS_CFG, TerrainImporterCfg
from simlab.utils import configclass


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="simlab bench raycast", description=__doc__.splitlines()[0])
    parser.add_argument("--num_envs", type=int, default=64)
    parser.add_argument("--device", default="cpu", help="cpu (MuJoCo C) or cuda:N (MuJoCo Warp)")
    parser.add_argument("--box_tiles_as", default="height_field")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--casts", type=int, default=20, help="casts per round")
    args = parser.parse_args(argv)

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(
            prim_path="/World/ground",
            terrain_type="generator",
            terrain_generator=ROUGH_TERRAINS_CFG.replace(seed=0, box_tiles_as=args.box_tiles_as),
        )
        robot = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        height_scanner = RayCasterCfg(
            prim_path="{ENV_REGEX_NS}/Robot/torso",
            offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 20.0)),
            ray_alignment="yaw",
            pattern_cfg=patterns.GridPatternCfg(resolution=0.1, size=(1.6, 1.0)),
            mesh_prim_paths=["/World/ground"],
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device=args.device))
    scene = InteractiveScene(SceneCfg(num_envs=args.num_envs, env_spacing=2.0))
    sim.reset()
    sensor = scene["height_scanner"]
    caster = sensor._targets._caster
    sensor._cast()
    origins = sim.env_origins
    starts, directions = sensor._rays_w(sensor.data.pos_w, sensor.data.quat_w)
    starts, directions = (starts - origins[:, None]).reshape(-1, 3), directions.reshape(-1, 3)

    if isinstance(caster, _WarpCaster):
        unbinned = _WarpCaster(sensor._targets.model, len(starts), sim.physics, args.device, binned=False)
        torch.testing.assert_close(caster.cast(starts, directions), unbinned.cast(starts, directions), rtol=0, atol=0)

    def binned() -> None:
        caster.cast(starts, directions)

    def every_geom() -> None:
        if isinstance(caster, _WarpCaster):
            unbinned.cast(starts, directions)
        else:
            _mjbatch_rays(caster.full, starts, directions)

    def physics() -> None:
        sim.step()

    def synchronize() -> None:
        if starts.is_cuda:
            torch.cuda.synchronize(starts.device)

    times: dict[str, list[float]] = {"binned cast": [], "cast against every geom": [], "physics step": []}
    for _ in range(args.rounds):
        for name, run in zip(times, (binned, every_geom, physics), strict=True):
            synchronize()
            start = time.perf_counter()
            for _ in range(args.casts):
                run()
            synchronize()
            times[name].append((time.perf_counter() - start) / args.casts * 1e3)
    rays = args.num_envs * sensor.num_rays
    threads = getattr(sim.physics, "num_threads", None)  # MuJoCo C's pool; MuJoCo Warp has none
    where = f"{threads} threads" if threads else f"MuJoCo Warp on {args.device}"
    print(f"{args.num_envs} envs, {rays} rays, {where}")
    for name, ms in times.items():
        print(f"  {name:24s} {statistics.median(ms):8.2f} ms (rounds {[round(t, 2) for t in ms]})")


if __name__ == "__main__":
    main()
