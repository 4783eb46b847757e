"""The Shadow Hand's OpenAI variants (``simlab/Repose-Cube-Shadow-OpenAI-{FF,LSTM}-Direct-v0``).

Noise models: an additive-bias model keeps each env's bias for the whole episode and redraws it only
where a reset's mask is set; the direct env adds the action noise before ``_pre_physics_step`` and
the observation noise to the step's policy observations. The asymmetric critic gets 187 values with
the fingertips' incoming joint wrenches (zero for a weightless fingertip at rest, its weight when
gravity acts on it). Isaac Lab's agent configs train one iteration, the LSTM one included.
"""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch
from test_graph_contract import emulated_cuda_graph  # noqa: F401 (a fixture)

import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.assets import ArticulationCfg
from simlab.robots.shadow_hand import SHADOW_HAND_CFG, SHADOW_HAND_FINGERTIP_BODIES
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.tasks.utils import load_cfg_from_registry, parse_env_cfg
from simlab.utils import configclass
from simlab.utils.noise import GaussianNoiseCfg, NoiseModelWithAdditiveBiasCfg

FF = "simlab/Repose-Cube-Shadow-OpenAI-FF-Direct-v0"
LSTM = "simlab/Repose-Cube-Shadow-OpenAI-LSTM-Direct-v0"
NUM_ENVS = 4


def bias_only(std: float) -> NoiseModelWithAdditiveBiasCfg:
    """No per-step noise, a Gaussian bias: what the data gains is exactly the bias."""
    return NoiseModelWithAdditiveBiasCfg(
        noise_cfg=GaussianNoiseCfg(mean=0.0, std=0.0, operation="add"),
        bias_noise_cfg=GaussianNoiseCfg(mean=0.0, std=std, operation="abs"),
    )


def test_additive_bias_is_kept_within_an_episode_and_redrawn_where_the_mask_is_set():
    cfg = bias_only(1.0)
    model = cfg.class_type(cfg, num_envs=3, device="cpu")
    data = torch.zeros(3, 5)
    first = model(data)
    assert first.shape == (3, 5) and first.abs().min() > 0  # one bias per env and component
    torch.testing.assert_close(model(data), first)  # constant from step to step
    model.reset(torch.tensor([False, True, False]))
    second = model(data)
    torch.testing.assert_close(second[[0, 2]], first[[0, 2]])
    assert (second[1] != first[1]).all()
    model.reset([0])  # Isaac Lab's ids
    assert (model(data)[0] != first[0]).all()
    shared = NoiseModelWithAdditiveBiasCfg(
        noise_cfg=GaussianNoiseCfg(std=0.0), bias_noise_cfg=GaussianNoiseCfg(std=1.0, operation="abs"),
        sample_bias_per_component=False,
    )  # fmt: skip
    out = shared.class_type(shared, num_envs=2, device="cpu")(torch.zeros(2, 4))
    assert (out == out[:, :1]).all()  # one bias for all components of an env


@pytest.fixture(scope="module")
def openai():
    cfg = parse_env_cfg(FF, device="cpu", num_envs=NUM_ENVS)
    cfg.seed = 0
    env = gym.make(FF, cfg=cfg).unwrapped
    env.reset(seed=0)
    yield env
    env.close()


