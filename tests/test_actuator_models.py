"""Isaac Lab's other actuator models: delayed PD, remotized PD, MLP and LSTM actuator networks.

Torques against hand-computed values for each model; per-env state (delays, histories, hidden
states) reset only where the mask is set; the models in a simulated scene on mjbatch and on MuJoCo
Warp's CPU device; inside the env step replayed as a (CPU-emulated) CUDA graph, equal to eager
steps; network files are weights only (a crafted pickle or TorchScript file does not run); the
shipped networks imitate the DC motor with a delay they were fitted to.
"""

from __future__ import annotations

import os
import zipfile
from dataclasses import MISSING

import pytest
import torch
from conftest import load_script
from test_graph_contract import _Sim, emulated_cuda_graph  # noqa: F401 (a fixture)

from simlab.actuators import (
    ActuatorNetLSTMCfg,
    ActuatorNetMLPCfg,
    DelayedPDActuatorCfg,
    IdealPDActuatorCfg,
    RemotizedPDActuatorCfg,
)
from simlab.actuators.actuator_net import NETS_DIR, ActuatorLSTM, ActuatorMLP
from simlab.assets import ArticulationCfg
from simlab.envs.utils.cuda_graph import EnvStepper
from simlab.scene import InteractiveSceneCfg
from simlab.utils import configclass
from simlab.utils.assets import ISAACLAB_NUCLEUS_DIR
from simlab.utils.errors import ConfigError, UntrustedFileError
from simlab.utils.types import ArticulationActions

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NAMES = ["hip", "knee"]
NO_LIMITS = {"saturation_effort": 1e6, "effort_limit": 1e6, "velocity_limit": 1e6}  # the DC clip leaves torques be


def build(cfg, num_envs: int = 4):
    return cfg.class_type(cfg, joint_names=NAMES, joint_ids=[0, 1], num_envs=num_envs, device="cpu")


def actions(pos, vel=None, effort=None) -> ArticulationActions:
    zeros = torch.zeros_like(pos)
    return ArticulationActions(pos, zeros if vel is None else vel, zeros if effort is None else effort)


def signal(k: int, n: int = 4, scale: float = 1.0) -> torch.Tensor:
    """A distinct (n, 2) value for step k: env i, joint j -> scale * (k + 0.1 i + 0.01 j)."""
    return scale * (k + 0.1 * torch.arange(n).view(-1, 1) + 0.01 * torch.arange(2).view(1, -1))


# -- delayed PD ------------------------------------------------------------------------------------


def set_lags(actuator, lags: list[int]) -> None:
    actuator.targets_delay_buffer.set_time_lag(torch.tensor(lags, dtype=torch.int))


def test_delayed_pd_applies_the_command_of_d_steps_before():
    kp, kd = 10.0, 0.5
    pd = build(DelayedPDActuatorCfg(joint_names_expr=NAMES, stiffness=kp, damping=kd, max_delay=3))
    set_lags(pd, [0, 1, 2, 3])
    sent = []  # (q*, qd*, tau_ff) of every step
    for k in range(8):
        command = (signal(k), signal(k, scale=0.5), signal(k, scale=0.1))
        sent.append(command)
        q, qd = signal(k, scale=0.3), signal(k, scale=-0.2)
        out = pd.compute(actions(*command), q, qd)
        for env, lag in enumerate([0, 1, 2, 3]):
            old_q, old_qd, old_tau = (c[env] for c in sent[max(k - lag, 0)])  # before the first: the first
            expected = kp * (old_q - q[env]) + kd * (old_qd - qd[env]) + old_tau
            torch.testing.assert_close(out.joint_efforts[env], expected)
    torch.testing.assert_close(pd.applied_effort, out.joint_efforts)


