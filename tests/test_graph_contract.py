"""The CUDA graph's contract: a step that rebinds tensors (Isaac Lab's idiom) replays like eager code.

On the CPU: :class:`TensorSlots` finds and writes back rebound tensors anywhere under the env
(attributes, dict entries, lists, tuples; swaps), names the slot it cannot replay; a real env's walk
reaches the class-based reward term and the command term; and the env stepper's real capture path,
run with an emulated CUDA graph (replays the recorded torch ops at the recorded tensors), gives the
eager results with the write-back and stale ones without it. On the GPU: a manager-based cartpole
with an Isaac Lab-style reward term and command term, graphed and eager, step for step.
"""

from __future__ import annotations

import contextlib
from types import SimpleNamespace

import gymnasium as gym
import pytest
import torch
from conftest import cuda_available
from torch.utils._python_dispatch import TorchDispatchMode

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs import ManagerBasedRLEnv
from simlab.envs.mdp import generated_commands
from simlab.envs.utils.cuda_graph import EnvStepper
from simlab.envs.utils.tensor_slots import GraphContractError, TensorSlots
from simlab.managers import CommandTerm, CommandTermCfg, ManagerTermBase
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg
from simlab.tasks.utils import parse_env_cfg
from simlab.utils import configclass
from simlab.utils.env_mask import masked_copy_

gpu = pytest.mark.skipif(not cuda_available(), reason="needs an NVIDIA GPU and mujoco-warp")


# -- TensorSlots on a plain object graph ----------------------------------------------------------


def test_write_back_copies_rebound_tensors_into_the_old_ones_wherever_they_sit():
    term = SimpleNamespace(metrics={"error": torch.zeros(3)}, buf=torch.zeros(3), pair=(torch.zeros(2), 1.0))
    root = SimpleNamespace(manager=SimpleNamespace(terms=[term]), logs={"a": torch.zeros(1)})
    old = {"error": term.metrics["error"], "buf": term.buf, "pair": term.pair[0], "a": root.logs["a"]}
    slots = TensorSlots(root, "env")
    term.metrics["error"] = torch.full((3,), 2.0)  # Isaac Lab's idiom
    term.buf = term.buf + 1.0
    term.pair = (torch.ones(2), 1.0)  # a rebuilt tuple
    root.logs = {"a": torch.full((1,), 5.0)}  # a rebuilt dict
    paths = {path for path, _, _ in slots.rebound()}
    assert paths == {
        "env.manager.terms[0].metrics['error']",
        "env.manager.terms[0].buf",
        "env.manager.terms[0].pair",
        "env.logs",
    }
    assert slots.write_back("cpu") == 4
    assert term.metrics["error"] is old["error"] and torch.equal(old["error"], torch.full((3,), 2.0))
    assert term.buf is old["buf"] and torch.equal(old["buf"], torch.ones(3))
    assert term.pair[0] is old["pair"] and torch.equal(old["pair"], torch.ones(2))
    assert root.logs["a"] is old["a"] and float(old["a"]) == 5.0


def test_write_back_leaves_the_dict_the_step_was_given_as_it_was():
    """A multi-agent task keeps its actions dict (``self.actions = actions``, Isaac Lab's cart double
    pendulum): that dict is the stepper's static input, which each replay refills, so the write-back
    must not swap the old tensors into it."""
    env = SimpleNamespace(actions={"cart": torch.zeros(2), "pendulum": torch.zeros(2)})
    old = dict(env.actions)
    static = {"cart": torch.ones(2), "pendulum": torch.full((2,), 2.0)}
    given = dict(static)
    slots = TensorSlots(env, "env")
    env.actions = static  # the step keeps the dict it was given
    assert slots.write_back("cpu") == 2
    assert all(static[agent] is given[agent] for agent in given)  # still the tensors the graph reads
    assert all(env.actions[agent] is old[agent] for agent in old)
    assert torch.equal(old["pendulum"], torch.full((2,), 2.0))


