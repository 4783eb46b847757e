"""Actions checked against the env's action space, for each space kind (Box, Discrete, MultiDiscrete,
Dict, Tuple): ``env.action_space.sample()`` steps; a wrong shape, a wrong dtype, NaN or a discrete
action out of range is refused in one line that says what was given and what is allowed.

Oracles: Gymnasium's batched spaces (what ``env.action_space.sample()`` returns) and the showcase's
action table (Discrete(3): 1 full force backwards, 2 forwards; the force lands in the cart's effort target).
"""

from __future__ import annotations

from types import SimpleNamespace

import gymnasium as gym
import numpy as np
import pytest
import torch
from conftest import cuda_available
from test_graph_contract import _Sim, emulated_cuda_graph  # noqa: F401 (a fixture)

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs.utils.cuda_graph import EnvStepper
from simlab.envs.utils.spaces import ActionValueCheck, check_action
from simlab.tasks.direct.cartpole_showcase.cartpole.cartpole_env import CartpoleShowcaseEnv
from simlab.tasks.utils.parse_cfg import parse_env_cfg

N = 4
INF = float("inf")


def _showcase(action_kind: str):
    task = f"simlab/Cartpole-Showcase-Box-{action_kind}-Direct-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=N)).unwrapped
    env.reset(seed=0)
    return env


def _refused(env, action, pattern: str) -> str:
    """The one-line message ``env.step(action)`` is refused with."""
    with pytest.raises(ValueError, match=pattern) as info:
        env.step(action)
    assert "\n" not in str(info.value), str(info.value)
    return str(info.value)


def _cart_force(env) -> list[float]:
    return env.cartpole.data.joint_effort_target[:, env._cart_dof_idx[0]].tolist()


@pytest.mark.parametrize(("kind", "sample_shape"), [("Box", (N, 1)), ("Discrete", (N,)), ("MultiDiscrete", (N, 2))])
def test_the_showcase_steps_with_what_its_action_space_samples_and_refuses_other_shapes(kind, sample_shape):
    env = _showcase(kind)
    try:
        sample = env.action_space.sample()
        assert sample.shape == sample_shape  # Gymnasium batches Discrete(3) as MultiDiscrete([3] * N)
        for _ in range(2):
            env.step(env.action_space.sample())
        expected = {"Box": r"\(4, 1\)", "Discrete": r"\(4, 1\) or \(4,\)", "MultiDiscrete": r"\(4, 2\)"}[kind]
        _refused(env, np.zeros((N, 3), dtype=sample.dtype), rf"must have shape {expected} .*got \(4, 3\)")
        _refused(env, np.zeros(N + 1, dtype=sample.dtype), r"got \(5,\)")
    finally:
        env.close()


def test_a_discrete_action_per_env_acts_as_the_column_skrl_passes():
    env = _showcase("Discrete")
    try:
        env.step(np.array([0, 1, 2, 1]))  # as env.action_space.sample() gives it
        assert env.actions.shape == (N, 1)
        assert _cart_force(env) == [0.0, -100.0, 100.0, -100.0]
        env.step(torch.tensor([[2], [2], [0], [1]]))  # (num_envs, 1), as skrl's categorical policy acts
        assert _cart_force(env) == [100.0, 100.0, 0.0, -100.0]
    finally:
        env.close()


def test_discrete_actions_out_of_range_or_not_integers_are_refused():
    env = _showcase("Discrete")
    try:
        message = _refused(env, np.array([0, 1, 3, 2]), r"outside Discrete\(3\) \(envs \[2\]\)")
        assert "allowed: integers 0 to 2" in message
        _refused(env, torch.tensor([0, -1, 0, 0]), r"envs \[1\]")
        _refused(env, torch.zeros(N), r"must hold integers \(integers 0 to 2\), got torch.float32")
    finally:
        env.close()
    env = _showcase("MultiDiscrete")
    try:
        message = _refused(env, np.array([[0, 1], [2, 1], [2, 2], [3, 0]]), r"outside MultiDiscrete\(\[3 2\]\)")
        assert "(envs [2, 3])" in message and "nvec [3, 2]" in message
    finally:
        env.close()