def test_isaac_labs_three_delay_buffer_names_set_and_read_the_one_lag():
    """Isaac Lab code sets the lags through its three buffer names, one after the other, and reads
    ``positions_delay_buffer.time_lags``: both work on the one stacked buffer."""
    pd = build(DelayedPDActuatorCfg(joint_names_expr=NAMES, stiffness=1.0, damping=0.0, max_delay=3))
    lags = torch.tensor([3, 2, 1, 0], dtype=torch.int)
    for buffer in (pd.positions_delay_buffer, pd.velocities_delay_buffer, pd.efforts_delay_buffer):
        buffer.set_time_lag(lags)
    assert pd.positions_delay_buffer.time_lags.tolist() == [3, 2, 1, 0]
    assert pd.targets_delay_buffer.time_lags.tolist() == [3, 2, 1, 0]
    q0 = signal(0)
    first = pd.compute(actions(q0), torch.zeros(4, 2), torch.zeros(4, 2)).joint_efforts.clone()
    later = pd.compute(actions(signal(1)), torch.zeros(4, 2), torch.zeros(4, 2)).joint_efforts
    torch.testing.assert_close(first, q0)  # kp 1: every env starts from the first command
    torch.testing.assert_close(later[3], signal(1)[3])  # lag 0: the new command
    torch.testing.assert_close(later[0], q0[0])  # lag 3: still the first


def test_delays_are_drawn_in_range_and_redrawn_only_where_the_mask_is_set():
    torch.manual_seed(0)
    pd = build(DelayedPDActuatorCfg(joint_names_expr=NAMES, stiffness=1.0, damping=0.0, min_delay=1, max_delay=5), 64)
    lags = pd.targets_delay_buffer.time_lags  # one delay for positions, velocities and efforts
    mask = torch.arange(64) % 2 == 0
    seen = set()
    for _ in range(10):
        before = lags.clone()
        pd.reset(mask)
        assert torch.equal(lags[~mask], before[~mask])
        assert int(lags.min()) >= 1 and int(lags.max()) <= 5
        seen |= set(lags[mask].tolist())
    assert seen == {1, 2, 3, 4, 5}


def test_a_reset_env_forgets_its_old_commands_and_the_others_keep_theirs():
    pd = build(DelayedPDActuatorCfg(joint_names_expr=NAMES, stiffness=1.0, damping=0.0, min_delay=2, max_delay=2), 2)
    zero = torch.zeros(2, 2)
    for k in range(4):
        pd.compute(actions(torch.full((2, 2), float(k))), zero, zero)
    pd.reset([0])  # Isaac Lab's ids work as a mask does
    out = pd.compute(actions(torch.full((2, 2), 9.0)), zero, zero)
    # env 0 has one command since its reset (9); env 1 gets the one of two steps before (2)
    assert out.joint_efforts[:, 0].tolist() == [9.0, 2.0]


def test_bad_delays_are_one_line_errors():
    with pytest.raises(ConfigError, match="0 <= min_delay <= max_delay"):
        build(DelayedPDActuatorCfg(joint_names_expr=NAMES, stiffness=1.0, damping=0.0, min_delay=3, max_delay=1))


# -- remotized PD ----------------------------------------------------------------------------------

TABLE = [[-1.0, 1.5, 5.0], [0.0, 1.2, 10.0], [1.0, 1.0, 20.0]]


def test_remotized_pd_limits_the_torque_by_the_table_at_the_joint_angle():
    cfg = RemotizedPDActuatorCfg(
        joint_names_expr=NAMES, stiffness=100.0, damping=0.0, joint_parameter_lookup=TABLE, effort_limit=3.0
    )
    pd = build(cfg)
    assert cfg.effort_limit == 3.0  # the user's config is left alone; the table is the only limit
    q = torch.tensor([[-2.0, -0.5], [0.25, 2.0], [0.0, 0.5], [0.0, 0.0]])
    target = q + torch.tensor([[1.0, 1.0], [1.0, -1.0], [-1.0, 0.05], [0.0, 0.0]])
    out = pd.compute(actions(target), q, torch.zeros(4, 2))
    # limits: held 5 below the table, 7.5 and 12.5 between rows, held 20 above; 10 and 15 at 0 and 0.5
    expected = torch.tensor([[5.0, 7.5], [12.5, -20.0], [-10.0, 5.0], [0.0, 0.0]])
    torch.testing.assert_close(out.joint_efforts, expected)
    torch.testing.assert_close(pd.computed_effort, 100.0 * (target - q))
    assert pd.transmission_ratio_samples.tolist() == pytest.approx([1.5, 1.2, 1.0])


