"""configclass: fields, copies, MISSING, replace/copy/to_dict/from_dict/validate, yaml round trip."""

from __future__ import annotations

import copy
import dataclasses
import os
import pickle
from typing import ClassVar

import pytest
import torch

from simlab.utils import configclass
from simlab.utils.configclass import MISSING, MissingFieldError
from simlab.utils.io import dump_yaml, load_yaml


def joint_pos(env, scale: float = 1.0):
    return scale


def joint_vel(env):
    return 0.0


class DummyActuator:
    pass


class OtherActuator:
    pass


@configclass
class ActuatorCfg:
    class_type: type = DummyActuator
    joint_names_expr: list[str] = MISSING
    stiffness = 10.0


@configclass
class RobotCfg:
    prim_path: str = MISSING
    init_pos = (0.0, 0.0, 1.0)
    joint_names = [".*"]
    actuators: dict = {"legs": ActuatorCfg(joint_names_expr=[".*_hip"])}
    mass: float | None = None


@configclass
class TermCfg:
    func = joint_pos
    params = {"scale": 1.0}
    weight: float = 1.0


@configclass
class RewardsCfg:
    alive = TermCfg(weight=2.0)
    vel = TermCfg(func=joint_vel, weight=-0.1)


@configclass
class SceneCfg:
    num_envs: int = MISSING
    env_spacing = 2.0
    robot = RobotCfg()


@configclass
class EnvCfg:
    scene: SceneCfg = SceneCfg(num_envs=4)
    rewards = RewardsCfg()
    decimation = 2
    dt = 0.01
    step_dt: float = 0.0

    def __post_init__(self):
        self.step_dt = self.dt * self.decimation

    def helper(self) -> int:
        return 7


# -- fields ----------------------------------------------------------------------------------------


def test_unannotated_attributes_are_fields_in_written_order():
    names = [f.name for f in dataclasses.fields(EnvCfg)]
    assert names == ["scene", "rewards", "decimation", "dt", "step_dt"]
    assert [f.name for f in dataclasses.fields(RewardsCfg)] == ["alive", "vel"]
    assert "helper" not in names and EnvCfg().helper() == 7


def test_constructor_accepts_unannotated_fields():
    cfg = SceneCfg(num_envs=8, env_spacing=3.0)
    assert cfg.num_envs == 8 and cfg.env_spacing == 3.0


def test_nested_class_definition_is_not_a_field():
    @configclass
    class ObsCfg:
        @configclass
        class PolicyCfg:
            enable_corruption = False

        policy: PolicyCfg = PolicyCfg()

    assert [f.name for f in dataclasses.fields(ObsCfg)] == ["policy"]
    assert ObsCfg().policy.enable_corruption is False


def test_mutable_defaults_are_copied_per_instance():
    a, b = EnvCfg(), EnvCfg()
    a.scene.robot.joint_names.append("extra")
    a.scene.robot.actuators["legs"].stiffness = 99.0
    a.rewards.alive.params["scale"] = 5.0
    assert b.scene.robot.joint_names == [".*"]
    assert b.scene.robot.actuators["legs"].stiffness == 10.0
    assert b.rewards.alive.params == {"scale": 1.0}
    assert a.scene is not b.scene


def test_tensor_default_is_copied():
    @configclass
    class C:
        offset = torch.zeros(3)

    a, b = C(), C()
    a.offset += 1
    assert torch.equal(b.offset, torch.zeros(3))


def test_callables_and_classes_kept_as_values():
    cfg = EnvCfg()
    assert cfg.rewards.alive.func is joint_pos
    assert cfg.rewards.vel.func is joint_vel
    assert cfg.scene.robot.actuators["legs"].class_type is DummyActuator


def test_lambda_default_is_a_field():
    @configclass
    class C:
        fn = lambda x: x + 1  # noqa: E731

    assert [f.name for f in dataclasses.fields(C)] == ["fn"]
    assert C().fn(1) == 2


# -- MISSING / validate ----------------------------------------------------------------------------


def test_missing_fields_do_not_block_construction():
    cfg = RobotCfg()
    assert cfg.prim_path is MISSING


def test_a_field_needs_a_default_and_missing_needs_a_type():
    # Isaac Lab's rules: a required field is written `x: int = MISSING`
    with pytest.raises(ValueError, match="Missing default value for 'x' in class 'C'.*= MISSING"):

        @configclass
        class C:
            x: int

    with pytest.raises(TypeError, match="Missing type annotation for 'y' in class 'D'"):

        @configclass
        class D:
            y = MISSING

    @configclass
    class E:
        x: int = MISSING
        kind = dict  # an unannotated class value is a field of type type[dict]

    assert E().x is MISSING and E(x=3).x == 3
    assert E.__annotations__["kind"] == type[dict] and E().kind is dict