def make_ff(num_envs: int = NUM_ENVS):
    cfg = parse_env_cfg(FF, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    env = gym.make(FF, cfg=cfg).unwrapped
    env.reset(seed=0)
    return env


def test_openai_variant_step_is_captured_with_its_randomization(emulated_cuda_graph, monkeypatch):  # noqa: F811
    """The randomization events (friction, gains, joint limits, cube mass, gravity) take the reset mask
    and read nothing back: the step is captured (an emulated CUDA graph on the CPU, which fails a capture
    that reads a device value back, test_graph_contract.py) and its replays randomize the envs they reset."""
    from simlab.envs.utils.cuda_graph import EnvStepper

    env = make_ff()
    try:
        assert env.graph_blockers() == []
        physics = env.sim.physics
        # the CPU backend, told to capture as the GPU one does (which tracks staleness without reading a mask)
        monkeypatch.setattr(physics, "can_capture_steps", True, raising=False)
        monkeypatch.setattr(physics, "forwards_all_worlds", True, raising=False)
        # the replays run torch's ops only, not MuJoCo C: its clock stands still, which this backend
        # would take for worlds it restarted (MuJoCo Warp's backend has no such check)
        monkeypatch.setattr(physics, "_restarted_by_simulator", lambda: None)
        stepper = EnvStepper(env, env._step_body, warmup=2)
        assert stepper.eager_reason is None
        actions = torch.zeros(NUM_ENVS, 20)
        for _ in range(4):  # warm-up, capture, a replay
            stepper(actions)
        assert stepper.is_graphed and stepper.eager_reason is None, stepper.mode
        # a replayed step in which envs 1 and 3 end their episode with the 720-step gate open
        friction = physics.model_field("geom_friction")[:, :, 0]
        before = {name: t.clone() for name, t in (("friction", friction), ("mass", physics.model_field("body_mass")))}
        manager = env.event_manager
        for last in manager._reset_last_step.values():
            last.fill_(-1000)
        env.episode_length_buf[[1, 3]] = env.max_episode_length  # their time is up
        stepper(actions)
        for name, now in (("friction", friction), ("mass", physics.model_field("body_mass"))):
            changed = (now != before[name]).flatten(1).any(dim=1)
            assert changed.tolist() == [False, True, False, True], name
    finally:
        env.close()


def test_randomized_cube_mass_scales_mujoco_s_constants_as_set_const_does(openai):
    """A free cube's mass and inertia scaled by mask: its subtree mass and inverse weights follow as
    MuJoCo's mj_setConst computes them for that world's masses."""
    import mujoco

    env = openai
    physics, model = env.sim.physics, env.sim.model
    cube = env.object._body_ids[0]
    dofs = slice(int(model.body_dofadr[cube]), int(model.body_dofadr[cube]) + 6)
    reference = mujoco.MjModel.from_xml_string(env.sim.spec.to_xml())  # the compiled model, default masses
    data = mujoco.MjData(reference)
    for world in range(NUM_ENVS):
        mass = float(physics.model_field("body_mass")[world, cube])
        assert abs(mass - model.body_mass[cube]) > 1e-4, "the reset randomized the mass"
        reference.body_mass[cube] = mass
        reference.body_inertia[cube] = physics.model_field("body_inertia")[world, cube].numpy()
        mujoco.mj_setConst(reference, data)
        for field, rows in (("body_subtreemass", cube), ("body_invweight0", cube), ("dof_invweight0", dofs)):
            torch.testing.assert_close(
                physics.model_field(field)[world, rows].double(),
                torch.as_tensor(getattr(reference, field)[rows]),
                rtol=1e-4,
                atol=0.0,
                msg=field,
            )


def test_openai_variant_steps_with_isaac_lab_s_spaces_and_finite_values(openai):
    env = openai
    assert env.single_observation_space["policy"].shape == (42,)
    assert env.single_observation_space["critic"].shape == (187,)
    assert env.cfg.decimation == 3 and env.cfg.sim.dt == pytest.approx(1 / 60)
    generator = torch.Generator().manual_seed(0)
    for _ in range(20):
        obs, reward, terminated, truncated, _ = env.step(2 * torch.rand(NUM_ENVS, 20, generator=generator) - 1)
        assert obs["policy"].shape == (NUM_ENVS, 42) and obs["critic"].shape == (NUM_ENVS, 187)
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(obs["critic"]).all()
        assert torch.isfinite(reward).all()
    # the critic's fingertip force-torque readings (scaled by 10) sit before the 20 actions
    wrenches = obs["critic"][:, 137:167]
    torch.testing.assert_close(wrenches, 10.0 * env.fingertip_force_sensors.reshape(NUM_ENVS, 30))
    assert wrenches.abs().max() > 0


def test_env_adds_the_noise_models_to_actions_and_policy_observations(openai):
    env = openai
    env._action_noise_model = bias_only(0.1).class_type(bias_only(0.1), NUM_ENVS, "cpu")
    env._observation_noise_model = bias_only(0.01).class_type(bias_only(0.01), NUM_ENVS, "cpu")
    actions = torch.zeros(NUM_ENVS, 20)
    env._action_noise_model(actions)  # sizes the bias (the env does this when it builds its models)
    env._observation_noise_model(torch.zeros(NUM_ENVS, 42))
    env.episode_length_buf.zero_()
    for _ in range(2):
        obs, _, terminated, truncated, _ = env.step(actions)
        assert not (terminated | truncated).any()
        # the policy acted on the biased actions; its observation carries the observation bias
        torch.testing.assert_close(env.actions, env._action_noise_model.bias)
        torch.testing.assert_close(obs["policy"], env._get_observations()["policy"] + env._observation_noise_model.bias)
    before = env._action_noise_model.bias.clone()
    env._reset_idx(torch.tensor([1]))
    after = env._action_noise_model.bias
    torch.testing.assert_close(after[[0, 2, 3]], before[[0, 2, 3]])  # only the reset env draws a new bias
    assert (after[1] != before[1]).all()


@pytest.mark.parametrize("disable_gravity", [True, False])
def test_fingertip_wrenches_read_the_weight_only_where_gravity_acts(disable_gravity):
    hand = SHADOW_HAND_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
    hand.spawn.rigid_props.disable_gravity = disable_gravity

    @configclass
    class HandSceneCfg(InteractiveSceneCfg):
        robot: ArticulationCfg = hand

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=1 / 120, device="cpu"))
    try:
        scene = InteractiveScene(HandSceneCfg(num_envs=2, env_spacing=1.0))
        tips = list(SHADOW_HAND_FINGERTIP_BODIES)
        sim_utils.compute_body_interaction_forces(sim.spec)
        sim.reset()
        robot = scene["robot"]
        for _ in range(120):  # held at the default pose, touching nothing
            robot.set_joint_position_target(robot.data.default_joint_pos)
            scene.write_data_to_sim()
            sim.step()
            scene.update(1 / 120)
        ids = [robot.body_names.index(n) for n in tips]
        wrench = robot.data.body_incoming_joint_wrench_b[:, ids]
        weight = robot.data.default_mass[:, ids] * 9.81
        force = wrench[..., :3].norm(dim=-1)
        # the weight's moment about the fingertip's origin (its centre of mass is off it): none when weightless
        assert (
            (wrench[..., 3:].norm(dim=-1) < 1e-3).all()
            if disable_gravity
            else (wrench[..., 3:].norm(dim=-1) > 1e-3).all()
        )
        # Isaac Lab's in-hand env reads it through PhysX's view
        torch.testing.assert_close(
            robot.root_physx_view.get_link_incoming_joint_force(), robot.data.body_incoming_joint_wrench_b
        )
        expected = torch.zeros_like(weight) if disable_gravity else weight
        torch.testing.assert_close(force, expected, atol=2e-3, rtol=0.02)
    finally:
        sim.clear_instance()


