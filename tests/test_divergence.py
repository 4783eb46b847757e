"""A world whose physics blows up is put back, ends its episode and is counted; or the step raises."""

from __future__ import annotations

import pytest
import torch
from test_graph_contract import emulated_cuda_graph  # noqa: F401 (a fixture)

from simlab.envs import ManagerBasedRLEnv
from simlab.envs.utils.cuda_graph import SimulationDivergedError
from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv, CartpoleEnvCfg
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg as ManagerCartpoleCfg


def direct_cartpole(num_envs: int = 6) -> CartpoleEnv:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    cfg.seed = 1
    return CartpoleEnv(cfg)


@pytest.mark.parametrize("bad_value", [float("nan"), 1e20])
def test_a_blown_up_world_ends_its_episode_and_is_counted(bad_value):
    env = direct_cartpole()
    env.reset()
    for _ in range(3):
        env.step(torch.zeros(6, 1))
    before = env.sim.physics.data("qpos").clone()
    env.sim.physics.data("qvel")[3, 1] = bad_value  # what a too-stiff gain or a huge action leads to
    obs, reward, terminated, truncated, extras = env.step(torch.zeros(6, 1))
    assert terminated.tolist() == [False, False, False, True, False, False]
    assert int(extras["log"]["Physics/diverged"]) == 1
    assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    assert env.episode_length_buf[3] == 0  # reset in the same step, as any finished episode
    assert not torch.equal(env.sim.physics.data("qpos")[0], before[0])  # the others went on stepping
    first_log = extras["log"]
    obs, *_, extras = env.step(torch.zeros(6, 1))
    assert int(extras["log"]["Physics/diverged"]) == 0
    assert int(first_log["Physics/diverged"]) == 1  # each step's log is its own (loggers keep one per step)
    env.close()


def test_on_divergence_raise_stops_with_a_message():
    env = direct_cartpole()
    env.sim.on_divergence = "raise"
    env.reset()
    env.sim.physics.data("qvel")[2, 0] = float("nan")
    with pytest.raises(SimulationDivergedError, match="1 world"):
        env.step(torch.zeros(6, 1))
    with pytest.raises(ValueError, match="'reset' or 'raise'"):
        env.sim.on_divergence = "ignore"
    env.close()


def test_manager_based_env_logs_divergence():
    cfg = ManagerCartpoleCfg()
    cfg.scene.num_envs = 4
    cfg.sim.device = "cpu"
    env = ManagerBasedRLEnv(cfg)
    env.reset(seed=0)
    env.sim.physics.data("qvel")[1, 0] = 1e20
    _, _, terminated, _, extras = env.step(torch.zeros(4, 1))
    assert terminated[1] and int(extras["log"]["Physics/diverged"]) == 1
    assert torch.isfinite(env.sim.physics.data("qvel")).all()
    env.close()


def test_a_control_mujoco_would_zero_counts_as_divergence():
    """MuJoCo zeroes a control above 1e10 with a console warning only: simlab counts it."""
    env = direct_cartpole()
    env.reset()
    action = torch.zeros(6, 1)
    action[4] = 1e12  # times action_scale: far above MuJoCo's limit
    _, _, terminated, _, extras = env.step(action)
    assert terminated[4] and int(extras["log"]["Physics/diverged"]) == 1
    env.close()


def test_check_finite_actions_false_skips_the_action_check():
    """The manager-based cfg's ``check_finite_actions`` still turns the action check off."""
    cfg = ManagerCartpoleCfg()
    cfg.scene.num_envs = 4
    cfg.sim.device = "cpu"
    cfg.check_finite_actions = False
    env = ManagerBasedRLEnv(cfg)
    env.reset(seed=0)
    action = torch.zeros(4, 1)
    action[0] = float("nan")
    env.step(action)  # no ValueError about the action: the user turned the check off
    assert env._stepper._check_actions is False
    env.close()