def test_validate_lists_every_missing_field_by_path():
    cfg = EnvCfg()
    cfg.scene.num_envs = MISSING
    cfg.scene.robot.actuators["arm"] = ActuatorCfg()
    with pytest.raises(MissingFieldError) as err:
        cfg.validate()
    msg = str(err.value)
    for path in ["scene.num_envs", "scene.robot.prim_path", "scene.robot.actuators.arm.joint_names_expr"]:
        assert path in msg
    assert "actuators.legs" not in msg  # legs has its joint names
    assert isinstance(err.value, TypeError) and isinstance(err.value, ValueError)


def test_validate_recurses_into_lists():
    @configclass
    class C:
        items = [ActuatorCfg(joint_names_expr=["a"]), ActuatorCfg()]

    with pytest.raises(TypeError, match=r"items\[1\]\.joint_names_expr"):
        C().validate()


def test_validate_passes_when_complete():
    cfg = EnvCfg()
    cfg.scene.robot.prim_path = "/World/envs/env_.*/Robot"
    cfg.validate()  # no error


def test_missing_survives_copy_and_pickle():
    cfg = RobotCfg()
    assert copy.deepcopy(cfg).prim_path is MISSING
    assert pickle.loads(pickle.dumps(cfg)).prim_path is MISSING
    assert EnvCfg().scene.robot.prim_path is MISSING  # default built by deep copy


# -- post_init and inheritance ---------------------------------------------------------------------


def test_post_init_runs():
    assert EnvCfg().step_dt == pytest.approx(0.02)
    assert EnvCfg(decimation=4).step_dt == pytest.approx(0.04)


def test_subclass_overrides_parent_defaults():
    @configclass
    class MyEnvCfg(EnvCfg):
        decimation = 5  # no annotation: still overrides the inherited field
        scene: SceneCfg = SceneCfg(num_envs=64)
        extra = "hello"

    cfg = MyEnvCfg()
    assert cfg.decimation == 5 and cfg.scene.num_envs == 64 and cfg.extra == "hello"
    assert cfg.step_dt == pytest.approx(0.05)  # parent's __post_init__ sees the new default
    assert [f.name for f in dataclasses.fields(MyEnvCfg)][:5] == [
        "scene",
        "rewards",
        "decimation",
        "dt",
        "step_dt",
    ]
    assert EnvCfg().decimation == 2  # parent untouched


def test_subclass_overrides_class_type_without_annotation():
    @configclass
    class OtherActuatorCfg(ActuatorCfg):
        class_type = OtherActuator

    assert OtherActuatorCfg().class_type is OtherActuator
    assert ActuatorCfg().class_type is DummyActuator


def test_subclass_post_init_calls_parent():
    @configclass
    class Child(EnvCfg):
        def __post_init__(self):
            super().__post_init__()
            self.dt = 0.5

    cfg = Child()
    assert cfg.dt == 0.5 and cfg.step_dt == pytest.approx(0.02)


# -- replace / copy --------------------------------------------------------------------------------


def test_replace_returns_independent_copy():
    cfg = SceneCfg(num_envs=4)
    new = cfg.replace(num_envs=16)
    assert new.num_envs == 16 and cfg.num_envs == 4
    new.robot.joint_names.append("x")
    assert cfg.robot.joint_names == [".*"]


def test_replace_reruns_post_init():
    assert EnvCfg().replace(decimation=10).step_dt == pytest.approx(0.1)


def test_replace_unknown_field_names_valid_ones():
    with pytest.raises(TypeError, match=r"num_env.*num_envs.*Valid fields"):
        SceneCfg().replace(num_env=3)


def test_copy_is_deep():
    cfg = EnvCfg()
    c = cfg.copy()
    c.scene.robot.actuators["legs"].stiffness = 1.0
    assert cfg.scene.robot.actuators["legs"].stiffness == 10.0
    assert c == c.copy()


# -- to_dict / from_dict ---------------------------------------------------------------------------


def test_to_dict_converts_recursively():
    d = EnvCfg().to_dict()
    assert d["scene"]["num_envs"] == 4
    assert d["scene"]["robot"]["init_pos"] == (0.0, 0.0, 1.0)  # tuples stay tuples, as in Isaac Lab
    assert d["rewards"]["alive"]["func"] == f"{__name__}:joint_pos"
    assert d["scene"]["robot"]["actuators"]["legs"]["class_type"] == f"{__name__}:DummyActuator"
    assert isinstance(d["scene"]["robot"]["actuators"]["legs"], dict)


def test_from_dict_updates_nested_in_place():
    cfg = EnvCfg()
    robot = cfg.scene.robot
    cfg.from_dict({"scene": {"num_envs": 32, "robot": {"init_pos": [1, 2, 3]}}, "decimation": 3})
    assert cfg.scene.num_envs == 32 and cfg.decimation == 3
    assert cfg.scene.robot is robot  # updated, not replaced
    assert cfg.scene.robot.init_pos == (1, 2, 3) and isinstance(cfg.scene.robot.init_pos, tuple)
    assert cfg.scene.env_spacing == 2.0  # untouched


