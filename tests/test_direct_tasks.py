"""The direct tasks: spaces, rewards of hand-set states, termination rules, and stepping on each backend."""

from __future__ import annotations

import math

import pytest
import torch
from conftest import DEVICES

from simlab.tasks.direct.ant.ant_env import AntEnv, AntEnvCfg
from simlab.tasks.direct.cart_double_pendulum.cart_double_pendulum_env import (
    CartDoublePendulumEnv,
    CartDoublePendulumEnvCfg,
)
from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv, CartpoleEnvCfg, compute_rewards
from simlab.tasks.direct.humanoid.humanoid_env import HumanoidEnv, HumanoidEnvCfg
from simlab.tasks.direct.locomotion.locomotion_env import resolve_joint_gears
from simlab.terrains import TerrainImporterCfg

SINGLE_AGENT = {"cartpole": (CartpoleEnv, CartpoleEnvCfg, 1, 4), "ant": (AntEnv, AntEnvCfg, 8, 36),
                "humanoid": (HumanoidEnv, HumanoidEnvCfg, 21, 75)}  # fmt: skip


def make(env_class, cfg_class, num_envs: int = 2, device: str = "cpu", **fields):
    cfg = cfg_class(seed=0, **fields)
    cfg.scene.num_envs = num_envs
    cfg.sim.device = device
    return env_class(cfg)


def set_joints(env, robot, values: dict[str, float], velocities: dict[str, float] | None = None):
    """Write joint positions (and velocities) by name in every env."""
    pos, vel = robot.data.joint_pos.clone(), torch.zeros_like(robot.data.joint_vel)
    for name, value in values.items():
        pos[:, robot.find_joints(name)[0][0]] = value
    for name, value in (velocities or {}).items():
        vel[:, robot.find_joints(name)[0][0]] = value
    robot.write_joint_state_to_sim(pos, vel)
    env.sim.forward()


# -- spaces and stepping ----------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(SINGLE_AGENT))
def test_spaces_and_shapes(name):
    env_class, cfg_class, num_actions, num_obs = SINGLE_AGENT[name]
    env = make(env_class, cfg_class, num_envs=3)
    assert env.single_action_space.shape == (num_actions,)
    assert env.single_observation_space["policy"].shape == (num_obs,)
    obs, _ = env.reset()
    assert obs["policy"].shape == (3, num_obs)
    obs, reward, terminated, truncated, _ = env.step(torch.zeros(3, num_actions))
    assert obs["policy"].shape == (3, num_obs) and reward.shape == terminated.shape == truncated.shape == (3,)
    env.close()


@pytest.mark.parametrize("device", DEVICES)
@pytest.mark.parametrize("name", ["cartpole", "ant", "humanoid", "cart_double_pendulum"])
def test_each_task_steps_on_each_backend(name, device):
    if name == "cart_double_pendulum":
        env = make(CartDoublePendulumEnv, CartDoublePendulumEnvCfg, num_envs=4, device=device)
        env.reset()
        for _ in range(10):
            obs, reward, *_ = env.step({a: 2 * torch.rand(4, 1, device=device) - 1 for a in env.possible_agents})
        values = [*obs.values(), *reward.values()]
    else:
        env_class, cfg_class, num_actions, _ = SINGLE_AGENT[name]
        env = make(env_class, cfg_class, num_envs=4, device=device)
        env.reset()
        for _ in range(10):
            obs, reward, *_ = env.step(2 * torch.rand(4, num_actions, device=device) - 1)
        values = [obs["policy"], reward]
    assert all(torch.isfinite(v).all() and v.device.type == torch.device(device).type for v in values)
    env.close()


# -- cartpole -----------------------------------------------------------------------------------------


def test_cartpole_reward_function_is_torchscript_and_matches_isaac_lab_terms():
    assert isinstance(compute_rewards, torch.jit.ScriptFunction)
    pole_pos, pole_vel = torch.tensor([0.5, 0.0]), torch.tensor([2.0, 0.0])
    cart_pos, cart_vel = torch.tensor([1.0, 0.0]), torch.tensor([-3.0, 0.0])
    terminated = torch.tensor([False, True])
    reward = compute_rewards(1.0, -2.0, -1.0, -0.01, -0.005, pole_pos, pole_vel, cart_pos, cart_vel, terminated)
    expected_0 = 1.0 - 0.25 - 0.01 * 3.0 - 0.005 * 2.0
    torch.testing.assert_close(reward, torch.tensor([expected_0, -2.0]))


