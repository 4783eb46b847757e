"""Isaac Lab's utils surface in simlab: timer, string and dict helpers, asset constants, types, datasets."""

from __future__ import annotations

import json
import math
import time

import numpy as np
import pytest
import torch

from simlab.utils import dict as dict_utils
from simlab.utils import string as string_utils
from simlab.utils.assets import ISAAC_NUCLEUS_DIR, ISAACLAB_NUCLEUS_DIR, NUCLEUS_ASSET_ROOT_DIR, retrieve_file_path
from simlab.utils.datasets import EpisodeData
from simlab.utils.timer import Timer, TimerError
from simlab.utils.types import ArticulationActions

# -- Timer -----------------------------------------------------------------------------------------


def test_timer_elapsed_and_total_run_time():
    t = Timer(name="nap")
    assert t.time_elapsed == 0.0 and t.total_run_time == 0.0
    t.start()
    time.sleep(0.05)
    running = t.time_elapsed
    assert 0.04 < running < 0.5 and t.total_run_time == 0.0  # not stopped yet
    t.stop()
    assert t.total_run_time >= running and t.elapsed == t.total_run_time
    assert Timer.get_timer_info("nap") == t.total_run_time
    with pytest.raises(TimerError, match="already stopped"):
        t.stop()
    with pytest.raises(TimerError, match="No timer named 'never'"):
        Timer.get_timer_info("never")


def test_timer_context_manager_prints_and_refuses_double_start(capsys):
    with Timer("block") as t, pytest.raises(TimerError, match="running"):
        t.start()
    assert capsys.readouterr().out.startswith("block: ")

    @Timer(name="decorated")
    def work():
        return 3

    assert work() == 3 and Timer.get_timer_info("decorated") >= 0.0


# -- string ----------------------------------------------------------------------------------------


def test_case_conversion():
    assert string_utils.to_snake_case("CamelCaseString") == "camel_case_string"
    assert string_utils.to_snake_case("camelCase") == "camel_case"
    assert string_utils.to_snake_case("HTTPServer") == "http_server"
    assert string_utils.to_camel_case("snake_case_string", to="CC") == "SnakeCaseString"
    assert string_utils.to_camel_case("snake_case_string") == "snakeCaseString"
    with pytest.raises(ValueError, match="'cC'"):
        string_utils.to_camel_case("a_b", to="Cc")


def test_resolvable_string_is_lazy_and_resolves_once():
    ref = string_utils.ResolvableString("math:sin")
    assert (ref.__module__, ref.__qualname__, ref.__name__) == ("math", "sin", "sin")
    assert ref(0.0) == 0.0 and ref.resolve() is math.sin
    missing = string_utils.ResolvableString("no_such_module_abc:f")
    assert not hasattr(missing, "__dataclass_fields__")  # probing never imports
    with pytest.raises(ValueError, match="no_such_module_abc"):
        missing()


def test_name_matching_cache_and_non_strict_values():
    names = ["a", "b", "c"]
    string_utils.clear_resolve_matching_names_cache()
    assert string_utils.resolve_matching_names(["b", "a"], names) == ([0, 1], ["a", "b"])
    assert string_utils.resolve_matching_names(["b", "a"], names, preserve_order=True) == ([1, 0], ["b", "a"])
    out = string_utils.resolve_matching_names_values({"a|c": 1, "zz": 2}, names, strict=False)
    assert out == ([0, 2], ["a", "c"], [1, 1])
    with pytest.raises(ValueError, match="Unmatched keys: \\['zz'\\]"):
        string_utils.resolve_matching_names_values({"a|c": 1, "zz": 2}, names)
    with pytest.raises(ValueError, match="Multiple matches for 'a'"):
        string_utils.resolve_matching_names_values({"a|c": 1, "a": 2}, names, strict=False)


# -- dict ------------------------------------------------------------------------------------------


def test_md5_hash_is_stable_and_key_order_free():
    a = {"x": 1, "y": {"z": [1, 2], "w": "s"}}
    b = {"y": {"w": "s", "z": [1, 2]}, "x": 1}
    assert dict_utils.dict_to_md5_hash(a) == dict_utils.dict_to_md5_hash(b)
    assert dict_utils.dict_to_md5_hash(a) != dict_utils.dict_to_md5_hash({**a, "x": 2})
    assert len(dict_utils.dict_to_md5_hash(a)) == 32


def test_slices_round_trip_through_strings_and_yaml_safe_json():
    data = {"ids": slice(None), "nested": [slice(1, 10, 2), {"s": slice(3, None)}], "n": 3}
    as_strings = dict_utils.replace_slices_with_strings(data)
    text = json.dumps(as_strings)  # plain strings now: writable to json or yaml
    assert dict_utils.replace_strings_with_slices(json.loads(text)) == data
    with pytest.raises(ValueError, match="integers or None"):
        string_utils.string_to_slice("slice(a, 2)")