def test_from_dict_resolves_callable_strings():
    cfg = EnvCfg()
    cfg.from_dict({"rewards": {"alive": {"func": f"{__name__}:joint_vel"}}})
    assert cfg.rewards.alive.func is joint_vel
    cfg.from_dict({"scene": {"robot": {"actuators": {"legs": {"class_type": f"{__name__}:OtherActuator"}}}}})
    assert cfg.scene.robot.actuators["legs"].class_type is OtherActuator


def test_from_dict_bad_callable_string_errors():
    with pytest.raises(ValueError, match="no attribute 'not_a_function'"):
        EnvCfg().from_dict({"rewards": {"alive": {"func": f"{__name__}:not_a_function"}}})


def test_from_dict_none_removes_term():
    cfg = EnvCfg()
    cfg.from_dict({"rewards": {"vel": None}})
    assert cfg.rewards.vel is None


def test_from_dict_unknown_key_suggests_closest():
    cfg = EnvCfg()
    with pytest.raises(KeyError) as err:
        cfg.from_dict({"scene": {"num_env": 3}})
    msg = str(err.value)
    assert "scene.num_env" in msg and "Did you mean 'num_envs'" in msg and "env_spacing" in msg


def test_from_dict_rejects_scalar_for_nested_config():
    with pytest.raises(ValueError, match="scene"):
        EnvCfg().from_dict({"scene": 3})


def test_from_dict_rebuilds_removed_term():
    cfg = EnvCfg()
    cfg.rewards.vel = None
    cfg.from_dict({"rewards": {"vel": {"weight": -0.5}}})
    assert isinstance(cfg.rewards.vel, TermCfg) and cfg.rewards.vel.weight == -0.5


# -- yaml round trip -------------------------------------------------------------------------------


def test_yaml_round_trip(tmp_path):
    cfg = EnvCfg()
    cfg.scene.num_envs = 128
    cfg.scene.robot.init_pos = (0.1, 0.2, 0.3)
    cfg.rewards.alive.func = joint_vel
    cfg.scene.robot.actuators["legs"].class_type = OtherActuator
    path = os.path.join(tmp_path, "params", "env.yaml")
    dump_yaml(path, cfg)

    cfg2 = EnvCfg()
    cfg2.from_dict(load_yaml(path))
    assert cfg2.to_dict() == cfg.to_dict()
    assert cfg2.rewards.alive.func is joint_vel
    assert cfg2.scene.robot.actuators["legs"].class_type is OtherActuator
    assert cfg2.scene.robot.init_pos == (0.1, 0.2, 0.3)
    assert cfg2.scene.robot.prim_path is MISSING  # written as "???", read back as MISSING


def test_decorator_with_arguments():
    @configclass(frozen=True)
    class Frozen:
        x = 1

    with pytest.raises(dataclasses.FrozenInstanceError):
        Frozen().x = 2


def test_decorating_a_non_class_errors():
    with pytest.raises(TypeError, match="decorates a class"):
        configclass(joint_pos)


def test_classvar_property_and_static_members_are_not_fields():
    @configclass
    class C:
        registry: ClassVar[dict] = {}
        items: list = dataclasses.field(default_factory=list)
        required: int = dataclasses.field()

        @property
        def twice(self) -> int:
            return 2 * self.required

        @staticmethod
        def helper() -> int:
            return 1

    assert [f.name for f in dataclasses.fields(C)] == ["items", "required"]
    assert C().required is MISSING and C(required=2).twice == 4 and C.helper() == 1


def test_to_dict_keeps_tuples_tensors_and_post_init_members():
    import torch

    @configclass
    class C:
        eye: tuple = (1.0, 2.0, 3.0)
        look: list = [0.0, 0.0, 0.0]
        gains: torch.Tensor = torch.tensor([1.0, 2.0])

        def __post_init__(self):
            self.derived = 2 * self.eye[0]

    cfg = C()
    d = cfg.to_dict()
    assert d["eye"] == (1.0, 2.0, 3.0) and d["look"] == [0.0, 0.0, 0.0] and d["derived"] == 2.0
    assert isinstance(d["gains"], torch.Tensor) and d["gains"].tolist() == [1.0, 2.0]
    cfg.from_dict({"eye": [4.0, 5.0, 6.0], "look": (1.0, 1.0, 1.0)})
    assert cfg.eye == (4.0, 5.0, 6.0), "a tuple member stays a tuple"
    assert cfg.look == (1.0, 1.0, 1.0), "a given tuple is kept as given (Isaac Lab's)"
