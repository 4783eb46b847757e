"""Each manager on the small cartpole scene: terms, settings, logs, and errors that name the term."""

from __future__ import annotations

import pytest
import torch

import simlab.envs.mdp as mdp
from simlab.envs import ManagerBasedRLEnv
from simlab.managers import CurriculumTermCfg as CurrTerm
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.managers.manager_base import ManagerTermBase
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg
from simlab.utils import configclass
from simlab.utils.modifiers import DigitalFilterCfg, ModifierCfg
from simlab.utils.noise import GaussianNoiseCfg, UniformNoiseCfg

N = 4
POLE = SceneEntityCfg("robot", joint_names=["cart_to_pole"])
CART = SceneEntityCfg("robot", joint_names=["slider_to_cart"])


def cartpole_cfg(**fields) -> CartpoleEnvCfg:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = N
    cfg.sim.device = "cpu"
    cfg.seed = 0
    for key, value in fields.items():
        setattr(cfg, key, value)
    return cfg


def record(env, env_ids, tag: str) -> None:
    """An event that remembers when it ran and for which envs."""
    env.__dict__.setdefault("calls", []).append((tag, env_ids.tolist(), env.common_step_counter))


# -- observations ----------------------------------------------------------------------------------


@configclass
class ProcessedObsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        pos = ObsTerm(func=mdp.joint_pos, scale=2.0, clip=(-0.1, 0.1))
        vel = ObsTerm(func=mdp.joint_vel, noise=UniformNoiseCfg(n_min=-0.5, n_max=0.5))

        def __post_init__(self):
            self.enable_corruption = True

    @configclass
    class CriticCfg(ObsGroup):
        pos = ObsTerm(func=mdp.joint_pos, history_length=3, noise=GaussianNoiseCfg(std=1.0))
        vel = ObsTerm(func=mdp.joint_vel, modifiers=[ModifierCfg(func=lambda x, k: x * k, params={"k": 3.0})])
        filtered = ObsTerm(func=mdp.joint_pos, modifiers=[DigitalFilterCfg(A=[], B=[0.5, 0.5])])

        def __post_init__(self):
            self.concatenate_terms = False  # a dict of terms, noise off (enable_corruption=False)

    policy: PolicyCfg = PolicyCfg()
    critic: CriticCfg = CriticCfg()


def test_observation_scale_clip_noise_history_modifiers():
    env = ManagerBasedRLEnv(cartpole_cfg(observations=ProcessedObsCfg()))
    obs, _ = env.reset()
    data = env.scene["robot"].data
    assert env.observation_manager.group_obs_dim["policy"] == (4,)
    assert env.single_observation_space["critic"]["pos"].shape == (6,)
    pos, vel = data.joint_pos.clone(), data.joint_vel.clone()
    torch.testing.assert_close(obs["policy"][:, :2], pos.clip(-0.1, 0.1) * 2.0)  # clip, then scale
    noise = obs["policy"][:, 2:] - vel
    assert noise.abs().max() <= 0.5 and noise.abs().max() > 0.01
    critic = obs["critic"]
    assert isinstance(critic, dict)
    torch.testing.assert_close(critic["pos"], pos.repeat(1, 3))  # history filled with the first value; no noise
    torch.testing.assert_close(critic["vel"], vel * 3.0)
    torch.testing.assert_close(critic["filtered"], 0.5 * pos)  # y = (x[n] + x[n-1]) / 2 with x[-1] = 0
    history = [pos]
    for _ in range(2):
        obs, *_ = env.step(torch.zeros(N, 1))
        history.append(env.scene["robot"].data.joint_pos.clone())
    torch.testing.assert_close(obs["critic"]["pos"], torch.cat(history, dim=1))  # oldest first
    torch.testing.assert_close(obs["critic"]["filtered"], 0.5 * (history[-1] + history[-2]))
    env.close()


# -- actions -----------------------------------------------------------------------------------------


@configclass
class PositionActionsCfg:
    pole = mdp.JointPositionActionCfg(
        asset_name="robot", joint_names=["cart_to_pole"], scale=0.5, clip={".*": (-0.2, 0.2)}
    )
    cart = mdp.RelativeJointPositionActionCfg(
        asset_name="robot", joint_names=["slider_to_cart"], scale={"slider.*": 2.0}
    )


