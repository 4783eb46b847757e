"""Physics step cost of a small legged body standing on each kind of terrain, with the box tiles of
ROUGH_TERRAINS_CFG (stairs, box grids) built as box geoms or as height fields.

No simlab env: a box body on four capsule legs, stepped on an infinite plane and on tiles of
ROUGH_TERRAINS_CFG (seed 1, curriculum). On the CPU one world steps with ``mj_step``; with
``--device cuda`` ``--num_envs`` worlds step together in MuJoCo Warp (``physics.step``, graphed).
The variants are timed in alternating rounds (the machine may be shared and noisy); the median
round is reported.

    simlab bench terrain
    simlab bench terrain --device cuda --num_envs 4096
"""

from __future__ import annotations

import argparse
import statistics
import time

import mujoco
import numpy as np

from simlab.sim.spawners.materials import RigidBodyMaterialCfg
from simlab.terrains import ROUGH_TERRAINS_CFG, TerrainGenerator, TerrainGeneratorCfg
from simlab.terrains.mjspec_terrain import add_terrain_to_spec

TILES = {"stairs": (5, 0), "inverted stairs": (5, 4), "box grid": (5, 9), "random rough": (5, 13)}


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


class CpuStepper:
    def __init__(self, model: mujoco.MjModel, steps: int):
        self.model, self.data, self.steps = model, mujoco.MjData(model), steps
        for _ in range(200):  # settle on the ground
            mujoco.mj_step(model, self.data)

    def round_us(self) -> float:
        start = time.perf_counter()
        for _ in range(self.steps):
            mujoco.mj_step(self.model, self.data)
        return (time.perf_counter() - start) / self.steps * 1e6


class GpuStepper:
    """``num_envs`` worlds in MuJoCo Warp; reports microseconds per step of all worlds."""

    def __init__(self, model: mujoco.MjModel, steps: int, num_envs: int, device: str):
        import torch

        from simlab.sim.backends import make_backend

        self.torch, self.steps = torch, steps
        self.physics = make_backend(model, num_envs, device)
        for _ in range(200):
            self.physics.step(1, forward=False)
        torch.cuda.synchronize()

    def round_us(self) -> float:
        self.torch.cuda.synchronize()
        start = time.perf_counter()
        for _ in range(self.steps):
            self.physics.step(1, forward=False)
        self.torch.cuda.synchronize()
        return (time.perf_counter() - start) / self.steps * 1e6


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="simlab bench terrain", description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--num_envs", type=int, default=4096, help="worlds on the GPU")
    parser.add_argument("--steps", type=int, default=500, help="steps per round")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--fine_scale", type=float, default=None, help="also box tiles sampled this finely [m]")
    args = parser.parse_args(argv)

    rough = ROUGH_TERRAINS_CFG.replace(seed=1, curriculum=True)
    variants = {
        "boxes": rough.replace(box_tiles_as="boxes"),
        "height_field": rough.replace(box_tiles_as="height_field"),
    }
    if args.fine_scale:
        variants[f"hf {args.fine_scale} m"] = rough.replace(box_height_field_scale=args.fine_scale)
    cases = [("plane", "-", None, (0, 0))]
    cases += [(tile, name, cfg, at) for tile, at in TILES.items() for name, cfg in variants.items()]
    steppers = []
    for tile, variant, cfg, at in cases:
        model = legged_model(cfg, at)
        if args.device == "cpu":
            stepper = CpuStepper(model, args.steps)
        else:
            stepper = GpuStepper(model, args.steps, args.num_envs, args.device)
        steppers.append((tile, variant, model.ngeom, stepper, []))
    for _ in range(args.rounds):
        for *_, stepper, times in steppers:
            times.append(stepper.round_us())
    unit = "us per mj_step" if args.device == "cpu" else f"us per step of {args.num_envs} worlds"
    print(f"{args.device}: median of {args.rounds} alternating rounds of {args.steps} steps, {unit}")
    for tile, variant, ngeom, _, times in steppers:
        rounds = np.round(times, 1).tolist()
        print(f"  {tile:16s} {variant:13s} ngeom {ngeom:6d}  {statistics.median(times):9.1f}  (rounds {rounds})")


if __name__ == "__main__":
    main()
