"""rsl_rl's symmetry augmentation through Isaac Lab's ``RslRlSymmetryCfg`` and the cartpole's mirror function."""

from __future__ import annotations

import glob

import pytest
import torch
from tensordict import TensorDict

from simlab.cli.main import main
from simlab.tasks.manager_based.classic.cartpole.mdp.symmetry import compute_symmetric_states


def test_the_cartpoles_mirror_image_negates_every_observation_and_action():
    obs = TensorDict({"policy": torch.arange(8.0).reshape(2, 4)}, batch_size=[2])
    actions = torch.tensor([[0.5], [-1.0]])
    mirrored_obs, mirrored_actions = compute_symmetric_states(None, obs, actions)
    assert mirrored_obs.batch_size == torch.Size([4])
    torch.testing.assert_close(mirrored_obs["policy"], torch.cat([obs["policy"], -obs["policy"]]))
    torch.testing.assert_close(mirrored_actions, torch.tensor([[0.5], [-1.0], [-0.5], [1.0]]))
    assert compute_symmetric_states(None, None, actions)[0] is None


def _median_symmetry_loss(tmp_path, name: str, *overrides: str) -> float:
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    argv = ["train", "--task", "simlab/Cartpole-v0", "--agent", "rsl_rl_with_symmetry_cfg_entry_point", "--headless"]
    argv += ["--device", "cpu", "--num_envs", "64", "--max_iterations", "15", "--seed", "3"]
    argv += ["--log_root", str(tmp_path / name), *overrides]
    assert main(argv) == 0
    (run,) = glob.glob(str(tmp_path / name / "rsl_rl" / "cartpole" / "*"))
    events = EventAccumulator(run)
    events.Reload()
    losses = sorted(e.value for e in events.Scalars("Loss/symmetry"))  # one per iteration
    return losses[len(losses) // 2]


@pytest.mark.slow  # a learning check: two 15-iteration trainings, compared
def test_symmetry_augmentation_makes_the_policy_mirror_symmetric(tmp_path):
    # the same mirror loss is logged either way; only augmentation trains on it
    augmented = _median_symmetry_loss(tmp_path, "augmented")
    logged_only = _median_symmetry_loss(tmp_path, "logged", "agent.algorithm.symmetry_cfg.use_data_augmentation=false")
    assert augmented < 0.2 * logged_only, (augmented, logged_only)