def test_write_back_reads_swapped_tensors_before_writing_any():
    """``prev = cur; cur = new``: the old ``cur`` is both a source and a target."""
    state = SimpleNamespace(prev=torch.zeros(2), cur=torch.ones(2))
    prev, cur = state.prev, state.cur
    slots = TensorSlots(state, "env")
    state.prev, state.cur = state.cur, torch.full((2,), 7.0)
    slots.write_back("cpu")
    assert state.prev is prev and state.cur is cur
    assert torch.equal(prev, torch.ones(2)) and torch.equal(cur, torch.full((2,), 7.0))


def test_a_rebinding_that_cannot_replay_names_its_slot_and_restore_undoes_the_step():
    term = SimpleNamespace(metrics={"error": torch.zeros(4)})
    root = SimpleNamespace(command_manager=SimpleNamespace(_terms={"pose": term}))
    before = term.metrics["error"]
    slots = TensorSlots(root, "env")
    term.metrics["error"] = torch.zeros(4, 2)
    with pytest.raises(GraphContractError, match=r"env.command_manager._terms\['pose'\].metrics\['error'\]"):
        slots.write_back("cpu")
    slots.restore()
    assert term.metrics["error"] is before
    term.metrics["error"] = torch.zeros(1).expand(4)  # one element seen four times: cannot be refilled
    slots = TensorSlots(root, "env")
    term.metrics["error"] = torch.ones(4)
    with pytest.raises(GraphContractError, match=r"\['error'\], and its old tensor cannot be refilled"):
        slots.write_back("cpu")
    slots.restore()
    term.metrics["error"] = torch.ones(4)  # made on another device than the step's: not replayed
    with pytest.raises(GraphContractError, match=r"\['error'\] to a tensor on cpu.*the graph replays work on meta"):
        slots.write_back("meta")


# -- a real env: the walk reaches every object the step touches ------------------------------------


class SmoothedPoleReward(ManagerTermBase):
    """A class-based reward term written Isaac Lab's way: it rebinds its tensors every step."""

    def __init__(self, cfg, env):
        super().__init__(cfg, env)
        self.metrics = {"pole_error": torch.zeros(env.num_envs, device=env.device)}
        self._smoothed = torch.zeros(env.num_envs, device=env.device)

    def reset(self, env_ids=None):
        masked_copy_(self._smoothed, env_ids, 0.0)

    def __call__(self, env):
        target = env.command_manager.get_command("target")[:, 0]
        error = (env.scene["robot"].data.joint_pos[:, 0] - target).abs()
        self.metrics["pole_error"] = error  # rebinds a dict entry
        self._smoothed = 0.8 * self._smoothed + 0.2 * error  # reads the old tensor, then rebinds
        return -self._smoothed


class DriftingTargetCommand(CommandTerm):
    """A command term written Isaac Lab's way: it rebinds its command and metrics every step."""

    resamples_by_mask = True

    def __init__(self, cfg, env):
        super().__init__(cfg, env)
        self.target = torch.zeros(self.num_envs, 1, device=self.device)
        self.metrics["error"] = torch.zeros(self.num_envs, device=self.device)

    @property
    def command(self) -> torch.Tensor:
        return self.target

    def _resample_command(self, mask):
        draw = torch.empty_like(self.target).uniform_(-0.5, 0.5)
        self.target = torch.where(mask[:, None], draw, self.target)

    def _update_command(self):
        self.target = self.target * 0.98 + 0.01

    def _update_metrics(self):
        cart = self._env.scene["robot"].data.joint_pos[:, :1]
        self.metrics["error"] = torch.norm(cart - self.target, dim=-1)


@configclass
class TargetCommandsCfg:
    target = CommandTermCfg(class_type=DriftingTargetCommand, resampling_time_range=(0.3, 0.6))