def test_position_actions_scale_offset_clip():
    env = ManagerBasedRLEnv(cartpole_cfg(actions=PositionActionsCfg()))
    env.reset()
    am = env.action_manager
    assert am.active_terms == ["pole", "cart"] and am.total_action_dim == 2
    action = torch.tensor([[0.2, 0.1], [1.0, -0.1], [-0.1, 0.0], [-4.0, 0.3]])
    am.process_action(action)
    pole = am.get_term("pole").processed_actions[:, 0]
    torch.testing.assert_close(pole, torch.tensor([0.1, 0.2, -0.05, -0.2]))  # 0.5 a + default 0, clipped
    before = env.scene["robot"].data.joint_pos[:, 0].clone()
    am.apply_action()
    target = env.scene["robot"].data.joint_pos_target
    torch.testing.assert_close(target[:, 1], pole)
    torch.testing.assert_close(target[:, 0], before + 2.0 * action[:, 1])
    torch.testing.assert_close(am.action, action)
    am.process_action(torch.zeros(N, 2))
    torch.testing.assert_close(am.prev_action, action)
    assert "pole" in str(am) and "cart" in str(am)
    env.close()


def test_velocity_action_sets_velocity_targets():
    @configclass
    class VelocityActionsCfg:
        cart = mdp.JointVelocityActionCfg(asset_name="robot", joint_names=["slider_to_cart"], scale=3.0)

    env = ManagerBasedRLEnv(cartpole_cfg(actions=VelocityActionsCfg()))
    env.reset()
    env.action_manager.process_action(torch.ones(N, 1))
    env.action_manager.apply_action()
    torch.testing.assert_close(env.scene["robot"].data.joint_vel_target[:, 0], torch.full((N,), 3.0))
    env.close()


# -- events ----------------------------------------------------------------------------------------


def test_event_modes_interval_and_min_steps_between_resets():
    cfg = cartpole_cfg()
    dt = cfg.sim.dt * cfg.decimation
    cfg.events.startup = EventTerm(func=record, mode="startup", params={"tag": "startup"})
    cfg.events.every_2 = EventTerm(
        func=record, mode="interval", interval_range_s=(2 * dt, 2 * dt), params={"tag": "every_2"}
    )
    cfg.events.global_3 = EventTerm(
        func=record, mode="interval", interval_range_s=(3 * dt, 3 * dt), is_global_time=True, params={"tag": "global_3"}
    )
    cfg.events.rare_reset = EventTerm(func=record, mode="reset", min_step_count_between_reset=5, params={"tag": "rare"})
    env = ManagerBasedRLEnv(cfg)
    calls = env.calls
    assert calls == [("startup", [0, 1, 2, 3], 0)]
    env.reset()
    assert calls[-1] == ("rare", [0, 1, 2, 3], 0)
    for _ in range(6):
        env.step(torch.zeros(N, 1))
    ticks = [(tag, step) for tag, ids, step in calls if tag != "startup" and tag != "rare"]
    assert [s for t, s in ticks if t == "every_2"] == [2, 4, 6]
    assert [s for t, s in ticks if t == "global_3"] == [3, 6]
    # An env reset within 5 env steps of its last application skips the event.
    env.reset(env_ids=[1])
    assert calls[-1] == ("rare", [1], 6)
    n_calls = len(calls)
    env.reset(env_ids=[1])
    assert len(calls) == n_calls
    for _ in range(4):
        env.step(torch.zeros(N, 1))
    env.reset(env_ids=[1, 2])
    assert calls[-1] == ("rare", [2], 10)
    assert "every_2" in str(env.event_manager)
    env.close()


# -- rewards and terminations ------------------------------------------------------------------------


def test_reward_weights_logs_and_termination_kinds():
    @configclass
    class Rewards:
        alive = RewTerm(func=mdp.is_alive, weight=2.0)
        unused = RewTerm(func=mdp.joint_vel_l2, weight=0.0)

    @configclass
    class Terminations:
        time_out = DoneTerm(func=mdp.time_out, time_out=True)
        tilted = DoneTerm(func=mdp.joint_pos_out_of_manual_limit, params={"asset_cfg": POLE, "bounds": (-10.0, 0.5)})

    env = ManagerBasedRLEnv(cartpole_cfg(rewards=Rewards(), terminations=Terminations(), episode_length_s=0.5))
    env.reset()
    _, rew, *_ = env.step(torch.zeros(N, 1))
    alive = ~env.termination_manager.terminated
    torch.testing.assert_close(rew, 2.0 * alive.float() * env.step_dt)
    assert env.termination_manager.active_terms == ["time_out", "tilted"]
    for _ in range(env.max_episode_length * 2):
        _, _, term, trunc, extras = env.step(torch.zeros(N, 1))
        if trunc.any():
            break
    assert trunc.any()
    log = extras["log"]
    assert set(log) >= {"Episode_Reward/alive", "Episode_Reward/unused", "Episode_Termination/time_out"}
    assert log["Episode_Reward/unused"] == 0.0
    assert "alive" in str(env.reward_manager) and "tilted" in str(env.termination_manager)
    env.close()


