"""DirectRLEnv: construction, spaces, the step loop, autoreset, errors, render and close (on the cartpole)."""

from __future__ import annotations

import math

import gymnasium as gym
import pytest
import torch
from conftest import DEVICES

from simlab.envs import DirectRLEnv, DirectRLEnvCfg
from simlab.envs.utils.spaces import sample_space, spec_to_gym_space
from simlab.sim import SimulationCfg, SimulationContext
from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv, CartpoleEnvCfg


def make_cfg(num_envs: int = 4, device: str = "cpu", **fields) -> CartpoleEnvCfg:
    cfg = CartpoleEnvCfg(seed=0, **fields)
    cfg.scene.num_envs = num_envs
    cfg.sim.device = device
    return cfg


class CountingCartpole(CartpoleEnv):
    """Counts the hook calls of the step loop."""

    def __init__(self, *args, **kwargs):
        self.calls = {"pre": 0, "apply": 0}
        super().__init__(*args, **kwargs)

    def _pre_physics_step(self, actions):
        self.calls["pre"] += 1
        super()._pre_physics_step(actions)

    def _apply_action(self):
        self.calls["apply"] += 1
        super()._apply_action()


class CriticCartpole(CartpoleEnv):
    """An asymmetric actor-critic variant: the critic also sees the applied force."""

    def _get_states(self):
        return torch.cat([self._get_observations()["policy"], self.actions], dim=-1)


def test_spaces_metadata_and_timing():
    env = CartpoleEnv(make_cfg(num_envs=3))
    assert isinstance(env, gym.Env)
    assert env.num_envs == 3 and env.device == "cpu"
    assert env.single_observation_space["policy"].shape == (4,)
    assert env.single_action_space.shape == (1,)
    assert env.observation_space.shape == (3, 4) and env.action_space.shape == (3, 1)
    assert env.state_space is None and "critic" not in env.single_observation_space.spaces
    assert env.metadata["autoreset_mode"] == gym.vector.AutoresetMode.SAME_STEP
    assert env.physics_dt == pytest.approx(1 / 120) and env.step_dt == pytest.approx(1 / 60)
    assert env.metadata["render_fps"] == pytest.approx(60.0)
    assert env.max_episode_length == math.ceil(5.0 / (2 / 120)) == 300
    assert env.actions.shape == (3, 1) and not env.actions.any()
    env.close()


def test_step_returns_batched_tensors_and_counts_steps():
    env = CountingCartpole(make_cfg(num_envs=4))
    obs, extras = env.reset()
    assert set(obs) == {"policy"} and obs["policy"].shape == (4, 4)
    physics_steps = env.sim._step_count
    obs, reward, terminated, truncated, extras = env.step(torch.zeros(4, 1))
    assert obs["policy"].shape == (4, 4) and reward.shape == (4,)
    assert terminated.dtype == torch.bool and truncated.dtype == torch.bool
    assert env.calls == {"pre": 1, "apply": env.cfg.decimation}
    assert env.sim._step_count - physics_steps == env.cfg.decimation
    assert env.common_step_counter == 1 and env.episode_length_buf.tolist() == [1, 1, 1, 1]
    assert extras["time_outs"] is truncated


def test_time_out_truncates_and_resets_in_the_same_step():
    env = CartpoleEnv(make_cfg(num_envs=2, episode_length_s=0.1))  # 6 env steps of 1/60 s
    env.reset()
    assert env.max_episode_length == 6
    for step in range(1, 6):
        _, _, terminated, truncated, _ = env.step(torch.zeros(2, 1))
        assert not terminated.any()
        assert truncated.all() == (step == 5), f"step {step}"  # Isaac Lab: length >= max - 1
    assert env.episode_length_buf.tolist() == [0, 0]
    assert env.reset_buf.all()


def test_termination_autoresets_and_keeps_the_final_observation():
    env = CartpoleEnv(make_cfg(num_envs=3))
    env.reset()
    cart = env._cart_dof_idx[0]
    # push env 1's cart beyond the 3 m bound by hand
    pos = env.cartpole.data.joint_pos.clone()
    pos[1, cart] = 3.5
    env.cartpole.write_joint_state_to_sim(pos, torch.zeros_like(pos))
    obs, reward, terminated, truncated, extras = env.step(torch.zeros(3, 1))
    assert terminated.tolist() == [False, True, False] and not truncated.any()
    final = extras["final_obs"]["policy"]
    assert final[1, 2] > 3.0, "final_obs shows the state that terminated"
    assert obs["policy"][1, 2] == 0.0, "the returned observation is the reset one"
    assert abs(obs["policy"][1, 0]) <= 0.25 * math.pi + 1e-6
    torch.testing.assert_close(final[[0, 2]], obs["policy"][[0, 2]])
    assert env.episode_length_buf.tolist() == [1, 0, 1]
    assert reward[1] == pytest.approx(
        -2.0 - 0.01 * abs(float(final[1, 3])) - 0.005 * abs(float(final[1, 1])) - float(final[1, 0]) ** 2, abs=1e-5
    )


def test_bad_actions_are_rejected():
    env = CartpoleEnv(make_cfg(num_envs=2))
    env.reset()
    with pytest.raises(ValueError, match="NaN"):
        env.step(torch.tensor([[0.0], [float("nan")]]))
    with pytest.raises(ValueError, match=r"shape \(2, 1\)"):
        env.step(torch.zeros(2, 3))