@pytest.mark.parametrize(
    ("device", "engine"),
    [("cpu", "mujoco"), ("cpu", "mujoco_warp"), pytest.param("cuda:0", "auto", marks=pytest.mark.gpu)],
)
@pytest.mark.parametrize(("field", "bad_value"), [("qvel", float("nan")), ("qpos", 1e25)])
def test_one_blown_up_allegro_world_is_reset_and_training_goes_on(device, engine, field, bad_value):
    """The attack behind a dead 8192-world Allegro run: one world's state turns NaN, or huge but finite
    (MuJoCo Warp does not restart it; a cube 1e25 m away made the reward's distance inf). That world
    ends its episode and is counted; the others step on untouched; every observation and reward is
    finite. On the GPU the step is the replayed CUDA graph."""
    if engine != "mujoco":
        pytest.importorskip("mujoco_warp")
    from simlab.tasks.direct.allegro_hand.allegro_hand_env_cfg import AllegroHandEnvCfg
    from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import InHandManipulationEnv

    cfg = AllegroHandEnvCfg()
    cfg.scene.num_envs, cfg.sim.device, cfg.sim.engine, cfg.seed = 4, device, engine, 1
    env = InHandManipulationEnv(cfg)
    env.reset()
    actions = torch.zeros(4, 16, device=env.device)
    for _ in range(4):  # on the GPU: the warm-up steps and the capture
        env.step(actions)
    assert env.step_is_graphed == device.startswith("cuda"), env.step_mode
    cube_column = env.hand.num_joints  # the cube's free joint follows the hand's 16 joints
    env.sim.physics.data(field)[2, cube_column] = bad_value
    _, reward, terminated, _, extras = env.step(actions)
    assert terminated.tolist() == [False, False, True, False]
    assert int(extras["log"]["Physics/diverged"]) == 1
    assert torch.isfinite(reward).all()
    for _ in range(3):  # the reset world and the others step on
        obs, reward, terminated, _, extras = env.step(actions)
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        assert int(extras["log"]["Physics/diverged"]) == 0 and not terminated.any()
    env.close()


def test_the_others_step_as_if_no_world_had_blown_up():
    """A restart touches only the blown-up world: the others' states equal a run without it."""

    def run(attack: bool) -> dict[str, torch.Tensor]:
        env = direct_cartpole()  # seeds the global generator: one env at a time
        env.reset()
        if attack:
            env.sim.physics.data("qvel")[3, 1] = float("nan")
        for _ in range(3):
            env.step(torch.linspace(-1, 1, 6).unsqueeze(1))
        state = {field: env.sim.physics.data(field).clone() for field in ("qpos", "qvel")}
        env.close()
        return state

    clean, attacked = run(attack=False), run(attack=True)
    others = [0, 1, 2, 4, 5]
    for field in ("qpos", "qvel"):
        assert torch.equal(clean[field][others], attacked[field][others])
        assert not torch.equal(clean[field][3], attacked[field][3])  # world 3 was restarted


def test_rsl_rl_training_goes_on_past_a_blown_up_world():
    """End to end: a world turns NaN in the middle of an rsl_rl rollout; the run finishes its
    iterations with finite weights and the rollout's logs carry the count."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.cli.libraries.rsl_rl import make_runner
    from simlab.tasks.utils import load_cfg_from_registry, parse_env_cfg

    task = "simlab/Cartpole-Direct-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=8))
    agent = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    agent.num_steps_per_env, agent.device = 8, "cpu"
    physics = env.unwrapped.sim.physics
    physics_step, physics_steps = physics.step, [0]

    def step_then_blow_up(*args, **kwargs):
        out = physics_step(*args, **kwargs)
        physics_steps[0] += 1
        if physics_steps[0] == 20:  # iteration 2 of 3 (2 physics steps per env step, 8 env steps each)
            physics.data("qvel")[5, 1] = float("nan")
        return out

    physics.step = step_then_blow_up
    runner = make_runner(env, agent, None)
    env_step, counts = runner.env.step, []

    def step_and_record(actions):
        out = env_step(actions)
        counts.append(int(out[-1]["log"]["Physics/diverged"]))
        return out

    runner.env.step = step_and_record
    runner.learn(num_learning_iterations=3)
    assert len(counts) == 24 and sum(counts) == 1 and counts.index(1) == 9
    weights = runner.alg.save()["actor_state_dict"].values()
    assert all(torch.isfinite(w).all() for w in weights)
    env.close()


def test_a_task_term_dividing_by_zero_still_raises():
    """Resetting blown-up worlds hides no task bug: a reward that is inf in one world with finite physics
    stops the step with the error, which names the task's math, not the physics."""
    env = direct_cartpole()
    env.reset()
    get_rewards = env._get_rewards

    def one_over_zero_in_world_2():
        divisor = (torch.arange(6) != 2).float()  # a term whose denominator is 0 in world 2
        return get_rewards() / divisor

    env._get_rewards = one_over_zero_in_world_2
    with pytest.raises(ValueError, match=r"NaN or inf in this step: reward, in 1 world\(s\) \(2\).*divides") as info:
        env.step(torch.zeros(6, 1))
    assert int(env.sim.physics.diverged_count) == 0
    assert "\n" not in str(info.value)
    env.close()


