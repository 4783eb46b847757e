"""The GPU fast path: masked resets (checked on the CPU) and the captured env step (on the GPU)."""

from __future__ import annotations

import pytest
import torch
from conftest import cuda_available

from simlab.envs.utils.cuda_graph import CudaGraphStep, PackedOutputs, _get
from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv, CartpoleEnvCfg


def make_env(device: str, num_envs: int = 16, use_cuda_graph: bool = True, seed: int = 7) -> CartpoleEnv:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = device
    cfg.sim.use_cuda_graph = use_cuda_graph
    cfg.seed = seed
    return CartpoleEnv(cfg)


def test_masked_reset_matches_index_reset_outside_the_finished_envs():
    """The masked path (eager, on the CPU) changes finished envs only, as the index path does."""
    masked, eager = make_env("cpu"), make_env("cpu")
    masked._cuda_graph = CudaGraphStep(masked, masked._graph_step, warmup=10**9)  # never captures on CPU
    obs_m, _ = masked.reset(seed=3)
    obs_e, _ = eager.reset(seed=3)
    torch.testing.assert_close(obs_m["policy"], obs_e["policy"])
    actions = torch.full((16, 1), 0.3)
    resets = 0
    for _ in range(120):
        obs_m, rew_m, term_m, trunc_m, extras_m = masked.step(actions)
        obs_e, rew_e, term_e, trunc_e, extras_e = eager.step(actions)
        # dones and rewards come before the reset: identical on both paths
        torch.testing.assert_close(term_m, term_e)
        torch.testing.assert_close(rew_m, rew_e)
        done = term_m | trunc_m
        kept = ~done
        torch.testing.assert_close(obs_m["policy"][kept], obs_e["policy"][kept])
        torch.testing.assert_close(extras_m["final_obs"]["policy"], extras_e["final_obs"]["policy"])
        if done.any():
            resets += int(done.sum())
            # reset envs start a new episode from the task's ranges (random draws differ by path)
            pole = obs_m["policy"][done, 0].abs()
            assert (pole <= 0.25 * torch.pi + 1e-5).all()
            assert (masked.episode_length_buf[done] == 0).all()
            # bring the eager env to the masked one's state so the comparison goes on
            eager.cartpole.write_joint_state_to_sim(masked.cartpole.data.joint_pos, masked.cartpole.data.joint_vel)
            eager.sim.forward()
        torch.testing.assert_close(masked.episode_length_buf, eager.episode_length_buf)
    assert resets > 0, "the test must see resets"
    masked.close()
    eager.close()


def test_masked_reset_follows_tensors_a_reset_replaces():
    """The locomotion tasks' reset *replaces* their potentials; the blend must act on the new ones.

    Staggered episode counters make envs time out at different steps; the locomotion reset is
    deterministic, so the masked and the index paths must agree on every value.
    """
    from simlab.tasks.direct.ant.ant_env import AntEnv, AntEnvCfg

    envs = []
    for _ in range(2):
        cfg = AntEnvCfg()
        cfg.scene.num_envs = 8
        cfg.sim.device = "cpu"
        cfg.episode_length_s = 0.5
        envs.append(AntEnv(cfg))
    masked, eager = envs
    masked._cuda_graph = CudaGraphStep(masked, masked._graph_step, warmup=10**9)
    masked.reset()
    eager.reset()
    for env in envs:
        env.episode_length_buf[:] = torch.arange(8) * 3
    actions = torch.full((8, 8), 0.2)
    resets = 0
    for i in range(45):
        obs_m, rew_m, term_m, trunc_m, _ = masked.step(actions)
        obs_e, rew_e, term_e, trunc_e, _ = eager.step(actions)
        torch.testing.assert_close(rew_m, rew_e, msg=f"step {i}")
        torch.testing.assert_close(obs_m["policy"], obs_e["policy"], msg=f"step {i}")
        resets += int((term_m | trunc_m).sum())
    assert resets > 0
    masked.close()
    eager.close()


class ReplayInPlace:
    """Stands in for a CUDA graph on the CPU: a replay recomputes the step into the same buffers."""

    def __init__(self, graph_step: CudaGraphStep):
        self.step = graph_step

    def replay(self) -> None:
        fresh = PackedOutputs(self.step.step_fn(self.step._static_action))
        for dtype, buffer in self.step._packed.buffers.items():
            buffer.copy_(fresh.buffers[dtype])