def test_remotized_pd_is_delayed_too():
    cfg = RemotizedPDActuatorCfg(
        joint_names_expr=NAMES, stiffness=1.0, damping=0.0, min_delay=1, max_delay=1, joint_parameter_lookup=TABLE
    )
    pd = build(cfg, 1)
    zero = torch.zeros(1, 2)
    pd.compute(actions(torch.full((1, 2), 1.0)), zero, zero)
    out = pd.compute(actions(torch.full((1, 2), 3.0)), zero, zero)
    assert out.joint_efforts.tolist() == [[1.0, 1.0]]


@pytest.mark.parametrize("table", [[[0.0, 1.0]], [[1.0, 1.0, 5.0], [0.0, 1.0, 6.0]]])
def test_a_bad_table_is_a_one_line_error(table):
    cfg = RemotizedPDActuatorCfg(joint_names_expr=NAMES, stiffness=1.0, damping=0.0, joint_parameter_lookup=table)
    with pytest.raises(ConfigError, match="rows of \\(angle, transmission ratio, max torque\\)"):
        build(cfg)


# -- MLP -------------------------------------------------------------------------------------------


def mlp_file(tmp_path, sizes=(4, 8, 1)) -> tuple[str, ActuatorMLP]:
    torch.manual_seed(1)
    net = ActuatorMLP(list(sizes))
    path = str(tmp_path / "mlp.pt")
    torch.save(net.state_dict(), path)
    return path, net


def mlp_cfg(path: str, order: str = "pos_vel", **kwargs) -> ActuatorNetMLPCfg:
    fields = dict(joint_names_expr=NAMES, pos_scale=2.0, vel_scale=0.5, torque_scale=3.0, input_idx=[0, 2])
    return ActuatorNetMLPCfg(network_file=path, input_order=order, **{**fields, **NO_LIMITS, **kwargs})


@pytest.mark.parametrize("order", ["pos_vel", "vel_pos"])
def test_mlp_torque_is_the_network_of_the_scaled_history(tmp_path, order):
    path, net = mlp_file(tmp_path)
    actuator = build(mlp_cfg(path, order))
    errors, speeds = [], []
    for k in range(5):
        target, q, qd = signal(k), signal(k, scale=0.3), signal(k, scale=-2.0)
        out = actuator.compute(actions(target), q, qd)
        errors.append(target - q)
        speeds.append(qd)
        old_e = errors[k - 2] if k >= 2 else torch.zeros(4, 2)  # the history starts at zero
        old_v = speeds[k - 2] if k >= 2 else torch.zeros(4, 2)
        for env in range(4):
            for joint in range(2):
                pos = [2.0 * errors[k][env, joint], 2.0 * old_e[env, joint]]
                vel = [0.5 * speeds[k][env, joint], 0.5 * old_v[env, joint]]
                x = torch.tensor(pos + vel if order == "pos_vel" else vel + pos)
                expected = 3.0 * net(x).detach()[0]
                torch.testing.assert_close(out.joint_efforts[env, joint], expected)


def test_mlp_history_resets_only_where_the_mask_is_set(tmp_path):
    path, net = mlp_file(tmp_path)
    actuator = build(mlp_cfg(path), 2)
    zero = torch.zeros(2, 2)
    for k in range(3):
        actuator.compute(actions(torch.full((2, 2), k + 1.0)), zero, zero)
    actuator.reset(torch.tensor([False, True]))
    out = actuator.compute(actions(torch.full((2, 2), 0.5)), zero, zero)
    x_kept = torch.tensor([2.0 * 0.5, 2.0 * 2.0, 0.0, 0.0])  # env 0: the error of two steps before is 2
    x_reset = torch.tensor([2.0 * 0.5, 0.0, 0.0, 0.0])  # env 1: zeros before its reset
    torch.testing.assert_close(out.joint_efforts[:, 0], 3.0 * net(torch.stack([x_kept, x_reset])).detach()[:, 0])


def test_the_dc_motor_clips_the_network_torque(tmp_path):
    path, _ = mlp_file(tmp_path)
    actuator = build(mlp_cfg(path, torque_scale=1e4, saturation_effort=2.0, effort_limit=1.0, velocity_limit=10.0))
    out = actuator.compute(actions(signal(3)), torch.zeros(4, 2), torch.zeros(4, 2))
    assert out.joint_efforts.abs().max() <= 1.0 and actuator.computed_effort.abs().max() > 1.0