# -- commands and curricula --------------------------------------------------------------------------


def test_uniform_velocity_command_resamples_within_ranges():
    @configclass
    class Commands:
        base_velocity = mdp.UniformVelocityCommandCfg(
            asset_name="robot",
            resampling_time_range=(0.1, 0.1),
            rel_standing_envs=0.0,
            ranges=mdp.UniformVelocityCommandCfg.Ranges(
                lin_vel_x=(0.5, 1.0), lin_vel_y=(-0.2, 0.2), ang_vel_z=(-1.0, 1.0)
            ),
        )

    env = ManagerBasedRLEnv(cartpole_cfg(commands=Commands()))
    env.reset()
    command = env.command_manager.get_command("base_velocity")
    first = command.clone()
    assert command.shape == (N, 3)
    assert ((command[:, 0] >= 0.5) & (command[:, 0] <= 1.0)).all() and (command[:, 1].abs() <= 0.2).all()
    steps = round(0.1 / env.step_dt)
    for _ in range(steps + 1):
        env.step(torch.zeros(N, 1))
    assert not torch.equal(first, env.command_manager.get_command("base_velocity"))
    torch.testing.assert_close(
        mdp.generated_commands(env, "base_velocity"), env.command_manager.get_command("base_velocity")
    )
    env.close()


def test_curricula_change_reward_weight_and_event_params():
    def widen(env, env_ids, old_value, factor: float, after: int):
        if env.common_step_counter < after:
            return mdp.modify_env_param.NO_CHANGE
        return (old_value[0] * factor, old_value[1] * factor)

    @configclass
    class Curriculum:
        alive_weight = CurrTerm(
            func=mdp.modify_reward_weight, params={"term_name": "alive", "weight": 5.0, "num_steps": 3}
        )
        cart_range = CurrTerm(
            func=mdp.modify_env_param,
            params={
                "address": "event_manager.cfg.reset_cart_position.params.position_range",
                "modify_fn": widen,
                "modify_params": {"factor": 2.0, "after": 3},
            },
        )

    env = ManagerBasedRLEnv(cartpole_cfg(curriculum=Curriculum()))
    env.reset()
    assert env.reward_manager.get_term_cfg("alive").weight == 1.0
    for _ in range(4):
        env.step(torch.zeros(N, 1))
    env.reset()
    assert env.reward_manager.get_term_cfg("alive").weight == 5.0
    assert env.event_manager.get_term_cfg("reset_cart_position").params["position_range"] == (-2.0, 2.0)
    assert env.extras["log"]["Curriculum/alive_weight"] == 5.0
    env.close()


# -- errors name the term ----------------------------------------------------------------------------


def _rewards_with(term: RewTerm):
    @configclass
    class Rewards:
        broken = term

    return Rewards()


@pytest.mark.parametrize(
    ("term", "message"),
    [
        (
            RewTerm(func="simlab.envs.mdp:joint_vel_l3", weight=1.0),
            r"term 'broken'.*has no attribute 'joint_vel_l3'.*Did you mean 'joint_vel_l\d'",
        ),
        (
            RewTerm(func=mdp.joint_vel_l1, weight=1.0, params={"asset_cfg": CART, "scale": 2}),
            r"term 'broken'.*unknown parameter.*'scale'",
        ),
        (RewTerm(func=mdp.joint_vel_l1, weight=1.0), r"term 'broken'.*needs parameter\(s\) \['asset_cfg'\]"),
        (
            RewTerm(func=mdp.joint_vel_l1, weight=1.0, params={"asset_cfg": SceneEntityCfg("robt")}),
            r"term 'broken'.*no entity 'robt'",
        ),
        (
            RewTerm(
                func=mdp.joint_vel_l1,
                weight=1.0,
                params={"asset_cfg": SceneEntityCfg("robot", joint_names=["pole_joint"])},
            ),
            r"term 'broken'.*parameter 'asset_cfg'.*Unmatched keys: \['pole_joint'\].*cart_to_pole",
        ),
    ],
)
def test_bad_reward_terms_fail_at_construction(term, message):
    with pytest.raises(ValueError, match=message):
        ManagerBasedRLEnv(cartpole_cfg(rewards=_rewards_with(term)))


