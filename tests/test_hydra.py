"""Hydra-style overrides of env and agent configs."""

from __future__ import annotations

import sys

import pytest

from simlab.tasks.utils import apply_overrides, hydra_task_config, load_cfg_from_registry
from simlab.tasks.utils.hydra import OverrideError, parse_override


@pytest.fixture
def cfgs():
    env = load_cfg_from_registry("simlab/Cartpole-v0", "env_cfg_entry_point")
    agent = load_cfg_from_registry("simlab/Cartpole-v0", "rsl_rl_cfg_entry_point")
    return env, agent


def test_parse_override_values():
    assert parse_override("env.a.b=10") == (["env", "a", "b"], 10, False)
    assert parse_override("agent.x=0.5")[1] == 0.5
    assert parse_override("agent.x=null")[1] is None
    assert parse_override("agent.x=[1, 2]")[1] == [1, 2]
    assert parse_override("agent.x=hello")[1] == "hello"
    assert parse_override("+agent.x=true") == (["agent", "x"], True, True)


def test_override_env_and_agent(cfgs):
    env, agent = cfgs
    apply_overrides(
        env,
        agent,
        [
            "env.actions.joint_effort.scale=10",
            "agent.seed=2024",
            "env.scene.num_envs=8",
            "agent.actor.hidden_dims=[16, 16]",
        ],
    )
    assert env.actions.joint_effort.scale == 10
    assert agent.seed == 2024 and env.scene.num_envs == 8
    assert agent.actor.hidden_dims == [16, 16]


def test_null_removes_a_term(cfgs):
    env, agent = cfgs
    term = next(name for name in vars(env.rewards) if getattr(env.rewards, name) is not None)
    apply_overrides(env, agent, [f"env.rewards.{term}=null"])
    assert getattr(env.rewards, term) is None


def test_wrong_key_names_nearest(cfgs):
    env, agent = cfgs
    with pytest.raises(OverrideError, match="joint_effort") as e:
        apply_overrides(env, agent, ["env.actions.joint_efort.scale=10"])
    assert "Nearest valid keys" in str(e.value)
    with pytest.raises(OverrideError, match="'seed'"):
        apply_overrides(env, agent, ["agent.sed=1"])
    with pytest.raises(OverrideError, match="Did you mean 'agent.seed'"):
        apply_overrides(env, agent, ["agnt.seed=1"])


def test_type_checks(cfgs):
    env, agent = cfgs
    with pytest.raises(OverrideError, match="number"):
        apply_overrides(env, agent, ["env.scene.num_envs=many"])
    with pytest.raises(OverrideError, match="not an override"):
        apply_overrides(env, agent, ["--num_envs"])


def test_a_field_that_takes_a_tuple_takes_a_list_and_a_number_field_does_not():
    # an action term's ``scale: float | tuple[float, ...]`` is per joint (or per pose component)
    env = load_cfg_from_registry("simlab/Lift-Cube-Franka-IK-Abs-v0", "env_cfg_entry_point")
    agent = load_cfg_from_registry("simlab/Lift-Cube-Franka-IK-Abs-v0", "rsl_rl_cfg_entry_point")
    apply_overrides(env, agent, ["env.actions.arm_action.scale=[0.2, 0.3, 0.25, 1, 1, 1, 1]"])
    assert tuple(env.actions.arm_action.scale) == (0.2, 0.3, 0.25, 1, 1, 1, 1)
    with pytest.raises(OverrideError, match="expects a number"):
        apply_overrides(env, agent, ["env.sim.dt=[0.01, 0.02]"])


def test_dict_agent_and_new_keys():
    env = load_cfg_from_registry("simlab/Cartpole-v0", "env_cfg_entry_point")
    agent = load_cfg_from_registry("simlab/Cartpole-v0", "skrl_cfg_entry_point")
    apply_overrides(env, agent, ["agent.agent.rollouts=8", "+agent.agent.new_key=1"])
    assert agent["agent"]["rollouts"] == 8 and agent["agent"]["new_key"] == 1
    with pytest.raises(OverrideError, match="rollouts"):
        apply_overrides(env, agent, ["agent.agent.rolouts=8"])


def test_hydra_task_config_decorator(monkeypatch):
    monkeypatch.setattr(sys, "argv", ["train.py", "env.scene.num_envs=3", "agent.max_iterations=7"])
    seen = {}

    @hydra_task_config("simlab/Cartpole-v0", "rsl_rl_cfg_entry_point")
    def main(env_cfg, agent_cfg):
        seen["env"], seen["agent"] = env_cfg, agent_cfg

    main()
    assert seen["env"].scene.num_envs == 3 and seen["agent"].max_iterations == 7


# -- on hydra-core -------------------------------------------------------------------------------


def test_configs_are_registered_in_hydras_config_store():
    from hydra.core.config_store import ConfigStore

    from simlab.tasks.utils.hydra import register_task_to_hydra

    env, agent = register_task_to_hydra("simlab/Cartpole-v0", "rsl_rl_cfg_entry_point")
    node = ConfigStore.instance().load("simlab/Cartpole-v0.yaml").node
    assert node.env.scene.num_envs == env.scene.num_envs and node.agent.seed == agent.seed
    assert node.env.rewards.alive.func == "simlab.envs.mdp.rewards:is_alive"  # callables stored as names
    # composed by the task id, as Isaac Lab's tests do: env and agent at the root
    from hydra import compose, initialize

    with initialize(version_base="1.3", config_path=None):
        composed = compose(config_name="simlab/Cartpole-v0", overrides=["env.decimation=3"])
    assert set(composed) == {"env", "agent"} and composed.env.decimation == 3


def test_hydra_grammar_interpolation_and_delete(cfgs):
    env, agent = cfgs
    # ${...} interpolation and ~key are Hydra's grammar (the old hand-written parser had neither)
    apply_overrides(env, agent, ["env.decimation=3", "env.sim.render_interval=${env.decimation}", "~env.rewards.alive"])
    assert env.sim.render_interval == 3 and env.rewards.alive is None
    with pytest.raises(OverrideError, match="sweeps"):
        apply_overrides(env, agent, ["agent.seed=1,2"])


def test_slices_lists_none_and_callables_round_trip(cfgs):
    import simlab.envs.mdp as mdp

    env, agent = cfgs
    asset_cfg = "env.rewards.pole_pos.params.asset_cfg"
    apply_overrides(
        env,
        agent,
        [
            f'{asset_cfg}.joint_ids="slice(0,1,None)"',
            "env.viewer.eye=[1.0, 2.0, 3.0]",
            "env.rewards.terminating.func=simlab.envs.mdp.rewards:is_alive",
            "env.rewards.cart_vel=null",
        ],
    )
    assert env.rewards.pole_pos.params["asset_cfg"].joint_ids == slice(0, 1, None)
    assert env.viewer.eye == (1.0, 2.0, 3.0)  # a tuple field stays a tuple
    assert env.rewards.terminating.func is mdp.is_alive and env.rewards.cart_vel is None
    # what was not overridden is untouched (the same objects)
    assert env.rewards.pole_vel.params["asset_cfg"].joint_names == ["cart_to_pole"]


def test_env_overrides_are_picked_with_their_hydra_prefixes():
    # what a trained policy needs again at play (the run's record, the judge, make_pretrained): every
    # override of the env, also those that add (+, ++) or delete (~) a key; none of the agent's
    from simlab.tasks.utils.hydra import env_overrides_in

    overrides = ["env.decimation=4", "+env.extra=1", "++env.sim.dt=0.01", "~env.events", "agent.seed=3", "+agent.x=1"]
    assert env_overrides_in(overrides) == overrides[:4]
