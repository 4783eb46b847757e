"""simlab's rollout step (``agent.fast_rollout``) stores the transitions and logs the episodes that
rsl_rl's ``PPO.process_env_step`` and simlab's per-step logger do, eagerly and (on CUDA) replayed
as one graph per storage row."""

from __future__ import annotations

import contextlib
from types import SimpleNamespace

import pytest
import torch
from conftest import run_logs

pytest.importorskip("rsl_rl")
from rsl_rl.algorithms import PPO  # noqa: E402
from tensordict import TensorDict  # noqa: E402

from simlab.cli.libraries.rsl_rl import _ProgressLogger, use_fast_rollout  # noqa: E402
from simlab.rl.rsl_rl.fast_rollout import FastRolloutStep  # noqa: E402
from simlab.tasks.manager_based.classic.cartpole.agents.rsl_rl_ppo_cfg import CartpolePPORunnerCfg  # noqa: E402

NUM_ENVS, OBS_DIM = 64, 4
needs_cuda = pytest.mark.skipif(not torch.cuda.is_available(), reason="needs a CUDA device")


pytestmark = pytest.mark.usefixtures("one_torch_thread")


def _ppo(device: str) -> tuple[PPO, dict]:
    cfg = CartpolePPORunnerCfg().to_rsl_rl_dict(["policy"])
    cfg["multi_gpu"] = None
    torch.manual_seed(0)
    obs = TensorDict({"policy": torch.zeros(NUM_ENVS, OBS_DIM, device=device)}, batch_size=[NUM_ENVS])
    env = SimpleNamespace(num_envs=NUM_ENVS, num_actions=1)
    return PPO.construct_algorithm(obs, env, cfg, device), cfg


def _logger(cfg: dict, device: str) -> _ProgressLogger:
    return _ProgressLogger(None, cfg, None, NUM_ENVS, False, 1, 0, device)


def _made_up_rollout(seed: int, steps: int, device: str) -> list[tuple]:
    """Observations, rewards, dones and time-outs of ``steps`` env steps (about one env in six ends per step)."""
    g = torch.Generator().manual_seed(seed)
    data = []
    for _ in range(steps + 1):
        obs = TensorDict({"policy": torch.randn(NUM_ENVS, OBS_DIM, generator=g).to(device)}, batch_size=[NUM_ENVS])
        dones = torch.rand(NUM_ENVS, generator=g) < 0.15
        time_outs = dones & (torch.rand(NUM_ENVS, generator=g) < 0.5)
        data.append((obs, torch.randn(NUM_ENVS, generator=g).to(device), dones.long().to(device), time_outs.to(device)))
    return data


def _collect(alg: PPO, step, seed: int, device: str) -> dict[str, torch.Tensor]:
    """One rollout of made-up env steps through ``alg.act`` and ``step``; what the storage then holds."""
    data = _made_up_rollout(seed, alg.storage.num_transitions_per_env, device)
    torch.manual_seed(1000 + seed)  # the policy's draws (also those a replayed act graph makes)
    alg.storage.clear()
    with torch.inference_mode():
        for t in range(alg.storage.num_transitions_per_env):
            alg.act(data[t][0])
            obs, rewards, dones, time_outs = data[t + 1]
            step(obs, rewards, dones, {"time_outs": time_outs})
    s = alg.storage
    stored = {"obs": s.observations["policy"], "actions": s.actions, "rewards": s.rewards, "dones": s.dones}
    stored |= {"values": s.values, "log_prob": s.actions_log_prob, "mean": s.distribution_params[0]}
    return {name: value.clone() for name, value in stored.items()}


def _rsl_rl_step(alg: PPO, logger: _ProgressLogger):
    def step(obs, rewards, dones, extras):
        PPO.process_env_step(alg, obs, rewards, dones, extras)
        logger.process_env_step(rewards, dones, extras)

    return step


def _episodes(logger: _ProgressLogger) -> tuple[list[float], list[float]]:
    logger._flush_finished()
    returns, lengths = list(logger.rewbuffer), list(logger.lenbuffer)
    logger.rewbuffer.clear()
    logger.lenbuffer.clear()
    return returns, lengths