def test_mlp_config_mistakes_are_one_line_errors(tmp_path):
    path, _ = mlp_file(tmp_path)
    with pytest.raises(ConfigError, match="'pos_vel' or 'vel_pos'"):
        build(mlp_cfg(path, order="posvel"))
    with pytest.raises(ConfigError, match="takes 4 inputs; input_idx=\\[0, 1, 2\\] gives 6"):
        build(mlp_cfg(path, input_idx=[0, 1, 2]))
    torch.save({"encoder.weight": torch.zeros(2, 2)}, tmp_path / "other.pt")
    with pytest.raises(ConfigError, match="not an MLP's"):
        build(mlp_cfg(str(tmp_path / "other.pt")))
    with pytest.raises(ConfigError, match="Unable to find the file"):
        build(mlp_cfg(str(tmp_path / "missing.pt")))
    with pytest.raises(ConfigError, match="ActuatorNets/Unitree/unitree_go1.pt"):
        build(mlp_cfg(f"{ISAACLAB_NUCLEUS_DIR}/ActuatorNets/Unitree/unknown.pt"))


# -- LSTM ------------------------------------------------------------------------------------------


def lstm_file(tmp_path) -> tuple[str, ActuatorLSTM]:
    torch.manual_seed(2)
    net = ActuatorLSTM(hidden_size=6, num_layers=2)
    path = str(tmp_path / "lstm.pt")
    torch.save(net.state_dict(), path)
    return path, net


def test_lstm_torque_is_the_network_run_over_each_joints_sequence(tmp_path):
    path, net = lstm_file(tmp_path)
    actuator = build(ActuatorNetLSTMCfg(joint_names_expr=NAMES, network_file=path, **NO_LIMITS), 2)
    assert actuator.sea_hidden_state.shape == (2, 2 * 2, 6)  # layers, envs * joints, hidden
    inputs, outputs = [], []
    for k in range(5):
        if k == 3:
            actuator.reset(torch.tensor([True, False]))  # env 0 starts again from a zero state
        target, q, qd = signal(k, 2), signal(k, 2, 0.3), signal(k, 2, -2.0)
        inputs.append(torch.stack([target - q, qd], dim=-1))  # (envs, joints, 2)
        outputs.append(actuator.compute(actions(target), q, qd).joint_efforts.clone())
    for env, start in ((0, 3), (1, 0)):
        for joint in range(2):
            sequence = torch.stack([x[env, joint] for x in inputs[start:]]).unsqueeze(0)  # (1, steps, 2)
            hand, _ = net.lstm(sequence)  # zero initial state
            expected = net.output(hand[0]).detach()[:, 0]
            got = torch.stack([y[env, joint] for y in outputs[start:]])
            torch.testing.assert_close(got, expected)


# -- network files are data --------------------------------------------------------------------------


class _Touch:
    def __init__(self, path: str):
        self.path = path

    def __reduce__(self):
        return (open, (self.path, "w"))


def test_a_crafted_pickle_network_does_not_run(tmp_path):
    marker = tmp_path / "pwned"
    torch.save({"0.weight": _Touch(str(marker))}, tmp_path / "evil.pt")
    with pytest.raises(UntrustedFileError, match="holds more than weights; set trust_network_file=True"):
        build(mlp_cfg(str(tmp_path / "evil.pt")))
    assert not marker.exists()


def test_a_torchscript_network_is_refused_unless_trusted(tmp_path, monkeypatch):
    path, net = mlp_file(tmp_path)
    scripted = str(tmp_path / "scripted.pt")
    torch.jit.save(torch.jit.script(net), scripted)
    marker = tmp_path / "ran"
    real_load = torch.jit.load

    def load(*args, **kwargs):  # stands for the code a TorchScript file carries
        marker.touch()
        return real_load(*args, **kwargs)

    monkeypatch.setattr(torch.jit, "load", load)
    with pytest.raises(UntrustedFileError, match="TorchScript file \\(code\\).*trust_network_file=True"):
        build(mlp_cfg(scripted))
    assert not marker.exists()
    # trusted, it loads as Isaac Lab loads it, and computes what the weights-only network does
    trusted, plain = build(mlp_cfg(scripted, trust_network_file=True)), build(mlp_cfg(path))
    assert marker.exists()
    for actuator in (trusted, plain):
        actuator.compute(actions(signal(2)), signal(1), signal(1, scale=-1.0))
    torch.testing.assert_close(trusted.applied_effort, plain.applied_effort)
    assert zipfile.is_zipfile(scripted)