def test_nan_box_actions_are_refused_naming_the_envs():
    env = _showcase("Box")
    try:
        action = torch.zeros(N, 1)
        action[3] = float("nan")
        _refused(env, action, r"^Actions contain NaN or inf \(envs \[3\]\); actions must be finite$")
    finally:
        env.close()


# Dict and Tuple action spaces: the showcase's cartpole driven by a force and an on / off switch


class _SwitchedForceCartpole(CartpoleShowcaseEnv):
    def _pre_physics_step(self, actions) -> None:
        self.actions = actions

    def _apply_action(self) -> None:
        force, on = (self.actions["force"], self.actions["on"]) if isinstance(self.actions, dict) else self.actions
        self.cartpole.set_joint_effort_target(self.cfg.action_scale * force * on, joint_ids=self._cart_dof_idx)


def _switched(space: gym.spaces.Space) -> _SwitchedForceCartpole:
    cfg = parse_env_cfg("simlab/Cartpole-Showcase-Box-Box-Direct-v0", device="cpu", num_envs=N)
    cfg.action_space = space
    env = _SwitchedForceCartpole(cfg)
    env.reset(seed=0)
    return env


def test_dict_actions_step_as_the_space_samples_them_and_are_checked_per_key():
    env = _switched(gym.spaces.Dict({"force": gym.spaces.Box(-1.0, 1.0, (1,)), "on": gym.spaces.Discrete(2)}))
    try:
        sample = env.action_space.sample()
        assert sample["force"].shape == (N, 1) and sample["on"].shape == (N,)
        env.step(sample)
        env.step({"force": np.full((N, 1), 0.5, dtype=np.float32), "on": np.array([1, 0, 1, 0])})
        assert _cart_force(env) == [50.0, 0.0, 50.0, 0.0]
        _refused(
            env, {"force": np.zeros((N, 1))}, r"must be a dict with the keys \['force', 'on'\], got keys \['force'\]"
        )
        _refused(env, {"force": np.zeros((N, 2)), "on": np.zeros(N, int)}, r"^Actions\['force'\] .*got \(4, 2\)$")
        _refused(env, {"force": np.zeros((N, 1)), "on": np.array([0, 2, 0, 0])}, r"^Actions\['on'\] outside")
        _refused(env, np.zeros((N, 1)), r"must be a dict .*got a ndarray")
    finally:
        env.close()


def test_tuple_actions_step_as_the_space_samples_them_and_are_checked_per_item():
    env = _switched(gym.spaces.Tuple((gym.spaces.Box(-1.0, 1.0, (1,)), gym.spaces.MultiDiscrete([2]))))
    try:
        env.step(env.action_space.sample())
        env.step((np.full((N, 1), -1.0), np.array([[1], [1], [0], [1]])))
        assert _cart_force(env) == [-100.0, -100.0, 0.0, -100.0]
        _refused(env, (np.zeros((N, 1)),), r"must be a tuple of 2 actions, got 1 items")
        _refused(env, (np.zeros((N, 1)), np.zeros(N, int)), r"^Actions\[1\] for MultiDiscrete\(\[2\]\) .*got \(4,\)$")
        bad = np.zeros((N, 1))
        bad[0] = INF
        _refused(env, (bad, np.zeros((N, 1), int)), r"^Actions\[0\] contain NaN or inf \(envs \[0\]\)")
    finally:
        env.close()


def test_check_action_converts_to_the_spaces_dtypes():
    space = gym.spaces.Tuple((gym.spaces.Box(-1, 1, (2,)), gym.spaces.Discrete(5), gym.spaces.MultiDiscrete([2, 3])))
    box, discrete, multi = check_action(
        (np.zeros((3, 2), np.float64), np.arange(3, dtype=np.int32), torch.zeros(3, 2, dtype=torch.uint8)),
        space,
        3,
        "cpu",
    )
    assert (box.dtype, discrete.dtype, multi.dtype) == (torch.float32, torch.int64, torch.int64)
    assert discrete.tolist() == [[0], [1], [2]]


