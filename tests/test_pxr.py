"""``pxr`` -> ``simlab.sim.pxr``: a body's spawn pose read as Isaac Lab's task files read it from the USD stage."""

from __future__ import annotations

import math

import gymnasium as gym
import pytest
import torch

import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401  (registers the tasks)
from simlab.sim.pxr import Usd, UsdGeom
from simlab.tasks.utils.parse_cfg import parse_env_cfg


@pytest.fixture
def env():
    cfg = parse_env_cfg("simlab/Franka-Cabinet-Direct-v0", device="cpu", num_envs=2)
    env = gym.make("simlab/Franka-Cabinet-Direct-v0", cfg=cfg).unwrapped
    yield env
    env.close()


def _pose(path: str, time=None) -> tuple[torch.Tensor, torch.Tensor]:
    prim = sim_utils.get_current_stage().GetPrimAtPath(path)
    transform = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode.Default() if time is None else time)
    quat = transform.ExtractRotationQuat()
    assert quat.GetReal() == quat.real and quat.GetImaginary() == quat.imaginary
    return torch.tensor(transform.ExtractTranslation()), torch.tensor([quat.real, *quat.imaginary])


def test_the_transform_is_the_bodies_pose_as_built_in_each_env(env):
    # as built, every world is in the initial state (env.reset() would add the task's joint noise)
    for asset, bodies in (
        (env._robot, ("panda_link7", "panda_leftfinger", "panda_rightfinger")),
        (env._cabinet, ("drawer_top",)),
    ):
        name = asset.cfg.prim_path.split("/")[-1]
        for i in range(env.num_envs):
            for body in bodies:
                index = asset.find_bodies(body)[0][0]
                pos, quat = _pose(f"/World/envs/env_{i}/{name}/{body}", time=0)
                torch.testing.assert_close(pos.float(), asset.data.body_pos_w[i, index], atol=1e-5, rtol=0)
                torch.testing.assert_close(quat.float(), asset.data.body_quat_w[i, index], atol=1e-5, rtol=0)
            # the asset's own prim: its root body
            pos, quat = _pose(f"/World/envs/env_{i}/{name}")
            torch.testing.assert_close(pos.float(), asset.data.root_pos_w[i], atol=1e-5, rtol=0)
    # env 1's pose is env 0's moved by the difference of their origins
    origins = env.scene.env_origins
    shift = _pose("/World/envs/env_1/Robot/panda_link7")[0] - _pose("/World/envs/env_0/Robot/panda_link7")[0]
    torch.testing.assert_close(shift.float(), origins[1] - origins[0])


def test_the_transform_stays_the_spawn_pose_as_the_robot_moves(env):
    """USD's stage keeps the spawned pose; so does the mapping, at any time code."""
    env.reset()
    spawned = _pose("/World/envs/env_0/Robot/panda_link7")
    for _ in range(5):
        env.step(torch.ones(env.num_envs, *env.single_action_space.shape))
    index = env._robot.find_bodies("panda_link7")[0][0]
    assert (env._robot.data.body_pos_w[0, index] - spawned[0].float()).norm() > 1e-3  # the hand moved
    for time in (None, 0, 10.0):
        moved_or_not = _pose("/World/envs/env_0/Robot/panda_link7", time)
        torch.testing.assert_close(moved_or_not[0], spawned[0])
    rows = UsdGeom.Xformable("/World/envs/env_0/Robot/panda_link0").ComputeLocalToWorldTransform()
    assert rows[3][:3] == tuple(_pose("/World/envs/env_0/Robot/panda_link0")[0].tolist()) and rows[3][3] == 1.0
    assert math.isnan(Usd.TimeCode.Default()) and Usd.TimeCode.Default().IsDefault() and not Usd.TimeCode(0).IsDefault()


def test_the_rest_of_pxr_is_refused_in_one_line(env):
    with pytest.raises(ImportError, match=r"pxr\.Sdf: simlab's stage is a MuJoCo MjSpec, not USD") as refused:
        from simlab.sim.pxr import Sdf  # noqa: F401
    assert "\n" not in str(refused.value)
    with pytest.raises(AttributeError, match=r"pxr\.UsdGeom\.Mesh: .*body_pos_w"):
        UsdGeom.Mesh  # noqa: B018
    xformable = UsdGeom.Xformable(sim_utils.get_current_stage().GetPrimAtPath("/World/envs/env_0/Robot/panda_hand"))
    with pytest.raises(AttributeError, match=r"pxr\.Xformable\.AddTranslateOp"):
        xformable.AddTranslateOp()
    with pytest.raises(ValueError, match=r"no body 'Robot/nope' in the model \(bodies of 'Robot': 'Robot/"):
        UsdGeom.Xformable("/World/envs/env_0/Robot/nope").ComputeLocalToWorldTransform()
    with pytest.raises(ValueError, match=r"there are 2 envs \(env_0 to env_1\)"):
        UsdGeom.Xformable("/World/envs/env_2/Robot/panda_link7").ComputeLocalToWorldTransform()
    with pytest.raises(ValueError, match=r"'/World/envs/env_<i>/<asset>/<body>'"):
        UsdGeom.Xformable("/World/ground").ComputeLocalToWorldTransform()
