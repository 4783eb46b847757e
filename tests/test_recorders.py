"""Recording episodes: recorder terms, export modes, the HDF5 files they write, and demonstrations
recorded and replayed bit-identically (``simlab record`` / ``simlab replay``)."""

from __future__ import annotations

import os

import h5py
import pytest
import torch

import simlab.envs.mdp as mdp
from simlab.cli.main import main
from simlab.envs import ManagerBasedEnv, ManagerBasedEnvCfg
from simlab.managers import DatasetExportMode, RecorderManagerBaseCfg, RecorderTerm, RecorderTermCfg
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.scene import InteractiveSceneCfg
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleSceneCfg
from simlab.utils import configclass
from simlab.utils.datasets import HDF5DatasetFileHandler


class StepCounter(RecorderTerm):
    """Records the env's step count before and after each step, and the ids that reset."""

    def record_pre_step(self):
        return "count/pre", self._env._step_count.repeat(self.num_envs, 1).float()

    def record_post_step(self):
        return "count/post", self._env._step_count.repeat(self.num_envs, 1).float()

    def record_pre_reset(self, env_ids):
        return "reset_id", torch.tensor(env_ids, dtype=torch.float32).unsqueeze(1)


@configclass
class CounterRecorderCfg(RecorderManagerBaseCfg):
    counter = RecorderTermCfg(class_type=StepCounter)


@configclass
class NoTerms:
    pass


@configclass
class ActionsCfg:
    joint_effort = mdp.JointEffortActionCfg(asset_name="robot", joint_names=["slider_to_cart"], scale=5.0)


@configclass
class ObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        joint_pos = ObsTerm(func=mdp.joint_pos_rel)

    policy: PolicyCfg = PolicyCfg()


@configclass
class CartpoleRecordCfg(ManagerBasedEnvCfg):
    scene = CartpoleSceneCfg(num_envs=2, env_spacing=4.0)
    actions = ActionsCfg()
    observations = ObservationsCfg()

    def __post_init__(self):
        self.decimation = 2
        self.sim.dt = 0.01
        self.sim.device = "cpu"


def _read(path: str) -> dict[str, torch.Tensor]:
    with h5py.File(path, "r") as f:
        out = {}
        f.visititems(
            lambda name, obj: out.update({name: torch.from_numpy(obj[()])}) if isinstance(obj, h5py.Dataset) else None
        )
        return out


def test_episodes_are_written_at_reset_and_read_back_exactly(tmp_path):
    cfg = CartpoleRecordCfg()
    cfg.recorders = CounterRecorderCfg(dataset_export_dir_path=str(tmp_path), dataset_filename="counts")
    env = ManagerBasedEnv(cfg)  # no reset: a reset would record (and export) a "reset_id" episode
    for _ in range(3):
        env.step(torch.zeros(2, 1))
    recorded = env.recorder_manager.get_episode(1).data["count"]  # Isaac Lab's: lists of steps while recording
    assert torch.stack(recorded["post"]).flatten().tolist() == [1.0, 2.0, 3.0]
    in_memory = torch.stack(recorded["pre"])
    env.reset(env_ids=[1])  # exports env 1's episode only
    files = _read(str(tmp_path / "counts.hdf5"))
    assert sorted(files) == ["data/demo_0/count/post", "data/demo_0/count/pre", "data/demo_0/reset_id"]
    assert torch.equal(files["data/demo_0/count/pre"], in_memory) and files["data/demo_0/reset_id"].item() == 1.0
    assert env.recorder_manager.get_episode(1).is_empty() and not env.recorder_manager.get_episode(0).is_empty()
    handler = HDF5DatasetFileHandler()
    handler.open(str(tmp_path / "counts.hdf5"))
    loaded = handler.load_episode("demo_0", "cpu")
    assert torch.equal(loaded.data["count"]["pre"], in_memory)
    handler.close()
    env.close()


def test_export_modes_split_succeeded_and_failed(tmp_path):
    cfg = CartpoleRecordCfg()
    cfg.recorders = CounterRecorderCfg(
        dataset_export_dir_path=str(tmp_path),
        dataset_export_mode=DatasetExportMode.EXPORT_SUCCEEDED_FAILED_IN_SEPARATE_FILES,
        export_in_record_pre_reset=False,
    )
    env = ManagerBasedEnv(cfg)
    env.step(torch.zeros(2, 1))
    env.recorder_manager.set_success_to_episodes([0, 1], torch.tensor([True, False]))
    env.recorder_manager.export_episodes()
    assert env.recorder_manager.exported_successful_episode_count == 1
    assert env.recorder_manager.exported_failed_episode_count == 1
    assert len(_read(str(tmp_path / "dataset.hdf5"))) == 2  # count/pre and count/post of env 0
    assert len(_read(str(tmp_path / "dataset_failed.hdf5"))) == 2
    env.close()