def test_replayed_outputs_are_not_overwritten_by_the_next_step():
    """Learners keep the observation they acted on past the next step (rsl_rl stores it then):
    what a replayed step returns must not be the graph's buffers, which the next replay overwrites."""
    env = make_env("cpu")
    graph_step = CudaGraphStep(env, env._graph_step, warmup=10**9)
    env._cuda_graph = graph_step
    env.reset(seed=1)
    graph_step._static_action = torch.zeros(16, 1)
    graph_step._packed = PackedOutputs(graph_step.step_fn(graph_step._static_action))
    graph_step.graph = ReplayInPlace(graph_step)
    obs_1, *_ = env.step(torch.full((16, 1), 0.5))
    kept = obs_1["policy"].clone()
    obs_2, *_ = env.step(torch.full((16, 1), -0.5))
    torch.testing.assert_close(obs_1["policy"], kept)  # unchanged by the second step
    assert not torch.equal(obs_2["policy"], kept)
    env.close()


def test_packed_outputs_keep_structure_values_and_dtypes():
    outputs = (
        {"policy": torch.randn(4, 3)},
        torch.randn(4),
        torch.tensor([True, False, True, False]),
        {"log": {"a": torch.tensor(2.5), "n": torch.tensor(3)}},
    )
    packed = PackedOutputs(outputs)
    assert len(packed.buffers) == 3  # float32, bool, int64
    copy = packed.fresh_copy()
    assert isinstance(copy, tuple) and set(copy[0]) == {"policy"}
    for a, b in zip(_flat(outputs), _flat(copy)):
        assert a.dtype == b.dtype and a.shape == b.shape
        torch.testing.assert_close(a, b)
    packed.buffers[torch.float32].zero_()  # the next replay overwrites the buffers ...
    torch.testing.assert_close(copy[0]["policy"], outputs[0]["policy"])  # ... not what was handed out


def _flat(value):
    if isinstance(value, torch.Tensor):
        return [value]
    items = value.values() if isinstance(value, dict) else value
    return [t for item in items for t in _flat(item)]


def test_reset_footprint_covers_task_buffers():
    env = make_env("cpu")
    graph = CudaGraphStep(env, env._graph_step)
    graph.learn_reset_footprint()
    touched = {id(_get(loc)) for loc in graph._touched}
    assert id(env.episode_length_buf) in touched
    assert id(env.sim.physics.data("qpos")) in touched
    env.close()


@pytest.mark.gpu
@pytest.mark.skipif(not cuda_available(), reason="needs an NVIDIA GPU and mujoco-warp")
def test_captured_step_matches_eager_step_on_gpu():
    graphed, eager = make_env("cuda:0", 256), make_env("cuda:0", 256, use_cuda_graph=False)
    graphed.reset(seed=3)
    eager.reset(seed=3)
    actions = torch.zeros(256, 1, device="cuda:0")
    for i in range(20):  # before any episode ends (the pole needs longer to fall past 90 degrees)
        obs_g, rew_g, *_ = graphed.step(actions)
        obs_e, rew_e, *_ = eager.step(actions)
        torch.testing.assert_close(obs_g["policy"], obs_e["policy"], atol=1e-4, rtol=1e-4, msg=f"step {i}")
        torch.testing.assert_close(rew_g, rew_e, atol=1e-4, rtol=1e-4)
    assert graphed._cuda_graph.failed is None, graphed._cuda_graph.failed
    assert graphed._cuda_graph.graph is not None
    # and it keeps running through resets
    for _ in range(400):
        obs_g, *_ = graphed.step(torch.rand(256, 1, device="cuda:0") * 2 - 1)
    assert torch.isfinite(obs_g["policy"]).all()
    assert (graphed.episode_length_buf < graphed.max_episode_length).all()
    graphed.close()
    eager.close()


def make_manager_env(device: str, num_envs: int = 16, use_cuda_graph: bool = True):
    from simlab.envs import ManagerBasedRLEnv
    from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg as ManagerCartpoleCfg

    cfg = ManagerCartpoleCfg()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = device
    cfg.sim.use_cuda_graph = use_cuda_graph
    return ManagerBasedRLEnv(cfg)


