"""simlab's fast PPO update makes the same update as rsl_rl's own ``PPO.update`` on the same batch."""

from __future__ import annotations

import copy

import pytest
import torch

pytest.importorskip("rsl_rl")
from rsl_rl.algorithms import PPO  # noqa: E402
from tensordict import TensorDict  # noqa: E402

from simlab.cli.libraries.rsl_rl import use_fast_update  # noqa: E402
from simlab.rl.rsl_rl.fast_update import FastPPOUpdate  # noqa: E402
from simlab.tasks.manager_based.classic.cartpole.agents.rsl_rl_ppo_cfg import CartpolePPORunnerCfg  # noqa: E402

NUM_ENVS, OBS_DIM, NUM_ACTIONS = 64, 4, 1


pytestmark = pytest.mark.usefixtures("one_torch_thread")


class _Env:
    """What PPO.construct_algorithm reads of an env."""

    num_envs, num_actions = NUM_ENVS, NUM_ACTIONS


def _observations(device: str = "cpu") -> TensorDict:
    return TensorDict({"policy": torch.randn(NUM_ENVS, OBS_DIM).to(device)}, batch_size=[NUM_ENVS])


def _learner(seed: int, device: str = "cpu", **algorithm: object) -> PPO:
    """A cartpole-configured PPO with one rollout of made-up transitions in its storage."""
    agent_cfg = CartpolePPORunnerCfg()
    for key, value in algorithm.items():
        setattr(agent_cfg.algorithm, key, value)
    cfg = agent_cfg.to_rsl_rl_dict(["policy"])
    cfg["multi_gpu"] = None
    torch.manual_seed(seed)
    obs = _observations(device)
    alg = PPO.construct_algorithm(obs, _Env(), cfg, device)
    with torch.inference_mode():
        for _ in range(cfg["num_steps_per_env"]):
            alg.act(obs)
            obs = _observations(device)
            rewards, dones = torch.randn(NUM_ENVS).to(device), (torch.rand(NUM_ENVS) < 0.05).long().to(device)
            alg.process_env_step(obs, rewards, dones, {"time_outs": (torch.rand(NUM_ENVS) < 0.02).to(device)})
        alg.compute_returns(obs)
    return alg


def _state(alg: PPO) -> dict[str, torch.Tensor]:
    return {
        **{f"actor.{k}": v for k, v in alg.actor.state_dict().items()},
        **{f"critic.{k}": v for k, v in alg.critic.state_dict().items()},
    }


def _update_both(updates: int = 2, **algorithm: object) -> tuple[PPO, PPO, list, list]:
    reference, fast = _learner(0, **algorithm), _learner(0, **algorithm)
    fast.update = FastPPOUpdate(fast)
    ref_losses, fast_losses = [], []
    for i in range(updates):
        if i:  # the next rollout: the same made-up data in both storages, rewritten in place
            for alg in (reference, fast):
                alg.storage.step = alg.storage.num_transitions_per_env
            fast.storage.rewards.copy_(reference.storage.rewards)
        torch.manual_seed(100 + i)
        ref_losses.append(reference.update())
        torch.manual_seed(100 + i)
        fast_losses.append(fast.update())
    return reference, fast, ref_losses, fast_losses


def test_fast_update_matches_rsl_rl_update_with_the_adaptive_learning_rate():
    start = _learner(0)
    initial = copy.deepcopy(_state(start))
    reference, fast, ref_losses, fast_losses = _update_both(updates=1)
    # the adaptive schedule moved the learning rate, and both moved it alike
    assert reference.learning_rate != pytest.approx(1e-3)
    assert fast.learning_rate == pytest.approx(reference.learning_rate, rel=1e-5)
    assert fast.optimizer.param_groups[0]["lr"] == fast.learning_rate  # a float again after the update
    moved = 0.0
    for name, value in _state(reference).items():
        torch.testing.assert_close(_state(fast)[name], value, rtol=1e-4, atol=1e-6, msg=name)
        moved = max(moved, (value - initial[name]).abs().max().item())
    assert moved > 1e-3  # the update changed the weights, so agreeing means something
    for name in ("value", "surrogate", "entropy"):
        assert fast_losses[0][name] == pytest.approx(ref_losses[0][name], rel=1e-4, abs=1e-6)