def test_export_in_close_writes_the_open_episodes(tmp_path):
    cfg = CartpoleRecordCfg()
    cfg.recorders = CounterRecorderCfg(dataset_export_dir_path=str(tmp_path), export_in_close=True)
    env = ManagerBasedEnv(cfg)
    env.step(torch.zeros(2, 1))
    assert _read(str(tmp_path / "dataset.hdf5")) == {}
    env.close()
    assert len(_read(str(tmp_path / "dataset.hdf5"))) == 4


def test_recorders_config_must_be_a_recorder_manager_cfg():
    @configclass
    class Plain:
        counter = RecorderTermCfg(class_type=StepCounter)

    cfg = CartpoleRecordCfg()
    cfg.recorders = Plain()
    with pytest.raises(TypeError, match="RecorderManagerBaseCfg"):
        ManagerBasedEnv(cfg)


def test_an_env_without_action_terms_takes_a_zero_wide_action():
    @configclass
    class EmptyCfg(ManagerBasedEnvCfg):
        scene = InteractiveSceneCfg(num_envs=2, env_spacing=1.0)
        actions = NoTerms()
        observations = NoTerms()

        def __post_init__(self):
            self.decimation = 2
            self.sim.device = "cpu"

    env = ManagerBasedEnv(EmptyCfg())
    assert env.action_manager.action.shape == (2, 0)
    obs, _ = env.step(torch.zeros(2, 0))
    assert obs == {}
    with pytest.raises(ValueError):
        env.step(torch.zeros(2, 1))
    env.close()


def test_recorded_demos_replay_bit_identically(tmp_path, capsys):
    dataset = str(tmp_path / "demos.hdf5")
    common = ["--task", "simlab/Cartpole-v0", "--device", "cpu", "--headless", "--dataset_file", dataset]
    assert main(["record", *common, "--num_envs", "2", "--num_demos", "2", "env.episode_length_s=0.5"]) == 0
    handler = HDF5DatasetFileHandler()
    handler.open(dataset)
    episode = handler.load_episode("demo_1", "cpu")
    assert set(episode.data) == {"initial_state", "actions", "obs", "states", "processed_actions"}
    assert episode.data["actions"].shape == (30, 1)  # 0.5 s at 60 Hz
    handler.close()
    assert main(["replay", *common, "--validate_states"]) == 0
    out = capsys.readouterr().out
    assert out.count("30 steps replayed, states bit-identical") == 2


def test_record_keeps_an_existing_dataset_and_writes_the_file_it_names(tmp_path, capsys):
    dataset = tmp_path / "demos.hdf5"
    dataset.write_bytes(b"the user's demonstrations")
    common = ["--task", "simlab/Cartpole-v0", "--device", "cpu", "--headless", "env.episode_length_s=0.1"]
    assert main(["record", *common, "--dataset_file", str(dataset)]) == 2
    assert "demos.hdf5 exists: give another --dataset_file, or --overwrite" in capsys.readouterr().err
    assert dataset.read_bytes() == b"the user's demonstrations"
    assert main(["record", *common, "--dataset_file", str(tmp_path / "demos.h5")]) == 2
    assert "--dataset_file must end with .hdf5" in capsys.readouterr().err
    assert sorted(os.listdir(tmp_path)) == ["demos.hdf5"]
    assert main(["record", *common, "--dataset_file", str(dataset), "--overwrite"]) == 0
    assert f"into {dataset}" in capsys.readouterr().out
    assert dataset.read_bytes()[:8] == b"\x89HDF\r\n\x1a\n"  # an HDF5 file now