def test_the_error_names_the_observation_term_the_worlds_and_their_state():
    """A non-finite observation names its column by the task's term (the direct Allegro's fingertip
    velocities), the world, and that world's largest position, velocity and action then."""
    from simlab.tasks.direct.allegro_hand.allegro_hand_env_cfg import AllegroHandEnvCfg
    from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import InHandManipulationEnv

    cfg = AllegroHandEnvCfg()
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = 4, "cpu", 1
    env = InHandManipulationEnv(cfg)
    env.reset()
    compute = env._compute_intermediate_values

    def nan_in_world_1():
        compute()
        env.fingertip_velocities = env.fingertip_velocities.clone()
        env.fingertip_velocities[1, 2, 4] = float("nan")  # fingertip 2's angular velocity, y

    env._compute_intermediate_values = nan_in_world_1
    actions = torch.zeros(4, 16)
    actions[1, 0] = 3.0
    with pytest.raises(ValueError) as info:
        env.step(actions)
    message = str(info.value)
    # 16 + 16 + 3 + 4 + 3 + 3 + 3 + 4 + 4 + 12 + 16 columns come first; then 6 per fingertip
    assert "obs['policy'] columns 100 (fingertip_velocities[16]), in 1 world(s) (1)" in message
    assert "|action| 3 then" in message and "|qvel| nan" not in message
    env.close()


def test_a_graphed_step_names_the_columns_and_worlds_at_its_check_without_host_reads(
    emulated_cuda_graph,  # noqa: F811
    monkeypatch,
):
    """Graphed, the worlds and columns accumulate on the device between two checks (no read per step)."""
    from test_graph_contract import ToyEnv

    from simlab.envs.utils.cuda_graph import EnvStepper

    env = ToyEnv()
    body = env._step_body
    poison = torch.zeros(4, 4)

    def step_body(action):
        obs, reward, error = body(action)
        return {"policy": obs["policy"] + poison}, reward, error

    stepper = EnvStepper(env, step_body, warmup=1, check_interval=4)
    for _ in range(2):  # the warm-up call and the capture
        stepper(torch.zeros(4, 2))
    assert stepper.is_graphed
    reads = []
    for name in ("__bool__", "item", "tolist"):
        original = getattr(torch.Tensor, name)
        monkeypatch.setattr(torch.Tensor, name, lambda self, *a, _o=original, _n=name: reads.append(_n) or _o(self, *a))
    poison[2, 3] = float("inf")
    stepper(torch.zeros(4, 2))  # step 3: flagged on the device
    poison[2, 3] = 0.0
    assert reads == []
    with pytest.raises(ValueError, match=r"among the last 4: obs\['policy'\] columns 3, in 1 world\(s\) \(2\)"):
        stepper(torch.zeros(4, 2))  # step 4: the periodic check
    stepper(torch.zeros(4, 2))  # cleared: the next interval starts clean