def test_agent_configs_follow_isaac_lab():
    rl_ff = load_cfg_from_registry(FF, "rl_games_cfg_entry_point")["params"]
    assert rl_ff["network"]["mlp"]["units"] == [400, 400, 200, 100] and "rnn" not in rl_ff["network"]
    assert rl_ff["config"]["central_value_config"]["network"]["mlp"]["units"] == [512, 512, 256, 128]
    rl_lstm = load_cfg_from_registry(LSTM, "rl_games_cfg_entry_point")["params"]
    assert rl_lstm["network"]["rnn"] == {
        "name": "lstm",
        "units": 1024,
        "layers": 1,
        "before_mlp": True,
        "layer_norm": True,
    }
    assert rl_lstm["config"]["central_value_config"]["network"]["rnn"]["zero_rnn_on_done"] is False
    rsl = load_cfg_from_registry(FF, "rsl_rl_cfg_entry_point")
    assert rsl.actor.hidden_dims == [400, 400, 200, 100] and rsl.experiment_name == "shadow_hand_openai_ff"
    skrl = load_cfg_from_registry(FF, "skrl_cfg_entry_point")
    assert skrl["models"]["value"]["network"][0]["input"] == "STATES"
    assert gym.spec(LSTM).kwargs.keys() >= {"env_cfg_entry_point", "rl_games_cfg_entry_point"}