# -- the shipped networks --------------------------------------------------------------------------


def test_isaac_labs_network_paths_load_simlabs_networks():
    from simlab.robots.anymal import ANYDRIVE_3_LSTM_ACTUATOR_CFG
    from simlab.robots.unitree import GO1_ACTUATOR_CFG

    assert GO1_ACTUATOR_CFG.network_file == f"{ISAACLAB_NUCLEUS_DIR}/ActuatorNets/Unitree/unitree_go1.pt"
    for cfg in (GO1_ACTUATOR_CFG, ANYDRIVE_3_LSTM_ACTUATOR_CFG):
        actuator = cfg.class_type(cfg, NAMES, [0, 1], 3, "cpu")
        out = actuator.compute(actions(torch.full((3, 2), 0.1)), torch.zeros(3, 2), torch.zeros(3, 2))
        assert torch.isfinite(out.joint_efforts).all()
    for name in ("unitree_go1_mlp.pt", "anydrive_3_lstm.pt"):
        assert os.path.getsize(os.path.join(NETS_DIR, name)) < 12 * 1024  # a few KB each


@pytest.mark.parametrize("name", ["unitree_go1_mlp", "anydrive_3_lstm"])
def test_the_shipped_networks_imitate_the_delayed_dc_motor(name):
    """On held-out signals of the fitting script (another seed), the actuator torques stay within a few
    percent of the reference's RMS torque (docs/actuators.md has the figures)."""
    from simlab.robots.anymal import ANYDRIVE_3_LSTM_ACTUATOR_CFG
    from simlab.robots.unitree import GO1_ACTUATOR_CFG

    fit = load_script(os.path.join(ROOT, "scripts", "tools", "fit_actuator_nets.py"), "fit_actuator_nets")
    ref = fit.REFERENCES[name]
    error, speed, torque = fit.data(ref, 64, 100, seed=123)
    cfg = GO1_ACTUATOR_CFG if name.endswith("mlp") else ANYDRIVE_3_LSTM_ACTUATOR_CFG
    # one joint per sequence, run through the actuator step by step as an env would
    actuator = cfg.class_type(cfg, ["joint"], [0], 64, "cpu")
    got = []
    for k in range(100):
        e, qd = error[:, k : k + 1], speed[:, k : k + 1]
        got.append(actuator.compute(actions(e), torch.zeros_like(e), qd).joint_efforts[:, 0].clone())
    residual = (torch.stack(got, dim=1) - torque)[:, ref.delay :]
    rms_error, rms_torque = residual.pow(2).mean().sqrt().item(), torque.pow(2).mean().sqrt().item()
    assert rms_error < 0.08 * rms_torque, (rms_error, rms_torque)


@pytest.mark.parametrize("robot", ["anymal_c", "go1"])
def test_the_shipped_networks_hold_their_robots_up_as_the_dc_motors_they_imitate(robot):
    """ANYmal-C on the ANYdrive LSTM, Go1 on the Go1 MLP, under their default targets for 2 s: they
    settle level, at rest and at the height their DC-motor reference holds them (within 1 cm)."""
    from test_locomotion import robot_scene

    import simlab.sim as sim_utils
    from simlab.robots import anymal, unitree

    if robot == "anymal_c":
        base, group = anymal.ANYMAL_C_CFG, "legs"
        models = (anymal.ANYDRIVE_3_STIFF_ACTUATOR_CFG, anymal.ANYDRIVE_3_LSTM_ACTUATOR_CFG)
    else:
        base, group = unitree.UNITREE_GO1_CFG, "base_legs"
        models = (unitree.GO1_DC_ACTUATOR_CFG, unitree.GO1_ACTUATOR_CFG)
    heights = []
    for model in models:
        sim, scene = robot_scene(base.replace(actuators={group: model}))
        articulation = scene["robot"]
        assert type(articulation.actuators[group]).__name__ == model.class_type.__name__
        articulation.set_joint_position_target(articulation.data.default_joint_pos)
        trace = []
        for _ in range(400):
            scene.write_data_to_sim()
            sim.step()
            scene.update(sim.get_physics_dt())
            trace.append(articulation.data.root_pos_w[:, 2].clone())
        assert (articulation.data.projected_gravity_b[:, 2] < -0.99).all()
        assert articulation.data.root_lin_vel_w.norm(dim=1).max() < 0.05
        heights.append(torch.stack(trace[300:]).mean().item())
        sim_utils.SimulationContext.clear_instance()
    print(f"{robot}: settled base height {heights[0]:.4f} m (DC motor), {heights[1]:.4f} m (network)")
    assert abs(heights[1] - heights[0]) < 0.01, heights