def test_cartpole_rewards_of_hand_set_states():
    env = make(CartpoleEnv, CartpoleEnvCfg, num_envs=2)
    env.reset()
    set_joints(
        env, env.cartpole, {"cart_to_pole": 0.3, "slider_to_cart": 1.0}, {"cart_to_pole": -1.0, "slider_to_cart": 2.0}
    )
    env.reset_terminated[:] = torch.tensor([False, True])
    reward = env._get_rewards()
    torch.testing.assert_close(reward, torch.tensor([1.0 - 0.09 - 0.02 - 0.005, -2.0 - 0.09 - 0.02 - 0.005]))
    # the action is a force of 100 N per unit on the cart only
    env.step(torch.tensor([[0.5], [-1.0]]))
    effort = env.cartpole.data.joint_effort_target
    torch.testing.assert_close(effort[:, env._cart_dof_idx[0]], torch.tensor([50.0, -100.0]))
    assert not effort[:, env._pole_dof_idx[0]].any()


@pytest.mark.parametrize(
    ("joints", "done"),
    [
        ({"slider_to_cart": 2.9, "cart_to_pole": 1.5}, False),
        ({"slider_to_cart": 3.1}, True),
        ({"slider_to_cart": -3.1}, True),
        ({"cart_to_pole": math.pi / 2 + 0.05}, True),
        ({"cart_to_pole": -math.pi / 2 - 0.05}, True),
    ],
)
def test_cartpole_termination_rules(joints, done):
    env = make(CartpoleEnv, CartpoleEnvCfg, num_envs=1)
    env.reset()
    set_joints(env, env.cartpole, {"slider_to_cart": 0.0, "cart_to_pole": 0.0, **joints})
    terminated, time_out = env._get_dones()
    assert terminated.item() is done and not time_out.item()


def test_cartpole_reset_samples_the_pole_angle_within_a_quarter_turn():
    env = make(CartpoleEnv, CartpoleEnvCfg, num_envs=64)
    obs, _ = env.reset()
    pole, cart = obs["policy"][:, 0], obs["policy"][:, 2]
    assert pole.abs().max() <= 0.25 * math.pi and pole.std() > 0.2
    assert not cart.any() and not obs["policy"][:, [1, 3]].any()


# -- locomotion: ant and humanoid ---------------------------------------------------------------------


def test_humanoid_gears_are_mapped_by_joint_name():
    env = make(HumanoidEnv, HumanoidEnvCfg, num_envs=1)
    gears = dict(zip(env.robot.joint_names, env.joint_gears.tolist()))
    assert len(gears) == 21
    expected = {"lower_waist:0": 67.5, "lower_waist:1": 67.5, "pelvis": 67.5, "right_thigh:0": 45, "right_thigh:1": 135,
                "left_thigh:2": 45, "right_shin": 90, "left_foot:1": 22.5, "right_upper_arm:2": 67.5,
                "left_lower_arm": 45}  # fmt: skip
    for name, gear in expected.items():
        assert gears[name] == gear, name
    # torque = action_scale * gear * action, written as effort targets
    action = torch.linspace(-1, 1, 21).unsqueeze(0)
    env.reset()
    env.step(action)
    torch.testing.assert_close(env.robot.data.joint_effort_target, env.cfg.action_scale * env.joint_gears * action)


def test_joint_gears_errors_name_the_problem():
    names = ["a", "b"]
    with pytest.raises(ValueError, match="2 joints"):
        resolve_joint_gears([1.0, 2.0, 3.0], names, "cpu")
    with pytest.raises(ValueError, match=r"no gear for joints \['b'\]"):
        resolve_joint_gears({"a": 1.0}, names, "cpu")


def test_humanoid_falls_and_terminates_under_zero_action():
    env = make(HumanoidEnv, HumanoidEnvCfg, num_envs=2)
    env.reset()
    for step in range(env.max_episode_length):  # noqa: B007 - the count is reported
        _, reward, terminated, truncated, extras = env.step(torch.zeros(2, 21))
        if terminated.any():
            break
    assert terminated.all() and not truncated.any(), f"still standing after {step + 1} steps"
    assert step * env.step_dt < 3.0, "a limp humanoid falls within seconds"
    torch.testing.assert_close(reward, torch.full((2,), env.cfg.death_cost))
    assert (extras["final_obs"]["policy"][:, 0] < env.cfg.termination_height).all()
    assert env.torso_position[:, 2].tolist() == pytest.approx([1.34, 1.34]), "reset to the spawn height"