def isaac_style_cartpole(device: str, num_envs: int, use_cuda_graph: bool = True) -> ManagerBasedRLEnv:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = device
    cfg.sim.use_cuda_graph = use_cuda_graph
    cfg.seed = 3
    cfg.episode_length_s = 1.0  # episodes end within the rollouts: the comparison crosses resets
    cfg.commands = TargetCommandsCfg()
    cfg.rewards.smoothed_pole = RewTerm(func=SmoothedPoleReward, weight=1.0)
    cfg.observations.policy.target = ObsTerm(func=generated_commands, params={"command_name": "target"})
    return ManagerBasedRLEnv(cfg)


def test_the_walk_finds_what_isaac_lab_style_terms_rebind_in_a_real_env():
    env = isaac_style_cartpole("cpu", 8)
    env.reset(seed=1)
    actions = torch.zeros(8, 1)
    env.step(actions)
    slots = TensorSlots(env, "env", skip=(env._stepper,))
    env.step(actions)
    paths = {path for path, _, _ in slots.rebound()}
    assert "env.command_manager._terms['target'].target" in paths
    assert "env.command_manager._terms['target'].metrics['error']" in paths
    reward_terms = [p for p in paths if p.startswith("env.reward_manager.") and p.endswith("._smoothed")]
    assert reward_terms and any(p.endswith(".metrics['pole_error']") for p in paths), paths
    env.close()


# -- the stepper's capture path with an emulated CUDA graph (CPU) ------------------------------------


class _RecordingGraph(TorchDispatchMode):
    """A CPU stand-in for ``torch.cuda.CUDAGraph``: capture records each torch op with its tensors;
    replay runs them again on the same tensors, writing each result into the tensor recorded then
    (as a graph's kernels write fixed addresses). As on a GPU, capture leaves the tensors that existed
    before it unchanged, and a read back to the host or a tensor made from host data (a copy from
    pageable memory on a GPU: ``torch.tensor(list, device=...)``) fails it. The stepper captures
    under ``DeviceListIndices``, so list indices and indexed writes of numbers make none."""

    def __init__(self):
        super().__init__()
        self.ops: list[tuple] = []
        self._undo: list[tuple[torch.Tensor, torch.Tensor]] = []
        self._made: set[int] = set()

    def __torch_dispatch__(self, func, types, args=(), kwargs=None):
        kwargs = kwargs or {}
        if func.__name__.startswith(("_local_scalar_dense", "nonzero", "is_nonzero")):
            raise RuntimeError(f"{func.__name__}: operation not permitted when stream is capturing")
        if func.__name__.startswith("lift_fresh"):  # a tensor made from Python data: on a GPU a pageable copy
            raise RuntimeError(f"{func.__name__}: Cannot copy between CPU and CUDA tensors during CUDA graph capture")
        schema = func._schema
        given = {**{a.name: v for a, v in zip(schema.arguments, args)}, **kwargs}
        for arg in schema.arguments:
            value = given.get(arg.name)
            written = arg.alias_info is not None and arg.alias_info.is_write
            if written and isinstance(value, torch.Tensor) and value.untyped_storage().data_ptr() not in self._made:
                self._undo.append((value, value.clone()))
        out = func(*args, **kwargs)
        outs = out if isinstance(out, (tuple, list)) else (out,)
        fresh = [r.alias_info is None for r in schema.returns]
        for tensor, is_fresh in zip(outs, fresh):
            if isinstance(tensor, torch.Tensor) and is_fresh:
                self._made.add(tensor.untyped_storage().data_ptr())
        self.ops.append((func, args, kwargs, outs, fresh))
        return out

    def end_capture(self) -> None:
        for tensor, value in reversed(self._undo):  # a capture runs nothing
            tensor.copy_(value)

    def replay(self) -> None:
        for func, args, kwargs, outs, fresh in self.ops:
            out = func(*args, **kwargs)
            for target, result, is_fresh in zip(outs, out if isinstance(out, (tuple, list)) else (out,), fresh):
                if is_fresh and isinstance(target, torch.Tensor):
                    target.copy_(result)


@contextlib.contextmanager
def _capture(graph: _RecordingGraph, **_):
    with graph:
        yield
    graph.end_capture()