def test_the_anydrive_reference_is_the_dc_motor_on_targets_two_steps_late():
    """The fitting script's ANYdrive reference, written in the network's inputs (position error and
    velocity) alone, is the stiff DC motor acting on the targets of 2 physics steps before and the
    current joint state, on a joint advanced as MuJoCo advances it (``q_k = q_{k-1} + dt qd_k``)."""
    from simlab.robots.anymal import ANYDRIVE_3_STIFF_ACTUATOR_CFG

    fit = load_script(os.path.join(ROOT, "scripts", "tools", "fit_actuator_nets.py"), "fit_actuator_nets")
    ref = fit.REFERENCES["anydrive_3_lstm"]
    cfg = ANYDRIVE_3_STIFF_ACTUATOR_CFG
    motor = cfg.class_type(cfg, ["knee"], [0], 8, "cpu")
    torch.manual_seed(0)
    steps, inertia = 60, 0.07
    targets = (0.3 * torch.randn(8, steps // 4)).repeat_interleave(4, dim=1)  # held 4 steps, as a policy's
    q, qd = torch.zeros(8, 1), torch.zeros(8, 1)
    errors, speeds, torques = [], [], []
    for k in range(steps):
        late = targets[:, max(k - ref.delay, 0), None]
        torques.append(motor.compute(actions(late), q, qd).joint_efforts[:, 0].clone())
        errors.append(targets[:, k] - q[:, 0])
        speeds.append(qd[:, 0].clone())
        qd = qd + fit.DT * torques[-1][:, None] / inertia
        q = q + fit.DT * qd
    expected = fit.reference_torque(ref, torch.stack(errors, 1), torch.stack(speeds, 1))
    torch.testing.assert_close(torch.stack(torques, 1)[:, ref.delay :], expected[:, ref.delay :])


def _hung_legs_settle(robot_cfg, steps: int, settled_from: int) -> tuple[float, float]:
    """The robot hung by its base (feet well off the ground), every joint target 0.1 rad off the default
    pose: its fastest joint speed from physics step ``settled_from`` on, and its largest offset from
    the targets at the end."""
    from test_locomotion import robot_scene

    import simlab.sim as sim_utils

    props = robot_cfg.spawn.articulation_props.replace(fix_root_link=True)
    hung = robot_cfg.replace(
        spawn=robot_cfg.spawn.replace(articulation_props=props),
        init_state=robot_cfg.init_state.replace(pos=(0.0, 0.0, 1.0)),
    )
    sim, scene = robot_scene(hung, num_envs=1)
    legs = scene["robot"]
    legs.set_joint_position_target(legs.data.default_joint_pos + 0.1)
    speeds = []
    for step in range(steps):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        if step >= settled_from:
            speeds.append(legs.data.joint_vel.abs().max().item())
    offset = (legs.data.joint_pos - legs.data.default_joint_pos - 0.1).abs().max().item()
    sim_utils.SimulationContext.clear_instance()
    return max(speeds), offset


def test_the_anydrive_network_holds_swinging_legs_still():
    """ANYmal-D hung by its base, every target 0.1 rad off the default pose: after 0.5 s the legs are
    still, as under the DC motor the network imitates. Its swinging knee (0.07 kg m^2) made the drive
    fitted to a 2-step *sensing* delay oscillate without end (knees at 7.8 rad/s, 0.07 rad off target)."""
    from simlab.robots import anymal

    for model in (anymal.ANYDRIVE_3_STIFF_ACTUATOR_CFG, anymal.ANYDRIVE_3_LSTM_ACTUATOR_CFG):
        speed, offset = _hung_legs_settle(anymal.ANYMAL_D_CFG.replace(actuators={"legs": model}), 200, 100)
        name = type(model).__name__
        assert speed < 0.01, f"{name}: joints still moving at {speed:.3f} rad/s"
        assert offset < 0.05, f"{name}: {offset:.3f} rad off target"  # sagging 0.035 rad under gravity at kp 200


def test_the_go1_network_lets_swinging_legs_come_to_rest():
    """Go1 hung by its base, every target 0.1 rad off the default pose, on the Go1 MLP: by 1.5 s its
    legs are at rest, as under the MLP's reference (the DC motor on the state 2 steps old, a loop
    damped only slowly: 0.016 rad/s at 1.5-1.75 s). The first network, fitted without held targets,
    damped 0.39 instead of 0.5 N m s/rad about rest, and its legs still swung at 0.085 rad/s then."""
    from simlab.robots import unitree

    speed, offset = _hung_legs_settle(unitree.UNITREE_GO1_CFG, 350, 300)
    assert speed < 0.03, f"joints still moving at {speed:.3f} rad/s"
    assert offset < 0.05, f"{offset:.3f} rad off target"  # sagging 0.03 rad under gravity at kp 25


# -- in a simulated scene, on both backends ----------------------------------------------------------


def _warp_cpu(monkeypatch):
    pytest.importorskip("mujoco_warp")
    import simlab.sim.simulation_context as simulation_context
    from simlab.sim.backends.cuda import CudaBackend

    def warp_on_cpu(model, num_envs, device, **options):
        return CudaBackend(model, num_envs, device="cpu", nconmax=options.get("nconmax"), njmax=options.get("njmax"))

    monkeypatch.setattr(simulation_context, "make_backend", warp_on_cpu)


@configclass
class RobotSceneCfg(InteractiveSceneCfg):
    robot: ArticulationCfg = MISSING


SCENE_MODELS = {
    "delayed": lambda paths: DelayedPDActuatorCfg(
        joint_names_expr=[".*"], stiffness=20.0, damping=2.0, min_delay=1, max_delay=3
    ),
    "remotized": lambda paths: RemotizedPDActuatorCfg(
        joint_names_expr=[".*"], stiffness=20.0, damping=2.0, max_delay=2, joint_parameter_lookup=TABLE
    ),
    "mlp": lambda paths: mlp_cfg(paths[0], joint_names_expr=[".*"]),
    "lstm": lambda paths: ActuatorNetLSTMCfg(joint_names_expr=[".*"], network_file=paths[1], **NO_LIMITS),
}


@pytest.mark.parametrize("backend", ["mjbatch", "warp-cpu"])
def test_the_models_drive_a_simulated_cartpole(backend, tmp_path, monkeypatch):
    """Each model's torque reaches MuJoCo's actuators, and equals a twin model fed the states the sim
    had before each step (the delayed models' twins get the same delays)."""
    import simlab.sim as sim_utils
    from simlab.robots.cartpole import CARTPOLE_CFG
    from simlab.scene import InteractiveScene

    if backend == "warp-cpu":
        _warp_cpu(monkeypatch)
    paths = mlp_file(tmp_path)[0], lstm_file(tmp_path)[0]
    for name, make in SCENE_MODELS.items():
        torch.manual_seed(0)
        robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot", actuators={"all": make(paths)})
        sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.01, device="cpu"))
        scene = InteractiveScene(RobotSceneCfg(num_envs=3, env_spacing=2.0, robot=robot))
        sim.reset()
        cartpole = scene["robot"]
        assert type(sim.physics).__name__ == ("CudaBackend" if backend == "warp-cpu" else "CpuBackend")
        actuator = cartpole.actuators["all"]
        twin = actuator.cfg.class_type(actuator.cfg, cartpole.joint_names, [0, 1], 3, "cpu")
        if name in ("delayed", "remotized"):
            set_lags(twin, actuator.targets_delay_buffer.time_lags.tolist())
        for k in range(12):
            target = 0.3 * torch.sin(torch.full((3, 2), 0.5 * k) + torch.arange(3).view(-1, 1))
            cartpole.set_joint_position_target(target)
            q, qd = cartpole.data.joint_pos.clone(), cartpole.data.joint_vel.clone()
            expected = twin.compute(actions(target), q, qd).joint_efforts
            scene.write_data_to_sim()
            sim.step()
            scene.update(sim.get_physics_dt())
            torch.testing.assert_close(actuator.applied_effort, expected)
            torch.testing.assert_close(cartpole.data.applied_torque, expected, atol=1e-4, rtol=1e-4)
        assert expected.abs().max() > 0.1, name  # the models were driving
        sim_utils.SimulationContext.clear_instance()


