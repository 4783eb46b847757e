"""CPU MuJoCo step cost of a small legged body standing on each kind of terrain.

One world, no simlab env: a box body on four capsule legs, stepped with ``mj_step`` on an infinite
plane, on ROUGH_TERRAINS_CFG (standing on a stairs, a boxes and a random-roughness tile) and on
ROUGH_TERRAINS_CFG without its boxes tiles, to show what the terrain's static geoms cost.

    PYTHONPATH=$PWD python scripts/benchmarks/terrain_step_cost.py
"""

from __future__ import annotations

import time

import mujoco

from simlab.sim.spawners.materials import RigidBodyMaterialCfg
from simlab.terrains import ROUGH_TERRAINS_CFG, TerrainGenerator, TerrainGeneratorCfg
from simlab.terrains.mjspec_terrain import add_terrain_to_spec

STEPS = 2000


def legged_model(terrain: TerrainGeneratorCfg | None, tile: tuple[int, int] = (0, 0)) -> mujoco.MjModel:
    spec = mujoco.MjSpec()
    start = [0.0, 0.0, 0.0]
    if terrain is None:
        spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1])
    else:
        generator = TerrainGenerator(terrain)
        add_terrain_to_spec(spec, generator, "ground", RigidBodyMaterialCfg(), None)
        start = generator.terrain_origins[tile].tolist()
    body = spec.worldbody.add_body(pos=[start[0], start[1], start[2] + 0.4])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.3, 0.15, 0.05])
    for x in (-0.25, 0.25):
        for y in (-0.12, 0.12):
            body.add_geom(type=mujoco.mjtGeom.mjGEOM_CAPSULE, fromto=[x, y, 0, x, y, -0.3], size=[0.03, 0, 0])
    return spec.compile()


def step_cost_us(model: mujoco.MjModel) -> float:
    data = mujoco.MjData(model)
    for _ in range(200):  # settle on the ground
        mujoco.mj_step(model, data)
    start = time.perf_counter()
    for _ in range(STEPS):
        mujoco.mj_step(model, data)
    return (time.perf_counter() - start) / STEPS * 1e6


def main() -> None:
    rough = ROUGH_TERRAINS_CFG.replace(seed=1, curriculum=True)
    without_boxes = rough.replace(sub_terrains={k: v for k, v in rough.sub_terrains.items() if k != "boxes"})
    cases = [
        ("plane", None, (0, 0)),
        ("rough, on a stairs tile", rough, (5, 0)),
        ("rough, on a boxes tile", rough, (5, 9)),
        ("rough, on a random tile", rough, (5, 13)),
        ("rough without boxes tiles", without_boxes, (5, 0)),
    ]
    for label, terrain, tile in cases:
        model = legged_model(terrain, tile)
        print(f"{label:28s} ngeom {model.ngeom:6d}  {step_cost_us(model):7.1f} us/step")


if __name__ == "__main__":
    main()
