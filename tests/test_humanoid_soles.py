"""The rough G1's soles on MuJoCo Warp's height fields (issue 39).

MuJoCo Warp warns at start-up that its HFIELD-CAPSULE and HFIELD-BOX pairs get "at most 1 contact"
(its multi-contact CCD), yet its height-field kernel runs CCD per prism of the tile under a geom
and keeps up to four contacts per pair (the deepest, the farthest from it, and two that widen the
patch), as MJX does. A G1 sole is two capsules: one contact per pair would leave a sole two points,
a line it could roll about; with four it rests on a patch. Measured standing at its default pose
(32 worlds, 3 s, scripts/benchmarks/humanoid_stance.py): see docs/humanoids.md. With a copy of MuJoCo
Warp whose kernel keeps one contact per pair this test fails (soles of 1-2 contacts) and the standing
G1 tilts and slides more.
"""

from __future__ import annotations

import mujoco
import numpy as np
import torch


def _rough_g1(engine: str, worlds: int):
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    task = "simlab/Velocity-Rough-G1-v0"
    cfg = parse_env_cfg(task, device="cpu", num_envs=worlds)
    cfg.sim.engine, cfg.sim.use_cuda_graph, cfg.seed = engine, False, 0
    return gym.make(task, cfg=cfg).unwrapped


def test_a_standing_rough_g1_rests_each_sole_on_several_contacts_on_mujoco_warp():
    """Eight G1s stand 0.5 s at their default pose (zero actions) on the rough tiles on MuJoCo Warp
    (Warp's CPU device). Every sole on the ground touches the height field at three or more points
    on average, and most soles at three or more: a single contact per capsule would give two."""
    env = _rough_g1("mujoco_warp", 8)
    try:
        env.reset()
        model, data = env.sim.model, env.sim.physics.wp_data
        actions = torch.zeros(env.num_envs, env.action_manager.total_action_dim)
        for _ in range(round(0.5 / env.step_dt)):
            env.step(actions)
        soles = {}
        for side in ("left", "right"):
            body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"Robot/{side}_ankle_roll_link")
            soles.update({int(g): side for g in np.flatnonzero(model.geom_bodyid == body)})
        hfield = model.geom_type == mujoco.mjtGeom.mjGEOM_HFIELD
        n = int(data.nacon.numpy()[0])
        counts = np.zeros((env.num_envs, 2), dtype=int)
        for (g1, g2), world, dist in zip(
            data.contact.geom.numpy()[:n], data.contact.worldid.numpy()[:n], data.contact.dist.numpy()[:n], strict=True
        ):
            sole = soles.get(int(g2), soles.get(int(g1)))
            if sole is not None and dist < 0.0 and (hfield[g1] or hfield[g2]):
                counts[world, ("left", "right").index(sole)] += 1
        touching = counts[counts > 0]
        assert touching.size >= 12, f"the G1s stand on the tiles: contacts per sole {counts.tolist()}"
        assert touching.mean() >= 3.0, f"contacts per sole on the height field {counts.tolist()}"
        assert (touching >= 3).mean() >= 0.75, f"contacts per sole on the height field {counts.tolist()}"
    finally:
        env.close()