def test_convert_dict_to_backend():
    data = {"t": torch.arange(3), "n": np.ones(2), "inner": {"t": torch.zeros(1)}, "s": "keep"}
    as_np = dict_utils.convert_dict_to_backend(data, backend="numpy")
    assert isinstance(as_np["t"], np.ndarray) and isinstance(as_np["inner"]["t"], np.ndarray)
    assert as_np["s"] == "keep"
    as_torch = dict_utils.convert_dict_to_backend(data, backend="torch", array_types=("numpy",))
    assert isinstance(as_torch["n"], torch.Tensor) and as_torch["t"] is data["t"]
    with pytest.raises(ValueError, match="backend"):
        dict_utils.convert_dict_to_backend(data, backend="jax")


def test_update_from_dict_sets_class_attributes_of_plain_objects():
    class Plain:
        gain = 1.0
        func = staticmethod(math.cos)

    obj = Plain()
    dict_utils.update_class_from_dict(obj, {"gain": 2.0, "func": "math:sin"})
    assert obj.gain == 2.0 and obj.func is math.sin
    with pytest.raises(KeyError, match="'gian'.*Did you mean 'gain'"):
        dict_utils.update_class_from_dict(obj, {"gian": 1.0})


# -- assets and types ------------------------------------------------------------------------------


def test_nucleus_paths_are_refused_with_what_to_use():
    assert ISAACLAB_NUCLEUS_DIR.startswith(ISAAC_NUCLEUS_DIR) and ISAAC_NUCLEUS_DIR.startswith(NUCLEUS_ASSET_ROOT_DIR)
    with pytest.raises(FileNotFoundError, match="MJCF"):
        retrieve_file_path(f"{ISAACLAB_NUCLEUS_DIR}/Robots/ANYbotics/ANYmal-C/anymal_c.usd")
    from simlab.utils.assets import check_usd_path_with_timeout

    with pytest.raises(FileNotFoundError, match="Nucleus.*simlab.robots"):
        check_usd_path_with_timeout(f"{ISAACLAB_NUCLEUS_DIR}/Robots/FrankaEmika/panda_instanceable.usd")
    assert check_usd_path_with_timeout(__file__) and not check_usd_path_with_timeout(__file__ + ".missing")


def test_mjcf_spawner_refuses_a_nucleus_path():
    from simlab.sim.spawners.from_files import MjcfFileCfg, spawn_from_mjcf

    cfg = MjcfFileCfg(asset_path=f"{ISAAC_NUCLEUS_DIR}/Robots/Ant/ant.usd")
    with pytest.raises(FileNotFoundError, match="simlab.robots"):
        spawn_from_mjcf("/World/Robot", cfg)


def test_articulation_actions_defaults():
    actions = ArticulationActions(joint_positions=torch.zeros(2, 3))
    assert actions.joint_velocities is None and actions.joint_efforts is None and actions.joint_indices is None


# -- datasets --------------------------------------------------------------------------------------


def test_episode_data_nested_keys_and_replay_order():
    ep = EpisodeData()
    assert ep.is_empty() and ep.get_next_action() is None and ep.get_state(0) is None
    for k in range(3):
        ep.add("actions", torch.tensor([k, k]))
        ep.add("states", {"robot": {"joint_pos": torch.full((2,), float(k))}})
    assert torch.stack(ep.data["actions"]).shape == (3, 2)  # Isaac Lab's: a list of steps while recording
    assert [ep.get_next_action()[0].item() for _ in range(3)] == [0, 1, 2] and ep.get_next_action() is None
    assert ep.get_next_state()["robot"]["joint_pos"].tolist() == [0.0, 0.0]
    assert ep.get_state(3) is None
    with pytest.raises(ValueError, match="already holds data"):
        ep.add("actions/x", torch.zeros(1))
    ep.pre_export()  # stacked for writing: time first
    assert ep.data["actions"].shape == (3, 2) and ep.data["states"]["robot"]["joint_pos"].shape == (3, 2)
    assert ep.get_state(2)["robot"]["joint_pos"].tolist() == [2.0, 2.0]
    with pytest.raises(ValueError, match="add before pre_export"):
        ep.add("actions", torch.zeros(2))


