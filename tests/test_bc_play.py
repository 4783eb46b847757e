"""A behaviour-cloned policy (simlab.rl.bc) is played, exported and stored like an RL library's:
``simlab play --library bc`` loads its file as weights only, and a shipped ``policy.pt`` unpacks to it."""

from __future__ import annotations

import pickle
import warnings
from pathlib import Path

import pytest
import torch

from simlab.cli.main import build_parser, main
from simlab.cli.play import run_play
from simlab.rl.bc import BCPolicy, load_bc_policy, save_bc_policy

TASK = "simlab/Stack-Cube-Franka-IK-Abs-v0"  # registers bc_cfg_entry_point
TERMS = ["eef_pos", "eef_quat", "gripper_pos", "object"]  # 3 + 4 + 2 + 39 columns of the policy group


def _policy_file(path: Path) -> BCPolicy:
    torch.manual_seed(0)
    policy = BCPolicy(TERMS, 48, 8, [32, 32], relative=3)
    policy.obs_std[:] = torch.rand(48) + 0.5
    save_bc_policy(policy, str(path), TASK, epochs=5)
    return policy


def test_play_steps_the_env_with_the_bc_policy_and_exports_what_it_plays(tmp_path):
    policy = _policy_file(tmp_path / "run" / "stack.pt")
    argv = ["play", "--task", TASK, "--library", "bc", "--checkpoint", str(tmp_path / "run" / "stack.pt")]
    argv += ["--headless", "--device", "cpu", "--num_envs", "2", "--steps", "3", "--log_root", str(tmp_path)]
    steps: list[tuple[dict, torch.Tensor]] = []
    result = run_play(build_parser().parse_args(argv), [], on_step=lambda env, obs, a: steps.append((obs, a.clone())))
    (obs, _), (_, actions) = steps[0], steps[1]  # the second step's actions are the policy's of the first's obs
    torch.testing.assert_close(actions, policy.act(obs["policy"]), rtol=0, atol=1e-6)
    # the export reads the whole policy group, concatenated in its order, as its deploy metadata says
    with warnings.catch_warnings():  # TorchScript's load is deprecated in torch 2.10+, still what play exports
        warnings.simplefilter("ignore", DeprecationWarning)
        exported = torch.jit.load(next(f for f in result["exported"] if f.endswith(".pt")))
    flat = torch.cat([v.reshape(2, -1) for v in obs["policy"].values()], dim=-1)
    torch.testing.assert_close(exported(flat), actions, rtol=0, atol=1e-5)


def test_a_bc_checkpoint_that_would_run_code_is_refused_and_runs_nothing(tmp_path, capsys):
    planted = tmp_path / "planted"

    class Payload:
        def __reduce__(self):
            return (Path.touch, (planted,))

    with open(tmp_path / "stack.pt", "wb") as file:
        pickle.dump({"state_dict": Payload(), "terms": TERMS}, file, protocol=2)  # the protocol torch.save writes
    argv = ["play", "--task", TASK, "--library", "bc", "--checkpoint", str(tmp_path / "stack.pt"), "--headless"]
    assert main([*argv, "--device", "cpu", "--log_root", str(tmp_path)]) == 2
    assert "Refused to load" in capsys.readouterr().err
    assert not planted.exists()


def test_a_bc_policy_of_other_terms_is_refused_in_one_line(tmp_path, capsys):
    for terms, size, said in ((["eef_pos", "nope"], 5, "which this env lacks"), (["eef_pos"], 4, "3 wide")):
        save_bc_policy(BCPolicy(terms, size, 8, [4]), str(tmp_path / "other.pt"), TASK)
        argv = ["play", "--task", TASK, "--library", "bc", "--checkpoint", str(tmp_path / "other.pt"), "--headless"]
        assert main([*argv, "--device", "cpu", "--num_envs", "1", "--log_root", str(tmp_path)]) == 2
        assert said in capsys.readouterr().err


def test_train_with_bc_names_the_command_that_fits_a_policy(tmp_path, capsys):
    argv = ["train", "--task", TASK, "--library", "bc", "--headless", "--device", "cpu", "--log_root", str(tmp_path)]
    assert main(argv) == 2
    assert "scripts/imitation_learning/bc.py train" in capsys.readouterr().err


def test_a_stored_bc_policy_unpacks_to_the_policy_within_int8_rows(tmp_path):
    from simlab.pretrained.weights import pack_policy, read_checkpoint, unpack_policy, write_checkpoint

    policy = _policy_file(tmp_path / "stack.pt")
    torch.save(pack_policy(read_checkpoint(str(tmp_path / "stack.pt"), "bc"), "bc", "stack.pt"), tmp_path / "policy.pt")
    name, checkpoint = unpack_policy(str(tmp_path / "policy.pt"))  # weights only
    write_checkpoint(checkpoint, str(tmp_path / "out.pt"), "bc")
    back, task = load_bc_policy(str(tmp_path / "out.pt"))
    assert (name, task, back.terms, back.hidden) == ("stack.pt", TASK, TERMS, [32, 32])
    assert torch.equal(back.obs_std, policy.obs_std)  # vectors stay float32
    weight = policy.mlp[0].weight.detach()
    assert float((back.mlp[0].weight - weight).abs().max()) <= float(weight.abs().max()) / 254 * 1.0001
    with pytest.raises(KeyError, match="play needs"):
        pack_policy({"state_dict": {}}, "bc", "stack.pt")


def test_a_file_that_is_not_a_bc_policy_is_refused_in_one_line(tmp_path):
    """bc.py play and make_pretrained read the file directly (no play wrapper): a missing file, bytes torch
    cannot read and another library's checkpoint each give a CheckpointError naming the file."""
    from simlab.utils.errors import CheckpointError

    rsl_rl = tmp_path / "model_3.pt"
    torch.save({"model_state_dict": {"w": torch.zeros(2)}, "iter": 3}, rsl_rl)
    corrupt = tmp_path / "corrupt.pt"
    corrupt.write_bytes(b"not a torch file")
    wrong_sizes = tmp_path / "sizes.pt"
    _policy_file(wrong_sizes)
    saved = torch.load(wrong_sizes, weights_only=True)
    torch.save({**saved, "sizes": [47, 8]}, wrong_sizes)
    cases = {
        tmp_path / "missing.pt": "does not exist",
        rsl_rl: r"not a BC policy.*lacks \['state_dict', 'terms'",
        corrupt: "Cannot read the BC policy",
        wrong_sizes: "Cannot read the BC policy",
    }
    for path, message in cases.items():
        with pytest.raises(CheckpointError, match=message) as error:
            load_bc_policy(str(path))
        assert str(path) in str(error.value) and "\n" not in str(error.value)
