"""yaml / pickle io, dict helpers, asset paths, seeding, timer."""

from __future__ import annotations

import os
import random
import time

import numpy as np
import pytest
import torch
import yaml

from simlab.utils import configclass, set_seed
from simlab.utils.assets import check_file_path, retrieve_file_path
from simlab.utils.configclass import MISSING
from simlab.utils.dict import class_to_dict, print_dict, update_class_from_dict, update_dict
from simlab.utils.io import dump_pickle, dump_yaml, load_pickle, load_yaml
from simlab.utils.timer import Timer


@configclass
class SimCfg:
    dt = 0.005
    gravity = (0.0, 0.0, -9.81)
    device: str = MISSING


def test_dump_yaml_creates_dirs_and_handles_types(tmp_path):
    path = tmp_path / "a" / "b" / "params.yaml"
    data = {
        "fn": os.path.join,
        "cls": SimCfg,
        "tuple": (1, 2),
        "np_scalar": np.float32(1.5),
        "np_array": np.arange(3),
        "torch_scalar": torch.tensor(2.5),
        "torch_vec": torch.tensor([1.0, 2.0]),
        "nested": {"cfg": SimCfg(device="cpu")},
        "missing": MISSING,
    }
    dump_yaml(path, data)
    back = load_yaml(path)
    assert back["fn"] == f"{os.path.join.__module__}:join"
    assert back["cls"] == f"{__name__}:SimCfg"
    assert back["tuple"] == (1, 2)
    assert back["np_scalar"] == 1.5 and back["np_array"] == [0, 1, 2]
    assert back["torch_scalar"] == 2.5 and back["torch_vec"] == [1.0, 2.0]
    assert back["nested"]["cfg"] == {"dt": 0.005, "gravity": (0.0, 0.0, -9.81), "device": "cpu"}
    assert back["missing"] == "???"


def test_yaml_tuples_round_trip_with_pyyamls_tuple_tag(tmp_path):
    data = {"pos": (0.0, 1.0), "mixed": [(1, 2), [3, (4,)]], "empty": (), "nested": {"t": ((1, 2), "a")}}
    dump_yaml(tmp_path / "t.yaml", data)
    text = (tmp_path / "t.yaml").read_text()
    assert "!!python/tuple" in text
    back = load_yaml(tmp_path / "t.yaml")
    assert back == data and type(back["mixed"][1][1]) is tuple and type(back["mixed"][1]) is list
    # PyYAML's own full loader (what Isaac Lab reads its configs with) reads the same values
    assert yaml.full_load(text) == data
    # an Isaac Lab file's tuples load; any other python tag is refused, not constructed
    (tmp_path / "isaac.yaml").write_text("eye: !!python/tuple\n- 7.5\n- 7.5\n- 7.5\n")
    assert load_yaml(tmp_path / "isaac.yaml") == {"eye": (7.5, 7.5, 7.5)}
    (tmp_path / "evil.yaml").write_text("x: !!python/object/apply:os.getcwd []\n")
    with pytest.raises(yaml.constructor.ConstructorError, match="python/object/apply"):
        load_yaml(tmp_path / "evil.yaml")


def test_dump_yaml_configclass_keeps_field_order(tmp_path):
    dump_yaml(tmp_path / "sim", SimCfg(device="cuda:0"))  # ".yaml" is appended
    text = (tmp_path / "sim.yaml").read_text()
    assert text.index("dt:") < text.index("gravity:") < text.index("device:")
    assert load_yaml(tmp_path / "sim.yaml")["device"] == "cuda:0"


def test_dump_yaml_rejects_other_types(tmp_path):
    with pytest.raises(TypeError, match="dict or a configclass"):
        dump_yaml(tmp_path / "x.yaml", [1, 2])


def test_load_missing_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="nope.yaml"):
        load_yaml(tmp_path / "nope.yaml")
    with pytest.raises(FileNotFoundError, match="nope.pkl"):
        load_pickle(tmp_path / "nope.pkl")
    (tmp_path / "empty.yaml").write_text("")
    assert load_yaml(tmp_path / "empty.yaml") == {}


def test_pickle_round_trip(tmp_path):
    cfg = SimCfg(device="cpu")
    dump_pickle(tmp_path / "p" / "env.pkl", cfg)
    back = load_pickle(tmp_path / "p" / "env.pkl", allow_modules=[SimCfg.__module__])  # a config of this test
    assert back == cfg and back is not cfg


def test_class_to_dict_and_update(tmp_path):
    cfg = SimCfg()
    d = class_to_dict(cfg)
    assert d == {"dt": 0.005, "gravity": (0.0, 0.0, -9.81), "device": MISSING}
    update_class_from_dict(cfg, {"dt": 0.01, "device": "cpu"})
    assert cfg.dt == 0.01 and cfg.device == "cpu"
    with pytest.raises(KeyError, match="'dtt'.*Did you mean 'dt'"):
        update_class_from_dict(cfg, {"dtt": 1.0})


def test_update_dict_merges_nested():
    orig = {"a": {"b": 1, "c": 2}, "d": 3}
    out = update_dict(orig, {"a": {"c": 5, "e": 6}, "f": 7})
    assert out is orig
    assert orig == {"a": {"b": 1, "c": 5, "e": 6}, "d": 3, "f": 7}


def test_print_dict(capsys):
    print_dict({"env": {"dt": 0.01, "fn": os.path.join}, "seed": 1})
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "env: "
    assert out[1] == "    dt: 0.01"
    assert out[2] == f"    fn: {os.path.join.__module__}:join"
    assert out[3] == "seed: 1"


def test_retrieve_file_path(tmp_path, monkeypatch):
    f = tmp_path / "robot.xml"
    f.write_text("<mujoco/>")
    assert retrieve_file_path(str(f)) == str(f)
    monkeypatch.chdir(tmp_path)
    assert retrieve_file_path("robot.xml") == str(f)  # relative
    monkeypatch.setenv("HOME", str(tmp_path))
    assert retrieve_file_path("~/robot.xml") == str(f)
    assert check_file_path(f) == 1 and check_file_path(tmp_path / "nope.xml") == 0
    with pytest.raises(FileNotFoundError, match="nope.xml"):
        retrieve_file_path(tmp_path / "nope.xml")
    copied = retrieve_file_path(f, download_dir=tmp_path / "dl")
    assert copied == str(tmp_path / "dl" / "robot.xml") and os.path.isfile(copied)


def test_set_seed_reproducible():
    assert set_seed(123) == 123
    a = (random.random(), np.random.rand(), torch.rand(1).item())
    set_seed(123)
    b = (random.random(), np.random.rand(), torch.rand(1).item())
    assert a == b
    s = set_seed(-1)
    assert isinstance(s, int) and 0 <= s < 2**32
    with pytest.raises(TypeError, match="seed must be an int"):
        set_seed(1.5)


def test_timer():
    with Timer() as t:
        time.sleep(0.01)
    assert t.elapsed >= 0.01
    frozen = t.elapsed
    time.sleep(0.005)
    assert t.elapsed == frozen  # stopped on exit
    with pytest.raises(RuntimeError):
        Timer().stop()