# -- inside the graphed env step ------------------------------------------------------------------


class ActuatorToyEnv:
    """An env-shaped object whose step drives unit masses with each actuator model and resets envs
    by a mask computed on the device (env i every i + 2 steps)."""

    device = "cpu"

    def __init__(self, models: dict, n: int = 4):
        from types import SimpleNamespace

        self.sim = _Sim()
        self.cfg = SimpleNamespace(sim=SimpleNamespace(use_cuda_graph=True), check_finite_actions=True)
        self.actuators = {k: cfg.class_type(cfg, NAMES, [0, 1], n, "cpu") for k, cfg in models.items()}
        self.pos = {k: torch.zeros(n, 2) for k in models}
        self.vel = {k: torch.zeros(n, 2) for k in models}
        self.count = torch.zeros(n, dtype=torch.long)
        self.period = torch.arange(n) + 2

    def graph_blockers(self) -> list[str]:
        return []

    def _step_body(self, action):
        torques = []
        for name, actuator in self.actuators.items():
            tau = actuator.compute(actions(action), self.pos[name], self.vel[name]).joint_efforts
            self.vel[name].add_(0.01 * tau)
            self.pos[name].add_(0.01 * self.vel[name])
            torques.append(tau)
        self.count += 1
        done = self.count % self.period == 0
        for name, actuator in self.actuators.items():
            actuator.reset(done)
            self.pos[name].masked_fill_(done.view(-1, 1), 0.0)
            self.vel[name].masked_fill_(done.view(-1, 1), 0.0)
        obs = torch.cat(torques, dim=1)
        return {"policy": obs}, obs.sum(dim=1), done