def test_hdf5_round_trip_is_exact(tmp_path):
    from simlab.utils.datasets import HDF5DatasetFileHandler

    episodes = []
    for seed in range(2):
        ep = EpisodeData()
        ep.seed, ep.success = seed, bool(seed)
        for _ in range(4):
            ep.add("actions", torch.randn(3, dtype=torch.float64))
            ep.add("obs/policy", torch.randn(5))
            ep.add("states/articulation/robot/joint_pos", torch.randint(0, 9, (2,)))
        episodes.append(ep)
    handler = HDF5DatasetFileHandler()
    handler.create(str(tmp_path / "demos" / "run"), env_name="Simlab-Cartpole-v0")
    for ep in episodes:
        handler.write_episode(ep)
    handler.write_episode(EpisodeData())  # empty: skipped
    handler.close()

    reader = HDF5DatasetFileHandler()
    reader.open(str(tmp_path / "demos" / "run.hdf5"))
    assert reader.get_num_episodes() == 2 and reader.get_env_name() == "Simlab-Cartpole-v0"
    for name, original in zip(sorted(reader.get_episode_names()), episodes):
        loaded = reader.load_episode(name, device="cpu")
        assert (loaded.seed, loaded.success, loaded.env_id) == (original.seed, original.success, "Simlab-Cartpole-v0")
        for key in ("actions",):
            assert loaded.data[key].dtype == original.data[key].dtype
            assert torch.equal(loaded.data[key], original.data[key])
        assert torch.equal(loaded.data["obs"]["policy"], original.data["obs"]["policy"])
        joint = loaded.data["states"]["articulation"]["robot"]["joint_pos"]
        assert torch.equal(joint, original.data["states"]["articulation"]["robot"]["joint_pos"])
    assert reader.load_episode("demo_9", device="cpu") is None
    reader.close()
    with pytest.raises(RuntimeError, match="create\\(path\\) or open\\(path\\)"):
        reader.get_env_name()
    with pytest.raises(FileNotFoundError, match="not found"):
        HDF5DatasetFileHandler().open(str(tmp_path / "missing.hdf5"))


# -- array, interpolation, names -------------------------------------------------------------------


def test_convert_to_torch_and_top_level_names():
    import simlab.utils as utils

    assert utils.convert_to_torch(np.arange(3, dtype=np.uint32)).dtype == torch.int32
    shared = np.zeros(2)
    assert utils.convert_to_torch(shared).data_ptr() == shared.ctypes.data  # no copy
    assert utils.convert_to_torch([1, 2], dtype=torch.int64).tolist() == [1, 2]
    assert utils.TENSOR_TYPES["numpy"] is np.ndarray
    assert utils.CircularBuffer is __import__("simlab.utils.buffers", fromlist=["x"]).CircularBuffer
    assert utils.to_snake_case is string_utils.to_snake_case and utils.dict_to_md5_hash is dict_utils.dict_to_md5_hash


def test_linear_interpolation_against_numpy():
    from simlab.utils.interpolation import LinearInterpolation

    x = torch.tensor([0.0, 0.5, 2.0, 3.0])
    y = torch.tensor([1.0, -1.0, 4.0, 0.0])
    q = torch.linspace(-1.0, 4.0, 101, dtype=torch.float64).reshape(101, 1)
    out = LinearInterpolation(x, y, "cpu").compute(q)
    assert out.shape == q.shape
    np.testing.assert_allclose(out.numpy()[:, 0], np.interp(q.numpy()[:, 0], x.numpy(), y.numpy()), atol=1e-6)
    with pytest.raises(ValueError, match="ascending"):
        LinearInterpolation(torch.tensor([1.0, 0.0]), torch.zeros(2), "cpu")
    # K functions per search (a remotized actuator's limit and its negative): each column as alone, bit for bit
    both = LinearInterpolation(x, torch.stack((y, -y), dim=1), "cpu").compute(q.float())
    alone = LinearInterpolation(x, y, "cpu").compute(q.float())
    assert both.shape == (101, 1, 2) and torch.equal(both[..., 0], alone) and torch.equal(both[..., 1], -alone)


def test_unique_names_and_regex_roots():
    taken = {"cam", "cam_1"}
    assert string_utils.find_unique_string_name("cam", lambda s: s not in taken) == "cam_2"
    assert string_utils.find_unique_string_name("imu", lambda s: s not in taken) == "imu"
    assert string_utils.find_root_prim_path_from_regex("/World/envs/env_.*/Robot") == ("/World/envs", 3)
    assert string_utils.find_root_prim_path_from_regex("/World/Robot") == ("/World/Robot", 2)


def test_modifier_chain_applies_functions_and_builds_stateful_modifiers_lazily():
    from simlab.utils import modifiers

    chain = modifiers.ModifierChain(
        [
            modifiers.ModifierCfg(func=modifiers.scale, params={"multiplier": 2.0}),
            modifiers.ModifierCfg(func=lambda data, keep: data[..., :keep], params={"keep": 1}),
            modifiers.IntegratorCfg(dt=0.5),
        ],
        "cpu",
    )
    x = torch.ones(4, 3)
    first = chain(x)
    assert first.shape == (4, 1) and chain._instances[0]._data_dim == (4, 1)
    second = chain(x)
    assert torch.all(second > first)  # the integrator accumulates
    chain.reset([0])
    assert torch.equal(chain(x)[0], first[0]) and torch.all(chain(x)[1:] > second[1:])
    assert torch.equal(x, torch.ones(4, 3))  # the input is not modified
    with pytest.raises(TypeError, match="ModifierCfg"):
        modifiers.ModifierChain([modifiers.scale], "cpu")