@pytest.mark.parametrize("device", ["cpu", pytest.param("cuda", marks=needs_cuda)])
def test_the_rollout_step_stores_and_logs_what_rsl_rl_and_the_per_step_logger_do(device):
    from simlab.rl.rsl_rl.graphed_act import GraphedAct

    alg, cfg = _ppo(device)
    graphed = device == "cuda"
    if graphed:
        alg.act = GraphedAct(alg)
        with torch.inference_mode():  # capture the act graph now: every rollout below only replays it
            alg.act(_made_up_rollout(0, 0, device)[0][0])
        alg.transition.clear()
    reference_logger, fast_logger = _logger(cfg, device), _logger(cfg, device)
    reference_logger.writer = fast_logger.writer = object()  # as in a run that writes logs
    fast = FastRolloutStep(alg, fast_logger, cuda_graph=graphed)
    assert fast_logger.episode_sums_in_rollout and not reference_logger.episode_sums_in_rollout
    # rollouts 1 (rows run eagerly), 2 (rows captured, then replayed) and 3 (replays) on CUDA
    for seed in (1, 2, 3):
        expected = _collect(alg, _rsl_rl_step(alg, reference_logger), seed, device)
        stored = _collect(alg, lambda *step: (fast(*step), fast_logger.process_env_step(*step[1:])), seed, device)
        for name, value in expected.items():
            assert torch.equal(stored[name], value), f"rollout {seed}: {name}"
        expected_returns, expected_lengths = _episodes(reference_logger)
        returns, lengths = _episodes(fast_logger)
        assert len(expected_returns) > 20 and returns == expected_returns and lengths == expected_lengths
        assert torch.equal(fast_logger.cur_reward_sum, reference_logger.cur_reward_sum)
    assert fast.captures == (alg.storage.num_transitions_per_env if graphed else 0)


def test_the_setting_chooses_the_rollout_step_and_says_why():
    alg, cfg = _ppo("cpu")
    runner = SimpleNamespace(alg=alg, logger=_logger(cfg, "cpu"), cfg=cfg)
    own = alg.process_env_step
    assert use_fast_rollout(runner, False) == "rsl_rl"
    assert use_fast_rollout(runner, None).startswith("rsl_rl (agent.fast_rollout=true: simlab's, opt-in")
    assert alg.process_env_step == own
    assert use_fast_rollout(runner, True) == "fast (eager)"
    assert isinstance(alg.process_env_step, FastRolloutStep) and alg.process_env_step.logger is runner.logger
    with pytest.raises(ValueError, match="needs a CUDA device"):
        FastRolloutStep(alg, cuda_graph=True)
    alg.rnd = object()  # what rsl_rl's PPO holds with an RND config
    with pytest.raises(ValueError, match="agent.fast_rollout=true, but simlab's rollout step does not cover RND"):
        use_fast_rollout(runner, True)


def test_simlab_train_with_the_rollout_step_logs_and_trains_as_rsl_rl_loop(tmp_path, monkeypatch, capsys):
    import glob

    from torch.utils.tensorboard import SummaryWriter

    from simlab.cli.main import build_parser
    from simlab.cli.train import run_train

    scalars: list[tuple[str, float, int]] = []
    monkeypatch.setattr(
        SummaryWriter,
        "add_scalar",
        lambda self, tag, value, step=None, *a, **k: scalars.append((tag, float(value), step)),
    )
    runs = {}
    for setting in ("true", "false"):
        scalars.clear()
        argv = ["train", "--task", "simlab/Cartpole-v0", "--headless", "--device", "cpu", "--num_envs", "16"]
        argv += ["--seed", "5", "--max_iterations", "3", "--log_root", str(tmp_path / setting)]
        # 1 s (60-step) episodes: episodes end in every iteration
        run_train(build_parser().parse_args(argv), ["env.episode_length_s=1.0", f"agent.fast_rollout={setting}"])
        assert f"rollout step: {'fast (eager)' if setting == 'true' else 'rsl_rl'}" in capsys.readouterr().out
        (final,) = glob.glob(str(tmp_path / setting / "rsl_rl" / "cartpole" / "*" / "model_2.pt"))
        episodes = run_logs(scalars, ("Episode_", "Train/mean_"))
        runs[setting] = episodes, torch.load(final, weights_only=False)
    (fast_logs, fast), (own_logs, own) = runs["true"], runs["false"]
    assert {"Train/mean_reward", "Train/mean_episode_length"} <= {tag for tag, _, _ in fast_logs}
    assert fast_logs == own_logs
    for model in ("actor_state_dict", "critic_state_dict"):
        assert all(torch.equal(fast[model][k], own[model][k]) for k in own[model]), model