def test_a_relative_state_moves_between_envs_to_the_bit():
    """``get_state(is_relative=True)`` holds root positions from the env origins exactly (each env is
    its own MuJoCo world) and the root's turning in its own frame, so an env's state put into another
    env is the same state: through the world frame, ``(q + origin) - origin`` and the turning's
    rotation there and back round in float32 where physics has left them off the grid."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    task = "simlab/Lift-Cube-Franka-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=4)).unwrapped
    env.reset()
    cube = env.scene["object"]
    moved = torch.tensor([[0.4123457, -0.1987655, 0.0550001, 0.9, 0.1, 0.2, 0.3]])  # off the origins' grid
    cube.write_root_pose_to_sim(moved + torch.cat([env.scene.env_origins[3], torch.zeros(4)]), torch.tensor([3]))
    cube.write_root_velocity_to_sim(torch.tensor([[0.1, 0.2, 0.3, 0.7, -1.3, 2.9]]), torch.tensor([3]))
    env.sim.step()  # physics leaves the position, unit quaternion and turning off any grid
    state = env.scene.get_state(is_relative=True)
    row = {g: {n: {k: v[3:4] for k, v in entry.items()} for n, entry in group.items()} for g, group in state.items()}
    env.scene.reset_to(row, torch.tensor([0]), is_relative=True)
    after = env.scene.get_state(is_relative=True)["rigid_object"]["object"]
    env.close()
    for key, value in after.items():
        assert torch.equal(value[0], value[3]), key


def test_a_states_edited_root_velocity_is_written():
    """A state whose ``root_velocity`` was changed after ``get_state`` (as Isaac Lab's code may do:
    there the velocity is that key) is written with the new velocity: ``root_ang_vel_b`` replaces
    the angular part only where it is that same turning, exactly."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    task = "simlab/Lift-Cube-Franka-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=2)).unwrapped
    env.reset()
    cube = env.scene["object"]
    cube.write_root_velocity_to_sim(torch.tensor([[0.0, 0.0, 0.0, 0.7, -1.3, 2.9]]).repeat(2, 1))
    state = env.scene.get_state()
    edited = torch.tensor([0.1, 0.2, 0.3, -0.5, 0.25, 0.0])
    state["rigid_object"]["object"]["root_velocity"][1] = edited
    env.scene.reset_to(state)
    velocity = cube.data.root_vel_w.clone()
    env.close()
    torch.testing.assert_close(velocity[1], edited, atol=1e-6, rtol=0)
    torch.testing.assert_close(velocity[0, 3:], torch.tensor([0.7, -1.3, 2.9]), atol=1e-6, rtol=0)


def test_reset_to_writes_a_roots_velocity_once(monkeypatch):
    """A state's root velocity goes in with one write of each column: the angular velocity in the
    root's frame (``root_ang_vel_b``, exact) is not first written from the world frame, then again."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.assets.root_body import RootedAsset
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    task = "simlab/Lift-Cube-Franka-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=2)).unwrapped
    env.reset()
    cube = env.scene["object"]
    cube.write_root_velocity_to_sim(torch.tensor([[0.1, 0.2, 0.3, 0.7, -1.3, 2.9]]).repeat(2, 1))
    state = env.scene.get_state()
    written: list[slice] = []
    write_cols = RootedAsset._write_cols

    def spy(dst, cols, env_ids, values):
        if dst is cube._qvel:  # the velocity columns written
            written.append(cols)
        write_cols(dst, cols, env_ids, values)

    monkeypatch.setattr(RootedAsset, "_write_cols", staticmethod(spy))
    env.scene.reset_to(state)
    monkeypatch.undo()
    after = env.scene.get_state()["rigid_object"]["object"]
    env.close()
    assert written.count(cube._root_ang_cols) == 1 and written.count(cube._root_lin_cols) == 1, written
    for key, value in state["rigid_object"]["object"].items():
        assert torch.equal(after[key], value), key


def test_demos_recorded_in_several_envs_replay_bit_identically_in_one(tmp_path, capsys):
    """Each env sits at its own origin, the replay's one env at another: the arm's IK reads the hand's
    pose from the robot's root in env-frame positions, so nothing of an origin's float32 rounding
    reaches the actions' joint targets (through the world frame: 2e-7 to 7e-5 off in 50 steps)."""
    dataset = str(tmp_path / "demos.hdf5")
    common = ["--task", "simlab/Lift-Cube-Franka-IK-Abs-v0", "--device", "cpu", "--headless", "--dataset_file", dataset]
    assert main(["record", *common, "--num_envs", "4", "--num_demos", "4", "env.episode_length_s=0.5"]) == 0
    assert main(["replay", *common, "--validate_states"]) == 0
    assert capsys.readouterr().out.count("states bit-identical") == 4


def test_a_state_restored_by_scene_reset_to_replays_bit_identically():
    """``scene.reset_to`` called directly starts the worlds from exactly the state it writes, as the
    env's resets do (the backend's ``mark_reset``): the float64 digits and the solver's warm start the
    worlds had before are dropped, so the same actions from the same restored state give the same
    states to the bit, whatever ran in between (the cube rests on the table: its contacts warm-start)."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    task = "simlab/Lift-Cube-Franka-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=2)).unwrapped
    env.reset()
    generator = torch.Generator().manual_seed(0)
    actions = [0.5 * torch.randn(2, env.action_manager.total_action_dim, generator=generator) for _ in range(12)]
    for action in actions[:4]:
        env.step(action)
    start = env.scene.get_state()

    def replay() -> list[dict]:
        env.scene.reset_to(start)
        states = []
        for action in actions[4:]:
            env.step(action)
            states.append(env.scene.get_state())
        return states

    first = replay()
    for action in actions[:6]:  # elsewhere in between: other float64 digits, another warm start
        env.step(-action)
    second = replay()
    env.close()
    for step, (a, b) in enumerate(zip(first, second, strict=True)):
        for group, assets in a.items():
            for name, entry in assets.items():
                for key, value in entry.items():
                    assert torch.equal(value, b[group][name][key]), f"step {step}: {group}/{name}/{key}"