def test_config_errors_are_clear():
    with pytest.raises(ValueError, match="decimation"):
        CartpoleEnv(make_cfg(decimation=0))
    cfg = DirectRLEnvCfg()
    with pytest.raises(TypeError, match="missing field"):
        CartpoleEnv(cfg)
    with pytest.raises(ValueError, match="render_mode"):
        CartpoleEnv(make_cfg(), render_mode="video")


def test_seeded_reset_is_reproducible():
    env = CartpoleEnv(make_cfg(num_envs=4))
    first, _ = env.reset(seed=7)
    first = first["policy"].clone()
    env.step(torch.ones(4, 1))
    second, _ = env.reset(seed=7)
    torch.testing.assert_close(first, second["policy"])
    assert first[:, 0].abs().max() > 0, "the pole angle is randomized at reset"


def test_state_space_adds_a_critic_observation():
    env = CriticCartpole(make_cfg(num_envs=2, state_space=5))
    assert env.single_observation_space["critic"].shape == (5,) and env.state_space.shape == (2, 5)
    obs, _ = env.reset()
    assert obs["critic"].shape == (2, 5)
    obs, *_ = env.step(0.5 * torch.ones(2, 1))
    torch.testing.assert_close(obs["critic"][:, 4], torch.full((2,), 50.0))


def test_env_owns_a_fresh_simulation_and_close_releases_it():
    stale = SimulationContext(SimulationCfg(device="cpu"))
    env = CartpoleEnv(make_cfg())
    assert SimulationContext.instance() is env.sim is not stale
    env.close()
    assert SimulationContext.instance() is None
    env.close()  # idempotent


def test_render_rgb_array():
    pytest.importorskip("simlab.sim.renderer")
    cfg = make_cfg(num_envs=2)
    cfg.viewer.resolution = (64, 48)
    cfg.viewer.eye, cfg.viewer.lookat, cfg.viewer.origin_type = (4.0, 0.0, 3.0), (0.0, 0.0, 2.0), "env"
    env = CartpoleEnv(cfg, render_mode="rgb_array")
    env.reset()
    frame = env.render()
    assert frame.shape == (48, 64, 3) and frame.dtype.name == "uint8" and frame.std() > 0
    assert CartpoleEnv(make_cfg(), render_mode=None).render() is None


def test_space_specs():
    assert spec_to_gym_space(3) == gym.spaces.Box(-math.inf, math.inf, (3,))
    assert spec_to_gym_space([2, 3]).shape == (2, 3)
    assert spec_to_gym_space({4}) == gym.spaces.Discrete(4)
    assert spec_to_gym_space([{2}, {5}]) == gym.spaces.MultiDiscrete([2, 5])
    composite = spec_to_gym_space({"joints": 7, "grip": {2}, "pair": (1, {3})})
    assert isinstance(composite["pair"], gym.spaces.Tuple)
    box = gym.spaces.Box(-1, 1, (2,))
    assert spec_to_gym_space(box) is box
    with pytest.raises(ValueError, match="Unsupported space spec"):
        spec_to_gym_space("7")
    sample = sample_space(composite, "cpu", batch_size=5)
    assert sample["joints"].shape == (5, 7) and sample["grip"].shape == (5, 1) and sample["grip"].dtype == torch.int64
    zeros = sample_space(spec_to_gym_space(3), "cpu", batch_size=4, fill_value=0)
    assert zeros.shape == (4, 3) and not zeros.any()


@pytest.mark.parametrize("device", DEVICES)
def test_steps_on_each_backend(device):
    env = CartpoleEnv(make_cfg(num_envs=8, device=device))
    obs, _ = env.reset()
    for _ in range(20):
        obs, reward, terminated, truncated, extras = env.step(2 * torch.rand(8, 1, device=device) - 1)
    assert obs["policy"].device.type == torch.device(device).type
    assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    assert isinstance(env, DirectRLEnv)


def test_events_of_the_event_manager_apply():
    import simlab.envs.mdp as mdp
    from simlab.managers import EventTermCfg, SceneEntityCfg
    from simlab.utils import configclass

    @configclass
    class EventsCfg:
        heavy_pole = EventTermCfg(
            func=mdp.randomize_rigid_body_mass,
            mode="startup",
            params={
                "asset_cfg": SceneEntityCfg("cartpole", body_names="pole"),
                "mass_distribution_params": (2.0, 2.0),
                "operation": "scale",
            },
        )

    env = CartpoleEnv(make_cfg(num_envs=2, events=EventsCfg()))
    pole = env.cartpole.find_bodies("pole")[0][0]
    torch.testing.assert_close(env.cartpole.data.body_mass[:, pole], 2 * env.cartpole.data.default_mass[:, pole])


def test_final_observations_can_be_left_out():
    import simlab.tasks  # noqa: F401
    from simlab.tasks.utils import parse_env_cfg

    seen = {}
    for final in (True, False):
        cfg = parse_env_cfg("simlab/Cartpole-Direct-v0", device="cpu", num_envs=2)
        cfg.final_observations = final
        env = gym.make("simlab/Cartpole-Direct-v0", cfg=cfg).unwrapped
        try:
            env.reset(seed=0)
            calls = []
            compute = env._get_observations
            env._get_observations = lambda calls=calls, compute=compute: calls.append(1) or compute()
            *_, extras = env.step(torch.zeros(2, 1))
            seen[final] = (len(calls), "final_obs" in extras)
        finally:
            env.close()
    assert seen == {True: (2, True), False: (1, False)}