@pytest.mark.parametrize(("env_class", "cfg_class"), [(AntEnv, AntEnvCfg), (HumanoidEnv, HumanoidEnvCfg)])
def test_locomotion_stands_on_a_terrain_importers_plane_as_on_a_ground_plane(env_class, cfg_class):
    """Isaac Lab's ant and humanoid configs give the terrain as a ``TerrainImporterCfg`` plane."""
    heights = []
    for terrain in (None, TerrainImporterCfg(prim_path="/World/ground", terrain_type="plane", collision_group=-1)):
        env = make(env_class, cfg_class, num_envs=2, **({} if terrain is None else {"terrain": terrain}))
        env.reset()
        for _ in range(20):  # zero torques: the robot settles onto the floor
            env.step(torch.zeros(2, env.cfg.action_space))
        heights.append(env.robot.data.root_pos_w[:, 2].clone())
        env.close()
    assert (heights[1] > 0.2).all()  # on the plane, not fallen through it
    torch.testing.assert_close(heights[1], heights[0], atol=0.02, rtol=0)


@pytest.mark.parametrize(("env_class", "cfg_class"), [(AntEnv, AntEnvCfg), (HumanoidEnv, HumanoidEnvCfg)])
def test_locomotion_termination_height(env_class, cfg_class):
    env = make(env_class, cfg_class, num_envs=2)
    env.reset()
    root = env.robot.data.default_root_state.clone()
    root[:, :3] += env.scene.env_origins
    root[0, 2] = env.cfg.termination_height - 0.01
    root[1, 2] = env.cfg.termination_height + 0.01
    env.robot.write_root_pose_to_sim(root[:, :7])
    terminated, time_out = env._get_dones()
    assert terminated.tolist() == [True, False] and not time_out.any()


def test_ant_observations_and_rewards_of_the_spawn_pose():
    env = make(AntEnv, AntEnvCfg, num_envs=2)
    obs, _ = env.reset()
    obs = obs["policy"]
    assert obs[:, 0].tolist() == pytest.approx([0.5, 0.5])  # torso height
    assert not obs[:, 1:7].any()  # torso-frame velocities
    assert obs[:, 10].tolist() == pytest.approx([1.0, 1.0]) and obs[:, 11].tolist() == pytest.approx([1.0, 1.0])
    # joint positions scaled by their limits: the front-left ankle at 45 deg in [30, 100] deg
    ankle = env.robot.joint_names.index("front_left_foot")
    assert obs[0, 12 + ankle].item() == pytest.approx((2 * 45 - 130) / 70, abs=1e-4)
    # standing still, upright, facing the target: alive + up + heading, no progress, no costs
    env.reset_terminated[:] = False
    reward = env._get_rewards()
    expected = env.cfg.alive_reward_scale + env.cfg.up_weight + env.cfg.heading_weight
    torch.testing.assert_close(reward, torch.full((2,), expected))
    # progress: moving 1 cm towards the target in one physics dt is worth 1 per unit potential
    root = env.robot.data.root_state_w.clone()
    root[:, 0] += 0.01
    env.robot.write_root_pose_to_sim(root[:, :7])
    env._compute_intermediate_values()
    torch.testing.assert_close(
        env._get_rewards(), torch.full((2,), expected + 0.01 / env.cfg.sim.dt), atol=2e-2, rtol=0
    )
    # a fallen robot gets the death cost instead
    env.reset_terminated[:] = True
    torch.testing.assert_close(env._get_rewards(), torch.full((2,), env.cfg.death_cost))
    # a joint at its upper limit costs 1
    env.reset_terminated[:] = False
    set_joints(env, env.robot, {"front_left_foot": 100 * math.pi / 180})
    env._compute_intermediate_values()
    env._compute_intermediate_values()  # no progress between the two
    torch.testing.assert_close(env._get_rewards(), torch.full((2,), expected - 1.0), atol=1e-4, rtol=0)