def test_snapshots_keep_the_state_a_bad_world_started_its_step_from(tmp_path, monkeypatch):
    """SIMLAB_SNAPSHOT_BAD_WORLDS=<file>: the error writes each bad world's state from the start of its
    first bad step, and the action it got, to replay it."""
    path = tmp_path / "bad_worlds.pt"
    monkeypatch.setenv("SIMLAB_SNAPSHOT_BAD_WORLDS", str(path))
    env = direct_cartpole()
    env.reset()
    for _ in range(3):
        env.step(torch.zeros(6, 1))
    get_rewards = env._get_rewards
    env._get_rewards = lambda: get_rewards() / (torch.arange(6) != 2).float()  # inf in world 2
    before = {name: env.sim.physics.data(name).clone() for name in ("qpos", "qvel")}
    action = torch.linspace(-1, 1, 6).unsqueeze(1)
    with pytest.raises(ValueError, match=rf"in 1 world\(s\) \(2\).*its action: {path}\)") as info:
        env.step(action)
    assert "\n" not in str(info.value)
    kept = torch.load(path)
    assert kept["worlds"].tolist() == [2]
    assert torch.equal(kept["qpos"], before["qpos"][2:3]) and torch.equal(kept["qvel"], before["qvel"][2:3])
    assert torch.equal(kept["action0"], action[2:3])
    env.close()


def blow_up_mid_step(env, world: int, at_physics_step: int) -> None:
    """Write NaN into one joint velocity of ``world`` right after physics step ``at_physics_step``: the
    step's later substeps then run the actuators and the physics on the blown-up state."""
    physics = env.sim.physics
    physics_step, count = physics.step, [0]

    def step_then_blow_up(*args, **kwargs):
        out = physics_step(*args, **kwargs)
        count[0] += 1
        if count[0] == at_physics_step:
            physics.data("qvel")[world, 8] = float("nan")  # a leg joint (the free joint comes first)
        return out

    physics.step = step_then_blow_up


@pytest.mark.parametrize(
    "task",
    [
        "simlab/Velocity-Flat-Spot-v0",  # delayed and remotized PD actuators
        "simlab/Velocity-Flat-Anymal-C-v0",  # an LSTM actuator net
    ],
)
def test_a_restarted_world_leaves_no_nan_in_torques_accelerations_or_actuator_memory(task):
    """Issue 40/41: a Spot world blown up on MuJoCo Warp restarted, yet the torques and accelerations
    derived from its blown-up state stayed NaN, and the task's joint_torques and joint_acc rewards then
    stopped training with the NaN error. Now the restart clears them (and the actuators' delay buffers and
    net states, and the contact histories) in that world only: every value the step returns is finite, and
    the other worlds' states, rewards and observations equal those of a run where nothing blew up."""
    pytest.importorskip("mujoco_warp")
    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    def run(attack: bool) -> tuple[list, ManagerBasedRLEnv]:
        cfg = parse_env_cfg(task, device="cpu", num_envs=4)
        cfg.sim.engine, cfg.sim.use_cuda_graph, cfg.seed = "mujoco_warp", False, 0
        env = ManagerBasedRLEnv(cfg)
        if attack:
            blow_up_mid_step(env, world=2, at_physics_step=cfg.decimation + 1)  # the first substep of step 2
        env.reset()
        actions = 0.3 * torch.ones(4, env.action_manager.total_action_dim)
        out = []
        for _ in range(3):
            obs, reward, terminated, _, _ = env.step(actions)
            robot = env.scene["robot"]
            torques = torch.cat([robot.data.joint_acc, robot.data.applied_torque, robot.data.computed_torque], dim=1)
            state = torch.cat([env.sim.physics.data(name) for name in ("qpos", "qvel")], dim=1)
            values = (obs["policy"], reward, terminated, torques, state)  # copies: the env refills its buffers
            out.append((*(value.clone() for value in values), int(env.sim.physics.diverged_count)))
        return out, env

    clean, env = run(attack=False)
    env.close()
    attacked, env = run(attack=True)  # before the fix: ValueError, NaN in the reward of world 2
    robot = env.scene["robot"]
    for k, (obs, reward, terminated, torques, state, diverged) in enumerate(attacked):
        assert torch.isfinite(obs).all() and torch.isfinite(reward).all() and torch.isfinite(torques).all(), k
        assert terminated.tolist() == [False, False, k == 1, False] and diverged == (k >= 1), k
        others = [0, 1, 3]
        for got, want in zip((obs, reward, torques, state), clean[k][:1] + clean[k][1:2] + clean[k][3:5]):
            assert torch.equal(got[others], want[others]), k
    for actuator in robot.actuators.values():  # what the models keep between steps
        kept = [getattr(actuator, name, None) for name in ("computed_effort", "applied_effort", "_joint_vel")]
        kept += [tensor for _, tensor in getattr(actuator, "state", [])]
        delay = getattr(actuator, "targets_delay_buffer", None)
        if delay is not None:
            kept.append(delay._buffer)
        assert all(torch.isfinite(t).all() for t in kept if t is not None), type(actuator).__name__
    env.close()