def test_the_models_replay_in_a_graphed_step_like_eager_steps(tmp_path, emulated_cuda_graph):  # noqa: F811
    """Fixed delays here: a graph's random draws differ from eager ones (on a GPU too), see below."""
    mlp_path, _ = mlp_file(tmp_path)
    lstm_path, _ = lstm_file(tmp_path)
    models = {
        "ideal": IdealPDActuatorCfg(joint_names_expr=NAMES, stiffness=5.0, damping=1.0),
        "delayed": DelayedPDActuatorCfg(joint_names_expr=NAMES, stiffness=5.0, damping=1.0, min_delay=2, max_delay=2),
        "remotized": RemotizedPDActuatorCfg(
            joint_names_expr=NAMES, stiffness=5.0, damping=1.0, min_delay=1, max_delay=1, joint_parameter_lookup=TABLE
        ),
        "mlp": mlp_cfg(mlp_path),
        "lstm": ActuatorNetLSTMCfg(joint_names_expr=NAMES, network_file=lstm_path, **NO_LIMITS),
    }
    rollouts = {}
    for graphed in (False, True):
        env = ActuatorToyEnv(models)
        env.cfg.sim.use_cuda_graph = graphed
        env.sim.can_capture_steps = graphed
        stepper = EnvStepper(env, env._step_body, warmup=2)
        rollouts[graphed] = [stepper(signal(k))[0]["policy"] for k in range(14)]
        assert stepper.is_graphed == graphed, stepper.mode
    for k, (eager, graphed) in enumerate(zip(rollouts[False], rollouts[True])):
        torch.testing.assert_close(graphed, eager, msg=f"step {k}")
    assert any(not torch.equal(a, b) for a, b in zip(rollouts[True][4:], rollouts[True][5:]))


def test_the_graphed_step_redraws_delays_only_for_the_envs_it_resets(emulated_cuda_graph):  # noqa: F811
    cfg = DelayedPDActuatorCfg(joint_names_expr=NAMES, stiffness=5.0, damping=1.0, min_delay=0, max_delay=5)
    env = ActuatorToyEnv({"delayed": cfg}, n=8)
    stepper = EnvStepper(env, env._step_body, warmup=2)
    lags = env.actuators["delayed"].targets_delay_buffer.time_lags
    drawn = set()
    for k in range(20):
        before = lags.clone()
        *_, done = stepper(signal(k, 8))
        assert torch.equal(lags[~done], before[~done]), k
        drawn |= set(lags[done].tolist())
    assert stepper.is_graphed and drawn == {0, 1, 2, 3, 4, 5}