def test_bad_action_and_event_terms_fail_at_construction():
    @configclass
    class Actions:
        joint_effort = mdp.JointEffortActionCfg(asset_name="cartpole", joint_names=["slider_to_cart"])

    with pytest.raises(
        ValueError, match=r"ActionManager: term 'joint_effort'.*asset_name 'cartpole' is not in the scene"
    ):
        ManagerBasedRLEnv(cartpole_cfg(actions=Actions()))

    cfg = cartpole_cfg()
    cfg.events.reset_pole_position.params["velocity_rnge"] = (0.0, 0.0)
    with pytest.raises(
        ValueError, match=r"EventManager: term 'reset_pole_position'.*'velocity_rnge'.*did you mean 'velocity_range'"
    ):
        ManagerBasedRLEnv(cfg)

    cfg = cartpole_cfg()
    cfg.events.reset_pole_position.mode = ""
    with pytest.raises(ValueError, match=r"term 'reset_pole_position'.*custom mode name"):
        ManagerBasedRLEnv(cfg)


def test_custom_event_modes_run_when_applied(capsys):
    """A mode other than the built-in ones is Isaac Lab's custom mode: it runs only when applied."""
    cfg = cartpole_cfg()
    cfg.events.nudge = EventTerm(func=record, mode="on_reset", params={"tag": "nudge"})
    env = ManagerBasedRLEnv(cfg)
    out = capsys.readouterr().out
    assert "custom mode 'on_reset'" in out and "Did you mean 'reset'" in out  # a likely typo is pointed out
    env.calls = []
    env.step(torch.zeros(env.num_envs, 1))
    assert env.calls == []  # never applied by the step
    env.event_manager.apply(mode="on_reset", env_ids=torch.tensor([1]))
    assert [c[:2] for c in env.calls] == [("nudge", [1])]
    env.event_manager.apply(mode="undeclared")  # skipped with a note, as Isaac Lab does
    assert "no event term has mode 'undeclared'" in capsys.readouterr().out
    env.close()


def test_terms_of_the_wrong_config_type_are_named():
    cfg = cartpole_cfg()
    cfg.rewards.alive = mdp.time_out  # a function where a RewardTermCfg belongs
    with pytest.raises(TypeError, match=r"RewardManager: term 'alive' must be a RewardTermCfg, got function"):
        ManagerBasedRLEnv(cfg)
    cfg = cartpole_cfg()
    cfg.events.reset_cart_position = 3
    with pytest.raises(TypeError, match=r"EventManager: term 'reset_cart_position' must be an EventTermCfg, got int"):
        ManagerBasedRLEnv(cfg)


def test_missing_config_fields_are_reported():
    from simlab.envs import ManagerBasedRLEnvCfg

    cfg = cartpole_cfg()
    with pytest.raises(ValueError, match=r"(?s)incomplete.*episode_length_s"):
        ManagerBasedRLEnv(
            ManagerBasedRLEnvCfg(
                scene=cfg.scene,
                observations=cfg.observations,
                actions=cfg.actions,
                rewards=cfg.rewards,
                terminations=cfg.terminations,
                decimation=2,
            )
        )


# -- Isaac Lab's manager internals -------------------------------------------------------------------


def _bare_env(num_envs: int = 3):
    """What reward and termination managers need from an env (Isaac Lab's tests use the same)."""
    from collections import namedtuple

    from simlab.sim import SimulationContext

    SimulationContext.clear_instance()
    return namedtuple("Env", ["num_envs", "dt", "device", "sim"])(num_envs, 0.1, "cpu", SimulationContext())


def test_reward_terms_may_return_a_number_and_a_missing_weight_is_a_type_error():
    from dataclasses import MISSING

    from simlab.managers import RewardManager
    from simlab.utils.errors import ConfigError

    env = _bare_env()
    manager = RewardManager({"one": RewTerm(func=lambda env: 1, weight=3.0)}, env)
    torch.testing.assert_close(manager.compute(dt=0.1), torch.full((3,), 0.3))
    assert manager._term_names == ["one"] and manager._term_cfgs[0].weight == 3.0
    with pytest.raises(TypeError, match="weight must be a number") as error:
        RewardManager({"one": RewTerm(func=lambda env: 1, weight=MISSING)}, env)
    assert isinstance(error.value, ConfigError)