@pytest.fixture
def emulated_cuda_graph(monkeypatch):
    monkeypatch.setattr(torch.cuda, "CUDAGraph", _RecordingGraph)
    monkeypatch.setattr(torch.cuda, "graph", _capture)
    monkeypatch.setattr(torch.cuda, "synchronize", lambda *a: None)
    generator = SimpleNamespace(clone_state=torch.get_rng_state, graphsafe_set_state=torch.set_rng_state)
    monkeypatch.setattr(torch.cuda, "default_generators", (generator,))


class _Sim:
    can_capture_steps = True
    has_step_callbacks = False
    on_divergence = "reset"

    def __init__(self):
        noop = lambda *a: None  # noqa: E731
        self.physics = SimpleNamespace(
            before_capture=noop, before_replay=noop, check_overflow=noop, diverged_count=torch.zeros(())
        )


class ToyEnv:
    """An env-shaped object whose step is torch ops only, written Isaac Lab's way: a point mass
    (asset data rebound each step), a command term and a class-based reward term that rebind."""

    device = "cpu"

    def __init__(self, n: int = 4):
        self.sim = _Sim()
        self.cfg = SimpleNamespace(sim=SimpleNamespace(use_cuda_graph=True), check_finite_actions=True)
        data = SimpleNamespace(pos=torch.zeros(n, 2), vel=torch.zeros(n, 2))
        self.scene = SimpleNamespace(articulations={"robot": SimpleNamespace(data=data)})
        command = SimpleNamespace(target=torch.ones(n, 2), metrics={"error": torch.zeros(n)})
        reward = SimpleNamespace(smoothed=torch.zeros(n), metrics={})
        self.command_manager = SimpleNamespace(_terms={"target": command})
        self.reward_manager = SimpleNamespace(_class_terms=[reward])
        self.prev_action, self.action = torch.zeros(n, 2), torch.zeros(n, 2)

    def graph_blockers(self) -> list[str]:
        return []

    def _step_body(self, action):
        self.prev_action, self.action = self.action, action.clone()  # a swap through the old tensor
        data = self.scene.articulations["robot"].data
        data.vel.add_(0.1 * self.action - 0.05 * self.prev_action)  # in place
        data.pos = data.pos + 0.1 * data.vel  # rebinds after reading
        command = self.command_manager._terms["target"]
        command.metrics["error"] = torch.norm(data.pos - command.target, dim=-1)
        command.target = command.target * 0.9 + 0.05 * data.pos
        reward = self.reward_manager._class_terms[0]
        reward.smoothed = 0.5 * reward.smoothed + command.metrics["error"]
        reward.metrics["smoothed"] = reward.smoothed
        return {"policy": torch.cat([data.pos, command.target], dim=-1)}, -reward.smoothed, command.metrics["error"]


def _toy_rollout(graphed: bool, steps: int = 8) -> list[torch.Tensor]:
    env = ToyEnv()
    env.cfg.sim.use_cuda_graph = graphed
    if not graphed:
        env.sim.can_capture_steps = False
    stepper = EnvStepper(env, env._step_body, warmup=2)
    outputs = []
    for i in range(steps):
        obs, reward, _ = stepper(torch.full((4, 2), 0.1 * (i + 1)))
        outputs.append(torch.cat([obs["policy"].flatten(), reward]))
    outputs.append(env.command_manager._terms["target"].metrics["error"].clone())
    assert stepper.is_graphed == graphed, stepper.mode
    return outputs


def graphed_allegro_env():
    """A 4-env direct Allegro env on the CPU whose step is captured (emulated graph: use with the
    ``emulated_cuda_graph`` fixture) after two warm-up steps, as on a GPU."""
    from simlab.tasks.direct.allegro_hand.allegro_hand_env_cfg import AllegroHandEnvCfg
    from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import InHandManipulationEnv

    cfg = AllegroHandEnvCfg()
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = 4, "cpu", 1
    env = InHandManipulationEnv(cfg)
    env.sim.physics.forwards_all_worlds = True  # a masked reset then marks worlds stale without a host read
    env._stepper.eager_reason = None  # capture as on a GPU (the physics itself is not replayed here)
    env.reset()
    for _ in range(3):  # two warm-up steps and the capture
        env.step(torch.zeros(4, 16))
    assert env.step_is_graphed, env.step_mode
    return env