def test_the_restart_of_a_task_with_actuator_and_contact_memory_stays_in_the_captured_step(
    emulated_cuda_graph,  # noqa: F811
):
    """The restart clears by mask with no host read: Spot's step (delayed actuators, contact history)
    is still captured whole (the emulated graph fails a capture that reads back)."""
    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    cfg = parse_env_cfg("simlab/Velocity-Flat-Spot-v0", device="cpu", num_envs=4)
    cfg.sim.engine, cfg.seed = "mujoco", 0
    env = ManagerBasedRLEnv(cfg)
    env.sim.physics.forwards_all_worlds = True  # a masked restart then marks worlds stale without a host read
    env._stepper.eager_reason = None  # capture as on a GPU (the physics itself is not replayed here)
    env.reset()
    for _ in range(3):  # two warm-up steps and the capture
        env.step(torch.zeros(4, env.action_manager.total_action_dim))
    assert env.step_is_graphed, env.step_mode
    env.close()


RESTART_XML = """
<mujoco>
  <worldbody>
    <body name="arm"><joint name="hinge" type="hinge"/><geom size="0.1" mass="1"/></body>
    <body name="ball" pos="0 0 1"><freejoint/><geom size="0.05" mass="0.2"/></body>
  </worldbody>
  <actuator>
    <position joint="hinge" kp="10"/>
    <general joint="hinge" dyntype="filter" dynprm="0.1"/>
  </actuator>
</mujoco>
"""


def test_the_warp_restart_kernel_clears_what_the_masked_restart_clears():
    """MuJoCo Warp's restart runs one kernel over the worlds instead of a masked select per field: from
    the same garbage (NaN in one restarted world), it leaves every field as ``PhysicsBackend.restart``
    does, bit for bit: the masked worlds at qpos0 with every other field zero, the others untouched."""
    pytest.importorskip("mujoco_warp")
    import mujoco

    from simlab.sim.backends.base import LAST_STEP_FIELDS, PhysicsBackend
    from simlab.sim.backends.cuda import CudaBackend

    model = mujoco.MjModel.from_xml_string(RESTART_XML)
    fields = ("qpos", "qvel", "act", "qacc_warmstart", "ctrl", "qfrc_applied", "xfrc_applied", *LAST_STEP_FIELDS)
    mask = torch.tensor([False, True, False, True])
    results = []
    for restart in (CudaBackend.restart, PhysicsBackend.restart):
        backend = CudaBackend(model, 4, device="cpu", overflow_check_interval=0)
        generator = torch.Generator().manual_seed(0)
        for name in fields:  # every field bound: the masked restart clears each one then
            tensor = backend.data(name)
            assert tensor.numel(), name
            tensor.copy_(torch.randn(tensor.shape, generator=generator))
        backend.data("qvel")[1, 0] = float("nan")
        before = {name: backend.data(name).clone() for name in fields}
        restart(backend, mask)
        results.append({name: backend.data(name).clone() for name in fields})
    kernel, masked = results
    for name in fields:
        assert torch.equal(kernel[name], masked[name]), name
        assert torch.equal(kernel[name][~mask], before[name][~mask]), name
        if name != "qpos":
            assert (kernel[name][mask] == 0).all(), name
    assert torch.equal(kernel["qpos"][mask], torch.as_tensor(model.qpos0, dtype=torch.float32).expand(2, -1))