class _ActWithStaticBuffers:
    """rsl_rl's act run on fixed input and output buffers, as simlab's GraphedAct keeps them (CPU stand-in)."""

    captures = 1
    _graph = "captured"

    def __init__(self, alg: PPO):
        self.alg, self._eager_act, self._obs = alg, alg.act, None

    def __call__(self, obs: TensorDict) -> torch.Tensor:
        if self._obs is None:
            self._obs = obs.clone()
        self._obs.update_(obs)
        self._eager_act(self._obs)
        t = self.alg.transition
        if not hasattr(self, "_outputs"):
            self._outputs = (t.actions.clone(), t.values.clone(), t.actions_log_prob.clone())
            self._distribution_params = tuple(p.clone() for p in t.distribution_params)
        for mine, fresh in zip(
            (*self._outputs, *self._distribution_params),
            (t.actions, t.values, t.actions_log_prob, *t.distribution_params),
        ):
            mine.copy_(fresh)
        t.actions, t.values, t.actions_log_prob = self._outputs
        t.distribution_params, t.observations = self._distribution_params, obs
        return t.actions


def test_a_failed_capture_leaves_nothing_behind_and_the_step_runs_eagerly(monkeypatch, capsys):
    alg, cfg = _ppo("cpu")
    alg.act = _ActWithStaticBuffers(alg)
    reference_logger, fast_logger = _logger(cfg, "cpu"), _logger(cfg, "cpu")
    reference_logger.writer = fast_logger.writer = object()
    fast = FastRolloutStep(alg, fast_logger, cuda_graph=False)
    fast.cuda_graph = True  # as on CUDA; the capture below fails as one that meets a host read would

    class _FailingCapture:
        def __init__(self, *args, **kwargs):
            pass

        def __enter__(self):
            raise RuntimeError("operation not permitted when stream is capturing")

        def __exit__(self, *exc):
            return False

    monkeypatch.setattr(torch.cuda, "CUDAGraph", lambda: None)
    monkeypatch.setattr(torch.cuda, "graph_pool_handle", lambda: None)
    monkeypatch.setattr(torch.cuda, "graph", _FailingCapture)
    monkeypatch.setattr(torch.cuda, "device", lambda device: contextlib.nullcontext())
    for seed in (1, 2):  # the second rollout tries to capture its first row
        expected = _collect(alg, _rsl_rl_step(alg, reference_logger), seed, "cpu")
        stored = _collect(alg, lambda *step: (fast(*step), fast_logger.process_env_step(*step[1:])), seed, "cpu")
        for name, value in expected.items():
            assert torch.equal(stored[name], value), f"rollout {seed}: {name}"
        assert _episodes(fast_logger) == _episodes(reference_logger)
    assert not fast.cuda_graph and fast.captures == 0 and "operation not permitted" in fast.eager_reason
    assert "capture of the rollout step failed, running it eagerly" in capsys.readouterr().out


def test_the_act_graph_key_follows_a_replaced_parameter_or_buffer():
    from simlab.rl.rsl_rl.graphed_act import GraphedAct

    alg, _ = _ppo("cpu")
    act = GraphedAct.__new__(GraphedAct)  # the key alone: a graph needs CUDA
    act.alg, act._slots = alg, None
    obs = _made_up_rollout(0, 0, "cpu")[0][0]
    key = act._static_key(obs)
    assert act._static_key(obs) == key
    layer = alg.actor.mlp[0]
    layer.weight = torch.nn.Parameter(layer.weight.detach().clone())  # a loaded or replaced weight
    assert act._static_key(obs) != key
    key = act._static_key(obs)
    alg.critic.register_buffer("running_std", torch.ones(OBS_DIM))  # a buffer the graph reads, replaced below
    act._slots = None
    key = act._static_key(obs)
    alg.critic.running_std = torch.ones(OBS_DIM)
    assert act._static_key(obs) != key