def test_graphed_steps_that_rebind_tensors_agree_with_eager_ones(emulated_cuda_graph):
    eager, graphed = _toy_rollout(graphed=False), _toy_rollout(graphed=True)
    for i, (a, b) in enumerate(zip(graphed, eager)):
        torch.testing.assert_close(a, b, msg=lambda m, i=i: f"step {i}: {m}")


def test_what_the_warm_up_steps_returned_is_not_refilled_by_the_replays(emulated_cuda_graph):
    """The env holds the tensors its step returns (here a metric): the write-back refills those, so
    warm-up steps must return copies, as replays do."""
    env = ToyEnv()
    stepper = EnvStepper(env, env._step_body, warmup=2)
    kept = [stepper(torch.full((4, 2), 0.5)) for _ in range(2)]
    values = [error.clone() for *_, error in kept]
    for _ in range(3):
        stepper(torch.full((4, 2), -0.5))
    assert stepper.is_graphed
    for (*_, error), value in zip(kept, values):
        assert torch.equal(error, value)


def _toy_rollout_with_a_reset_between_replays(graphed: bool) -> tuple[list[torch.Tensor], ToyEnv, EnvStepper]:
    """Six steps; before the fifth (a replay, graphed) eager code rebinds what the step rebinds, as an
    env's ``reset()`` does (its observation code rebinds the same names the step's does)."""
    env = ToyEnv()
    env.cfg.sim.use_cuda_graph = graphed
    if not graphed:
        env.sim.can_capture_steps = False
    stepper = EnvStepper(env, env._step_body, warmup=1)
    outputs = []
    for i in range(6):
        if i == 4:
            env.scene.articulations["robot"].data.pos = torch.full((4, 2), 3.0)
            env.command_manager._terms["target"].metrics["error"] = torch.zeros(4)
        obs, reward, _ = stepper(torch.full((4, 2), 0.1 * (i + 1)))
        outputs.append(torch.cat([obs["policy"].flatten(), reward]))
    assert stepper.is_graphed == graphed, stepper.mode
    return outputs, env, stepper


def test_a_reset_between_replays_is_where_the_next_replay_starts(emulated_cuda_graph):
    """Eager code between replays (an env's ``reset()``: a checkpoint judge resets the running env for
    each checkpoint) rebinds slots the graph holds: the next replay starts from the values it wrote, and
    the slots point at the graph's tensors again, so readers see what the replays compute."""
    eager, _, _ = _toy_rollout_with_a_reset_between_replays(graphed=False)
    graphed, env, stepper = _toy_rollout_with_a_reset_between_replays(graphed=True)
    for i, (a, b) in enumerate(zip(graphed, eager)):
        torch.testing.assert_close(a, b, msg=lambda m, i=i: f"step {i}: {m}")
    held = {id(before) for _, _, before, _ in stepper._slots.slots}
    assert id(env.scene.articulations["robot"].data.pos) in held
    assert id(env.command_manager._terms["target"].metrics["error"]) in held


def test_the_stepper_holds_the_tensors_the_graph_writes_when_their_slots_are_rebound(emulated_cuda_graph):
    """A CUDA graph holds no tensor: once eager code rebinds a slot, the tensor the replays write into
    would be freed and handed out again by torch (a policy loaded next got its weights overwritten each
    step, and judged a checkpoint with inf rewards; issue 40). The stepper keeps them."""
    import gc
    import weakref

    env = ToyEnv()
    stepper = EnvStepper(env, env._step_body, warmup=1)
    for _ in range(2):  # the warm-up step and the capture
        stepper(torch.zeros(4, 2))
    assert stepper.is_graphed
    data = env.scene.articulations["robot"].data
    written = weakref.ref(data.pos)  # rebound by the step: each replay writes the step's positions there
    stepper.graph.ops.clear()  # the emulation's records hold tensors; a CUDA graph does not
    stepper.graph._undo.clear()
    data.pos = torch.zeros(4, 2)  # an eager reset
    gc.collect()
    assert written() is not None