def test_fast_update_matches_over_updates_with_a_fixed_schedule_and_per_batch_advantages():
    reference, fast, ref_losses, fast_losses = _update_both(
        updates=2, schedule="fixed", normalize_advantage_per_mini_batch=True
    )
    assert fast.learning_rate == reference.learning_rate == pytest.approx(1e-3)
    for name, value in _state(reference).items():
        torch.testing.assert_close(_state(fast)[name], value, rtol=1e-4, atol=1e-6, msg=name)
    assert fast_losses[1]["value"] == pytest.approx(ref_losses[1]["value"], rel=1e-4)


def test_fast_update_picks_up_a_learning_rate_set_from_outside():
    reference, fast, _, _ = _update_both(updates=1)
    for alg in (reference, fast):  # as rsl_rl's load() does from a checkpoint
        alg.learning_rate = 3e-4
        alg.storage.step = alg.storage.num_transitions_per_env
    torch.manual_seed(7)
    reference.update()
    torch.manual_seed(7)
    fast.update()
    assert fast.learning_rate == pytest.approx(reference.learning_rate, rel=1e-5)


def test_another_rsl_rl_release_falls_back_to_its_own_update_with_a_warning(monkeypatch):
    """The fast update copies one release's PPO.update: with another installed it never runs."""
    import importlib.metadata

    from simlab.utils import versions

    assert versions.release_mismatch("rsl-rl-lib") is None  # the checked release (constraints.txt) is installed
    installed = importlib.metadata.version
    monkeypatch.setattr(
        importlib.metadata, "version", lambda name: "5.6.0" if name == "rsl-rl-lib" else installed(name)
    )
    alg = _learner(0)
    # even where asked for (agent.fast_update=true; the default on CUDA takes the same path)
    with pytest.warns(UserWarning, match=r"rsl-rl-lib 5.6.0 is installed, not 5.5: simlab's fast update copies"):
        kind = use_fast_update(alg, True)
    assert kind.startswith("rsl_rl (rsl-rl-lib 5.6.0") and not isinstance(alg.update, FastPPOUpdate)


def test_setting_chooses_the_update_and_says_what_it_does_not_cover():
    alg = _learner(0)
    assert use_fast_update(alg, False) == "rsl_rl"
    assert not isinstance(alg.update, FastPPOUpdate)
    assert use_fast_update(alg, None).startswith("rsl_rl (the fast update pays on CUDA")  # this is a CPU learner
    assert not isinstance(alg.update, FastPPOUpdate)
    assert use_fast_update(alg, True) == "fast"
    assert isinstance(alg.update, FastPPOUpdate)

    sgd = _learner(0, optimizer="sgd")
    with pytest.raises(ValueError, match="agent.fast_update=true.*optimizer SGD"):
        use_fast_update(sgd, True)
    with pytest.raises(ValueError, match="CUDA graph needs a CUDA device"):
        FastPPOUpdate(alg, cuda_graph=True)


def test_simlab_train_with_the_fast_update_trains_the_weights_rsl_rl_does(tmp_path, capsys):
    from simlab.cli.main import build_parser
    from simlab.cli.train import run_train

    weights = {}
    for setting in ("true", "false"):
        argv = ["train", "--task", "simlab/Cartpole-v0", "--headless", "--device", "cpu", "--num_envs", "32"]
        argv += ["--max_iterations", "3", "--seed", "3", "--log_root", str(tmp_path / setting)]
        run_dir = run_train(build_parser().parse_args(argv), [f"agent.fast_update={setting}"])
        weights[setting] = torch.load(f"{run_dir}/model_2.pt", weights_only=False)
        printed = capsys.readouterr().out
        assert (
            f"[simlab] PPO update: {'fast' if setting == 'true' else 'rsl_rl'}; policy in the rollout: eager ("
            in printed
        )
    fast, reference = weights["true"], weights["false"]
    assert isinstance(fast["optimizer_state_dict"]["param_groups"][0]["lr"], float)  # checkpoints load anywhere
    assert not fast["optimizer_state_dict"]["param_groups"][0]["capturable"]
    for model in ("actor_state_dict", "critic_state_dict"):
        for name, value in reference[model].items():
            torch.testing.assert_close(fast[model][name], value, rtol=1e-3, atol=1e-5, msg=f"{model} {name}")