def test_manager_env_masked_path_logs_like_the_index_path():
    """The manager-based masked step (eager on the CPU) reports the same episode logs."""
    masked, eager = make_manager_env("cpu"), make_manager_env("cpu")
    masked._cuda_graph = CudaGraphStep(masked, masked._graph_step, warmup=10**9)
    masked.reset(seed=5)
    eager.reset(seed=5)
    actions = torch.full((16, 1), 0.5)
    seen = 0
    for _ in range(150):
        obs_m, rew_m, term_m, trunc_m, extras_m = masked.step(actions)
        obs_e, rew_e, term_e, trunc_e, extras_e = eager.step(actions)
        torch.testing.assert_close(rew_m, rew_e)
        done = term_m | trunc_m
        torch.testing.assert_close(done, term_e | trunc_e)
        if done.any():
            seen += 1
            for key, value in extras_e["log"].items():
                torch.testing.assert_close(extras_m["log"][key], value, msg=key)
            torch.testing.assert_close(extras_m["final_obs"]["policy"], extras_e["final_obs"]["policy"])
            robot_m, robot_e = masked.scene["robot"], eager.scene["robot"]
            robot_e.write_joint_state_to_sim(robot_m.data.joint_pos, robot_m.data.joint_vel)
            eager.sim.forward()
            eager.episode_length_buf.copy_(masked.episode_length_buf)
        torch.testing.assert_close(obs_m["policy"][~done], obs_e["policy"][~done])
    assert seen > 0
    masked.close()
    eager.close()


@pytest.mark.gpu
@pytest.mark.skipif(not cuda_available(), reason="needs an NVIDIA GPU and mujoco-warp")
def test_manager_env_captures_on_gpu():
    graphed, eager = make_manager_env("cuda:0", 256), make_manager_env("cuda:0", 256, use_cuda_graph=False)
    graphed.reset(seed=3)
    eager.reset(seed=3)
    actions = torch.zeros(256, 1, device="cuda:0")
    for i in range(20):
        obs_g, rew_g, *_ = graphed.step(actions)
        obs_e, rew_e, *_ = eager.step(actions)
        torch.testing.assert_close(obs_g["policy"], obs_e["policy"], atol=1e-4, rtol=1e-4, msg=f"step {i}")
    assert graphed._cuda_graph.failed is None, graphed._cuda_graph.failed
    for _ in range(400):
        obs_g, *_ = graphed.step(torch.rand(256, 1, device="cuda:0") * 2 - 1)
    assert torch.isfinite(obs_g["policy"]).all()
    graphed.close()
    eager.close()


@pytest.mark.gpu
def test_diverged_state_is_reported_at_the_periodic_check():
    env = make_env("cuda:0", 64)
    env.reset()
    actions = torch.zeros(64, 1, device="cuda:0")
    for _ in range(4):  # warm-up steps and the capture
        env.step(actions)
    assert env._cuda_graph.graph is not None, env._cuda_graph.failed
    env._cuda_graph.check_interval = 2
    env.scene["cartpole"]._qvel[3] = float("nan")
    with pytest.raises(ValueError, match="NaN or inf"):
        for _ in range(4):
            env.step(actions)
    env.close()


@pytest.mark.gpu
def test_an_env_left_to_garbage_collection_does_not_break_the_next_capture():
    """An env nobody closed is freed by the cyclic collector; its CUDA graphs must not be destroyed
    in the middle of the next env's captures (which invalidates them)."""
    actions = torch.zeros(32, 1, device="cuda:0")
    for _ in range(3):
        env = make_env("cuda:0", 32)
        env.reset()
        for _ in range(4):
            env.step(actions)
        assert env._cuda_graph.graph is not None, env._cuda_graph.failed
        cycle = [env]
        cycle.append(cycle)  # only the cyclic collector can free it now
        del env, cycle


def test_closing_releases_the_graph():
    env = make_env("cpu")
    graph_step = CudaGraphStep(env, env._graph_step, warmup=10**9)
    env._cuda_graph = graph_step
    graph_step.graph = object()  # stands in for a captured graph
    env.close()
    assert graph_step.graph is None and graph_step.failed == "released"