def test_a_recapture_records_what_the_step_runs_now(emulated_cuda_graph):
    """``recapture()`` drops the graph: the next steps warm up and capture the step as its Python runs
    then (a benchmark that leaves the physics out changes it), and replay that."""
    env = ToyEnv()
    stepper = EnvStepper(env, env._step_body, warmup=1)
    for _ in range(3):
        stepper(torch.zeros(4, 2))
    first = stepper.graph
    body = env._step_body
    env._step_body = lambda action: body(2.0 * action)  # what the step runs, changed
    stepper.body = env._step_body
    stepper.recapture()
    assert not stepper.is_graphed and stepper.mode == "warming up"
    obs = [stepper(torch.full((4, 2), 0.5))[0]["policy"].clone() for _ in range(4)]
    assert stepper.is_graphed and stepper.graph is not first
    eager = ToyEnv()
    for _ in range(3):
        eager._step_body(torch.zeros(4, 2))
    eager_obs = [eager._step_body(torch.full((4, 2), 1.0))[0]["policy"].clone() for _ in range(4)]
    for a, b in zip(obs, eager_obs):  # the warm-up, the capture and the replay run the changed step
        torch.testing.assert_close(a, b)


def test_the_allegro_env_reset_between_replays_frees_nothing_the_graph_writes(emulated_cuda_graph):
    """Issue 40 end to end on the CPU: the direct Allegro task's step captured (the emulated graph), then
    ``env.reset()``, as the checkpoint judge does before each checkpoint (rsl_rl's env wrapper resets
    it). Every tensor the replays write into must stay alive: the reset's observation code rebinds some of
    them (the cube's per-state angular velocity; nine task attributes before the step wrote its own in
    place), which a CUDA graph (it holds no tensor) would go on writing after torch freed them."""
    import gc
    import weakref

    env = graphed_allegro_env()
    graph = env._stepper.graph
    made = graph._made  # storages the capture allocated (a CUDA graph's private pool keeps those)
    written = [
        weakref.ref(args[0])
        for func, args, *_ in graph.ops
        if func.__name__.startswith("copy_") and args[0].untyped_storage().data_ptr() not in made
    ]
    assert len(written) >= 5  # the actions, the joint targets, the per-state values' write-back
    graph.ops.clear()  # the emulation's records hold tensors; a CUDA graph does not
    graph._undo.clear()
    env.reset()
    gc.collect()
    assert all(ref() is not None for ref in written), "a tensor the replays write into was freed by env.reset()"
    env.close()


def test_without_the_write_back_the_replays_read_stale_tensors(emulated_cuda_graph, monkeypatch):
    """The emulation is faithful enough to show the bug the write-back fixes."""
    monkeypatch.setattr(TensorSlots, "write_back", lambda self, device: 0)
    eager, graphed = _toy_rollout(graphed=False), _toy_rollout(graphed=True)
    assert not all(torch.allclose(a, b) for a, b in zip(graphed, eager))


def test_a_rebinding_to_another_shape_keeps_the_step_eager_naming_the_slot(emulated_cuda_graph, capsys):
    env = ToyEnv()
    body = env._step_body

    calls = []

    def reshaping_body(action):  # a metric whose shape changes from step to step
        calls.append(1)
        out = body(action)
        env.reward_manager._class_terms[0].metrics["smoothed"] = torch.zeros(5 + len(calls) % 2)
        return out

    stepper = EnvStepper(env, reshaping_body, warmup=1)
    for _ in range(4):
        stepper(torch.zeros(4, 2))
    assert not stepper.is_graphed
    assert "env.reward_manager._class_terms[0].metrics['smoothed']" in stepper.eager_reason
    assert "stepping eagerly" in capsys.readouterr().out