@pytest.mark.slow
@pytest.mark.parametrize(("task", "library"), [(LSTM, "rl_games"), (FF, "rl_games"), (FF, "rsl_rl"), (FF, "skrl")])
def test_one_training_iteration(tmp_path, task, library):
    from simlab.cli.main import main

    small = ["agent.params.config.minibatch_size=32", "agent.params.config.central_value_config.minibatch_size=64"]
    argv = ["train", "--task", task, "--library", library, "--num_envs", "8", "--device", "cpu", "--headless"]
    argv += ["--max_iterations", "1", "--log_root", str(tmp_path / "logs")]
    assert main(argv + (small if library == "rl_games" else [])) == 0
    assert list((tmp_path / "logs" / library).glob("*/*/"))


@pytest.mark.slow
def test_played_lstm_policy_carries_its_state_and_restarts_it_with_the_episode(tmp_path):
    """An LSTM policy trained one iteration, played as `simlab play` plays it: the same observation
    gives other actions once the policy has a history, and the first actions again where an episode
    restarts (the env's episode_length_buf back at 0)."""
    from simlab.cli.libraries.rl_games import load_policy
    from simlab.cli.main import main
    from simlab.utils.io import load_yaml

    argv = ["train", "--task", LSTM, "--library", "rl_games", "--num_envs", "8", "--device", "cpu", "--headless"]
    argv += ["--max_iterations", "1", "--log_root", str(tmp_path / "logs")]
    assert (
        main(
            [
                *argv,
                "agent.params.config.minibatch_size=32",
                "agent.params.config.central_value_config.minibatch_size=64",
            ]
        )
        == 0
    )
    (checkpoint,) = (tmp_path / "logs" / "rl_games").glob("*/*/nn/last_*.pth")
    agent_cfg = load_yaml(str(checkpoint.parent.parent / "params" / "agent.yaml"))
    cfg = parse_env_cfg(LSTM, device="cpu", num_envs=NUM_ENVS)
    env = gym.make(LSTM, cfg=cfg)
    try:
        obs, _ = env.reset(seed=0)
        policy = load_policy(env, agent_cfg, str(checkpoint))
        assert policy.not_exportable
        first = policy(obs)
        env.unwrapped.episode_length_buf[:] = 1  # mid-episode: the state carries over
        second = policy(obs)
        assert not torch.allclose(first, second)
        env.unwrapped.episode_length_buf[[0, 2]] = 0  # envs 0 and 2 restart
        third = policy(obs)
        torch.testing.assert_close(third[[0, 2]], first[[0, 2]])
        assert not torch.allclose(third[[1, 3]], first[[1, 3]])
    finally:
        env.close()


@pytest.mark.slow
def test_contact_buffers_cover_the_peaks_of_random_play():
    """MuJoCo Warp's kernels on Warp's CPU device with the task's own buffers (an overflow raises),
    short episodes so that the rollout crosses resets: twice the peaks fit."""
    pytest.importorskip("mujoco_warp")
    from simlab.tasks.utils.contact_buffers import measure_task_buffers

    peaks, diverged, reserved = measure_task_buffers(FF, num_envs=4, env_steps=60, headroom=1, episode_length_s=0.5)
    assert diverged == 0 and peaks.contacts_per_world > 0
    assert reserved["nconmax"] >= 2 * peaks.contacts_per_world
    assert reserved["njmax"] >= 2 * peaks.constraint_rows


@pytest.mark.slow
def test_fingertip_wrenches_agree_on_mujoco_warp():
    """The same steps on MuJoCo C (mjbatch) and MuJoCo Warp (its CPU device): the critic's fingertip
    force-torque readings agree (float32 solvers, a few thousandths of readings of several units)."""
    pytest.importorskip("mujoco_warp")
    readings = []
    for engine in (None, "mujoco_warp"):
        cfg = parse_env_cfg(FF, device="cpu", num_envs=2)
        cfg.seed, cfg.events = 0, None
        cfg.action_noise_model = cfg.observation_noise_model = None
        if engine is not None:
            cfg.sim.engine, cfg.sim.use_cuda_graph = engine, False
        env = gym.make(FF, cfg=cfg).unwrapped
        try:
            env.reset(seed=0)
            for _ in range(5):
                obs, *_ = env.step(torch.zeros(2, 20))
            readings.append(obs["critic"][:, 137:167].clone())
        finally:
            env.close()
    assert readings[0].abs().max() > 1.0
    torch.testing.assert_close(readings[1], readings[0], atol=0.02, rtol=0.01)