def test_termination_manager_keeps_the_terms_that_ended_the_last_episode():
    from simlab.managers import TerminationManager

    env = _bare_env(num_envs=2)
    fired = {"a": torch.tensor([True, False]), "b": torch.tensor([False, False])}
    manager = TerminationManager(
        {"a": DoneTerm(func=lambda env: fired["a"].clone()), "b": DoneTerm(func=lambda env: fired["b"].clone())}, env
    )
    manager.compute()
    assert manager._last_episode_dones.tolist() == [[True, False], [False, False]]
    fired["a"] = torch.tensor([False, False])
    fired["b"] = torch.tensor([False, True])
    manager.compute()  # env 0 ended by nothing this step: its last episode's reason stays
    assert manager._last_episode_dones.tolist() == [[True, False], [False, True]]
    assert manager._term_dones.tolist() == [[False, False], [False, True]]


def test_observation_history_counts_appended_steps_only():
    @configclass
    class HistoryObsCfg:
        @configclass
        class PolicyCfg(ObsGroup):
            pos = ObsTerm(func=mdp.joint_pos)

            def __post_init__(self):
                self.history_length = 3

        policy: PolicyCfg = PolicyCfg()

    env = ManagerBasedRLEnv(cartpole_cfg(observations=HistoryObsCfg()))
    manager = env.observation_manager
    assert manager._group_obs_term_names == {"policy": ["pos"]}
    history = manager._group_obs_term_history_buffer["policy"]["pos"]
    env.reset()
    assert history.current_length.tolist() == [1] * N and history.max_length == 3
    manager.compute()  # a look without a step changes nothing
    assert history.current_length.tolist() == [1] * N
    for _ in range(4):
        env.step(torch.zeros(N, 1))
    assert history.current_length.tolist() == [3] * N, "capped at the history length"
    env.reset(env_ids=torch.tensor([1]))
    assert history.current_length.tolist() == [3, 1, 3, 3]
    env.close()


class _CallCount(ManagerTermBase):
    """A stateful observation term: how often it was called since the env's reset."""

    def __init__(self, cfg, env):
        super().__init__(cfg, env)
        self.calls = torch.zeros(env.num_envs)

    def reset(self, env_ids=None):
        self.calls[slice(None) if env_ids is None else env_ids] = 0.0

    def __call__(self, env):
        self.calls += 1.0
        return self.calls.unsqueeze(1).clone()


def test_measuring_the_terms_leaves_stateful_terms_as_reset():
    @configclass
    class CountingObsCfg:
        @configclass
        class PolicyCfg(ObsGroup):
            calls = ObsTerm(func=_CallCount)

        policy: PolicyCfg = PolicyCfg()

    env = ManagerBasedRLEnv(cartpole_cfg(observations=CountingObsCfg()))
    # the manager called the term to learn its shape; its first observation is still its first call
    torch.testing.assert_close(env.observation_manager.compute()["policy"], torch.ones(N, 1))
    env.close()


def test_a_modifiers_params_are_checked_against_its_function():
    from simlab.utils.errors import ConfigError
    from simlab.utils.modifiers import clip

    @configclass
    class ObsCfg:
        @configclass
        class PolicyCfg(ObsGroup):
            pos = ObsTerm(func=mdp.joint_pos, modifiers=[ModifierCfg(func=clip, params={"min": -1.0, "max": 1.0})])

        policy: PolicyCfg = PolicyCfg()

    with pytest.raises(ConfigError, match=r"term 'policy/pos modifier': .*unknown parameter\(s\) \['min', 'max'\]"):
        ManagerBasedRLEnv(cartpole_cfg(observations=ObsCfg()))


def test_observation_manager_serializes_its_terms():
    class Described(_CallCount):
        def serialize(self) -> dict:
            return {"counts": "calls"}

    @configclass
    class ObsCfg:
        @configclass
        class PolicyCfg(ObsGroup):
            calls = ObsTerm(func=Described)
            pos = ObsTerm(func=mdp.joint_pos, scale=2.0)

        policy: PolicyCfg = PolicyCfg()

    env = ManagerBasedRLEnv(cartpole_cfg(observations=ObsCfg()))
    serialized = env.observation_manager.serialize()["policy"]
    assert serialized["calls"] == {"counts": "calls"}
    assert serialized["pos"]["cfg"]["scale"] == 2.0 and serialized["pos"]["cfg"]["func"].endswith(":joint_pos")
    env.close()