def test_the_emulated_graph_fails_a_capture_that_reads_back(emulated_cuda_graph):
    env = ToyEnv()
    body = env._step_body
    stepper = EnvStepper(env, lambda a: body(a * float(a.abs().sum() >= 0)), warmup=1)  # a host read
    for _ in range(3):
        stepper(torch.zeros(4, 2))
    assert not stepper.is_graphed and "not permitted when stream is capturing" in stepper.eager_reason


def test_a_multi_agent_step_replays_each_steps_actions(emulated_cuda_graph):
    """The cart double pendulum (a DirectMARLEnv task that keeps its actions dict), its step captured
    in the emulated graph: each replay applies that step's actions (the emulation replays the torch
    ops, not the physics), and what the caller passed and got back in the warm-up steps stays as it was."""
    task = "simlab/Cart-Double-Pendulum-Direct-v0"
    cfg = parse_env_cfg(task, device="cpu", num_envs=4)
    cfg.episode_length_s = 3.5 * cfg.sim.dt * cfg.decimation  # time-outs at steps 3 and 6
    env = gym.make(task, cfg=cfg).unwrapped
    env.sim.physics.forwards_all_worlds = True  # a masked reset then marks worlds stale without a host read
    env._stepper.eager_reason = None  # capture as on a GPU
    env.reset(seed=1)
    generator = torch.Generator().manual_seed(0)
    cart = env._cart_dof_idx[0]
    for i in range(6):
        actions = {agent: torch.rand(4, 1, generator=generator) * 2 - 1 for agent in env.possible_agents}
        sent = {agent: action.clone() for agent, action in actions.items()}
        _, _, terminated, time_outs, _ = env.step(actions)
        effort = env.robot.data.joint_effort_target[:, cart]
        torch.testing.assert_close(effort, sent["cart"][:, 0] * env.cfg.cart_action_scale, msg=f"step {i}")
        if i == 1:  # the last warm-up step
            warm_up = actions, sent, terminated, {agent: t.clone() for agent, t in terminated.items()}, time_outs
    assert env.step_is_graphed, env.step_mode
    actions, sent, terminated, terminated_then, time_outs = warm_up
    for agent in env.possible_agents:
        assert torch.equal(actions[agent], sent[agent]), agent
        assert torch.equal(terminated[agent], terminated_then[agent]), agent
        assert not time_outs[agent].any(), agent
    env.close()


# -- on the GPU ------------------------------------------------------------------------------------


def _isaac_style_rollout(use_cuda_graph: bool, steps: int = 150):
    env = isaac_style_cartpole("cuda:0", 64, use_cuda_graph)
    env.reset(seed=4)
    generator = torch.Generator(device="cuda:0").manual_seed(0)
    outputs = []
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(
            torch.rand(64, 1, device="cuda:0", generator=generator) * 2 - 1
        )
        term = env.command_manager.get_term("target")
        outputs.append([obs["policy"].clone(), reward.clone(), terminated | truncated, term.metrics["error"].clone()])
    result = outputs, env.step_is_graphed, env._stepper.mode, env._stepper.write_backs
    env.close()
    return result


@pytest.mark.gpu
@gpu
def test_isaac_lab_style_terms_replay_like_eager_on_the_gpu():
    graphed, is_graphed, mode, write_backs = _isaac_style_rollout(True)
    eager, *_ = _isaac_style_rollout(False)
    assert is_graphed, mode
    assert write_backs >= 4  # the command's target and metric, the reward term's buffer and metric
    assert sum(int(out[2].sum()) for out in graphed) > 0, "the comparison must cross resets"
    for i, (out_g, out_e) in enumerate(zip(graphed, eager)):
        for a, b in zip(out_g, out_e):
            if a.dtype == torch.bool:
                assert torch.equal(a, b), f"step {i}: dones differ"
            else:
                torch.testing.assert_close(a, b, rtol=1e-4, atol=1e-4, msg=lambda m, i=i: f"step {i}: {m}")