# the graphed step: out-of-range actions set a device flag, read at the periodic check


class _DiscreteToyEnv:
    device = "cpu"

    def __init__(self):
        self.sim = _Sim()
        self.cfg = SimpleNamespace(sim=SimpleNamespace(use_cuda_graph=True))  # the check is on by default
        self.total = torch.zeros(N)

    def graph_blockers(self) -> list[str]:
        return []

    def _step_body(self, action):
        self.total.add_(action[:, 0].float())
        return {"policy": self.total.clone()[:, None]}, self.total.clone()


def test_a_graphed_step_reports_out_of_range_actions_at_its_periodic_check_without_host_reads(
    emulated_cuda_graph,  # noqa: F811
    monkeypatch,
):
    env = _DiscreteToyEnv()
    stepper = EnvStepper(env, env._step_body, warmup=1, check_interval=4, action_space=gym.spaces.Discrete(3))
    good = torch.tensor([[0], [1], [2], [1]])
    for _ in range(2):  # the warm-up call and the capture
        stepper(good)
    assert stepper.is_graphed
    reads = []
    for name in ("__bool__", "item", "tolist"):
        original = getattr(torch.Tensor, name)
        monkeypatch.setattr(torch.Tensor, name, lambda self, *a, _o=original, _n=name: reads.append(_n) or _o(self, *a))
    stepper(torch.tensor([[0], [5], [0], [0]]))  # step 3: flagged on the device, nothing read back
    assert reads == []
    with pytest.raises(ValueError, match=r"a discrete action out of range, in a step among the last 4") as info:
        stepper(good)  # step 4: the periodic check
    assert "Discrete(3): integers 0 to 2" in str(info.value) and "\n" not in str(info.value)


def test_the_value_check_without_a_space_looks_for_nan_only():
    check = ActionValueCheck(None, "cpu")
    assert not bool(check.any_outside({"a": torch.zeros(2, 1), "b": torch.tensor([[7]])}))
    assert bool(check.any_outside({"a": torch.tensor([[0.0], [INF]])}))
    with pytest.raises(ValueError, match=r"Actions\['a'\] contain NaN or inf \(envs \[1\]\)"):
        check.raise_if_outside({"a": torch.tensor([[0.0], [INF]])})


@pytest.mark.parametrize("kind", ["Discrete", "MultiDiscrete"])
def test_simlab_zero_and_random_step_the_discrete_showcase(tmp_path, capsys, kind):
    from simlab.cli.main import main

    task = ["--task", f"simlab/Cartpole-Showcase-Box-{kind}-Direct-v0", "--num_envs", "2", "--headless"]
    for command in ("zero", "random"):
        assert main([command, *task, "--device", "cpu", "--steps", "3", "--log_root", str(tmp_path)]) == 0
        assert "[simlab] 3 steps done" in capsys.readouterr().out


@pytest.mark.gpu
@pytest.mark.skipif(not cuda_available(), reason="needs a CUDA device and MuJoCo Warp")
def test_the_graphed_discrete_showcase_steps_with_sampled_actions_and_reports_out_of_range_ones():
    task = "simlab/Cartpole-Showcase-Box-Discrete-Direct-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cuda:0", num_envs=256)).unwrapped
    try:
        env.reset(seed=0)
        for _ in range(4):  # warm-up steps and the capture
            env.step(env.action_space.sample())
        assert env.step_is_graphed, env._stepper.eager_reason
        env._stepper.check_interval = 2
        bad = np.zeros(256, dtype=np.int64)
        bad[7] = 3
        with pytest.raises(ValueError, match=r"a discrete action out of range.*Discrete\(3\): integers 0 to 2"):
            for _ in range(2):
                env.step(bad)
    finally:
        env.close()