def test_the_rollout_policy_is_graphed_only_where_a_cuda_graph_can_run():
    from simlab.cli.libraries.rsl_rl import use_graphed_act
    from simlab.rl.rsl_rl.graphed_act import GraphedAct

    alg = _learner(0)
    act = alg.act
    assert use_graphed_act(alg, None) == "eager (a CUDA graph needs a CUDA device)"
    assert use_graphed_act(alg, False) == "eager"
    assert alg.act == act  # rsl_rl's own
    with pytest.raises(ValueError, match="agent.graph_act=true, but a CUDA graph needs a CUDA device"):
        use_graphed_act(alg, True)
    with pytest.raises(ValueError, match="cannot be graphed: a CUDA graph needs a CUDA device"):
        GraphedAct(alg)


needs_cuda = pytest.mark.skipif(not torch.cuda.is_available(), reason="needs a CUDA device")


@needs_cuda
def test_on_cuda_the_graphed_update_matches_rsl_rl_update():
    reference, fast = _learner(0, "cuda"), _learner(0, "cuda")
    fast.update = FastPPOUpdate(fast)
    assert fast.update.cuda_graph
    for i in range(3):  # the first update captures, the later ones replay
        if i:
            for alg in (reference, fast):
                alg.storage.step = alg.storage.num_transitions_per_env
        torch.manual_seed(100 + i)
        ref_losses = reference.update()
        torch.manual_seed(100 + i)
        fast_losses = fast.update()
        assert fast.learning_rate == pytest.approx(reference.learning_rate, rel=1e-5)
        for name in ("value", "surrogate", "entropy"):
            assert fast_losses[name] == pytest.approx(ref_losses[name], rel=1e-3, abs=1e-5)
    assert fast.update.captures == 1
    # The replayed graph sums in another order than eager kernels, and Adam moves a weight by about
    # the learning rate (1e-3) whatever its gradient's size, so a rounding difference in a near-zero
    # gradient shows in the weights; on an H200 the largest gap after these updates was 3.4e-5
    # (weights up to 0.55): the tolerance is a tenth of one Adam step.
    for name, value in _state(reference).items():
        torch.testing.assert_close(_state(fast)[name], value, rtol=1e-3, atol=1e-4, msg=name)


@needs_cuda
def test_on_cuda_the_graphed_act_fills_the_transition_as_rsl_rl_act():
    from simlab.rl.rsl_rl.graphed_act import GraphedAct

    alg = _learner(0, "cuda")
    graphed = GraphedAct(alg)
    obs = _observations("cuda")
    sampled = []
    with torch.inference_mode():
        for _ in range(3):
            actions = graphed(obs)
            t = alg.transition
            assert t.observations is obs and actions is t.actions
            sampled.append(actions.clone())
            values, log_prob, params = (
                t.values.clone(),
                t.actions_log_prob.clone(),
                [p.clone() for p in t.distribution_params],
            )
            alg.transition.clear()
            alg.act(obs)  # rsl_rl's own on the same observations: the same values and distribution
            torch.testing.assert_close(values, alg.transition.values)
            for mine, theirs in zip(params, alg.transition.distribution_params):
                torch.testing.assert_close(mine, theirs)
            torch.testing.assert_close(log_prob, alg.actor.get_output_log_prob(sampled[-1]))
            alg.transition.clear()
    assert graphed.captures == 1
    assert not torch.equal(sampled[0], sampled[1])  # each replay draws new noise


def test_capturable_distributions_draw_the_same_normal_and_restore_torch():
    from torch.distributions import Distribution, Normal

    from simlab.rl.rsl_rl.capturable import capturable_distributions

    loc, scale = torch.tensor([1.0, -2.0]), torch.tensor([0.5, 3.0])
    plain_sample, validating = Normal.sample, Distribution._validate_args
    Distribution.set_default_validate_args(True)  # rsl_rl's models may have turned it off
    with capturable_distributions():
        draws = Normal(loc, scale).sample((200_000,))
        Normal(loc, -scale)  # no argument check inside the block (it would read back to the host)
    torch.testing.assert_close(draws.mean(0), loc, atol=0.03, rtol=0)
    torch.testing.assert_close(draws.std(0), scale, atol=0.03, rtol=0)
    assert Normal.sample is plain_sample and Distribution._validate_args
    with pytest.raises(ValueError):
        Normal(loc, -scale)
    Distribution.set_default_validate_args(validating)
