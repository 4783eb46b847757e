"""Actuator models with Isaac Lab's API: gains and limits from the config or the robot file's
defaults, ``compute`` keeping ``computed_effort`` / ``applied_effort``, the DC motor's curve."""

from __future__ import annotations

import pytest
import torch

from simlab.actuators import DCMotorCfg, IdealPDActuatorCfg, ImplicitActuatorCfg
from simlab.utils.types import ArticulationActions

NAMES = ["hip", "knee"]


def build(cfg, num_envs=3, **defaults):
    return cfg.class_type(cfg, joint_names=NAMES, joint_ids=[0, 1], num_envs=num_envs, device="cpu", **defaults)


def test_config_values_win_over_the_robot_files_defaults():
    cfg = IdealPDActuatorCfg(joint_names_expr=NAMES, stiffness={"hip": 50.0}, damping=None, armature=0.1)
    pd = build(cfg, stiffness=7.0, damping=2.0, friction=0.3)
    assert pd.stiffness[0].tolist() == [50.0, 7.0]  # the dict names only the hip
    assert pd.damping.unique().tolist() == [2.0] and pd.friction.unique().tolist() == pytest.approx([0.3])
    assert pd.armature.unique().tolist() == pytest.approx([0.1])
    assert pd.computed_effort.shape == pd.applied_effort.shape == (3, 2)
    # an explicit model clips in torch; the simulation's cap stays out of its way unless set
    assert pd.effort_limit_sim.unique().item() == pd._DEFAULT_MAX_EFFORT_SIM


def test_ideal_pd_computes_then_clips():
    pd = build(IdealPDActuatorCfg(joint_names_expr=NAMES, stiffness=10.0, damping=1.0, effort_limit=25.0))
    targets = ArticulationActions(
        joint_positions=torch.full((3, 2), 1.0), joint_velocities=torch.zeros(3, 2), joint_efforts=torch.ones(3, 2)
    )
    pos = torch.tensor([[0.0, 0.5]]).repeat(3, 1)
    vel = torch.tensor([[-2.0, 0.0]]).repeat(3, 1)
    out = pd.compute(targets, pos, vel)
    # hip: 10 * 1 + 1 * 2 + 1 = 13; knee: 10 * 0.5 + 0 + 1 = 6 (both within 25)
    assert pd.computed_effort[0].tolist() == [13.0, 6.0] and torch.equal(out.joint_efforts, pd.applied_effort)
    targets.joint_positions = torch.full((3, 2), 10.0)
    pd.compute(targets, pos, vel)
    assert pd.computed_effort[0, 0].item() == 103.0 and pd.applied_effort[0].tolist() == [25.0, 25.0]


def dc_motor_bounds(speed: float, saturation: float, limit: float, no_load: float) -> tuple[float, float]:
    """The torque interval a four-quadrant DC motor allows at ``speed``, written out case by case."""
    upper_line = saturation * (1 - speed / no_load)
    lower_line = saturation * (-1 - speed / no_load)
    upper, lower = min(upper_line, limit), max(lower_line, -limit)
    if lower > upper:  # past the corner speed: braking at the effort limit (Isaac Lab's)
        return (-limit, -limit) if speed > 0 else (limit, limit)
    return lower, upper


@pytest.mark.parametrize("speed", [-130.0, -90.0, -40.0, -5.0, 0.0, 5.0, 40.0, 70.0, 90.0, 130.0])
@pytest.mark.parametrize("torque", [-150.0, -70.0, -10.0, 0.0, 25.0, 80.0, 150.0])
def test_dc_motor_curve_against_a_case_by_case_oracle(speed, torque):
    cfg = DCMotorCfg(
        joint_names_expr=NAMES,
        stiffness=0.0,
        damping=0.0,
        saturation_effort=100.0,
        effort_limit=60.0,
        velocity_limit=50.0,
    )
    motor = build(cfg, num_envs=1)
    targets = ArticulationActions(torch.zeros(1, 2), torch.zeros(1, 2), torch.full((1, 2), torque))
    motor.compute(targets, torch.zeros(1, 2), torch.full((1, 2), speed))
    lower, upper = dc_motor_bounds(speed, 100.0, 60.0, 50.0)
    assert motor.computed_effort[0, 0].item() == torque
    assert motor.applied_effort[0, 0].item() == pytest.approx(min(max(torque, lower), upper))
    # Isaac Lab's way to probe the curve: the last joint velocities, then _clip_effort alone
    motor._joint_vel[:] = speed
    assert motor._clip_effort(torch.full((1, 2), torque))[0, 0].item() == pytest.approx(min(max(torque, lower), upper))


@pytest.mark.parametrize(("effort_limit", "effort_limit_sim", "expected"), [(None, None, 1e9), (None, 400.0, 400.0)])
def test_an_explicit_models_effort_limit_comes_from_its_config(effort_limit, effort_limit_sim, expected):
    """As in Isaac Lab: unset, it is effort_limit_sim (1e9 unset), whatever the robot file says (5000 here)."""
    cfg = IdealPDActuatorCfg(
        joint_names_expr=NAMES, stiffness=1.0, damping=0.0, effort_limit=effort_limit, effort_limit_sim=effort_limit_sim
    )
    pd = build(cfg, effort_limit=5000.0)
    assert pd.effort_limit.unique().item() == expected and pd.effort_limit_sim.unique().item() == expected


def test_implicit_drive_has_one_effort_limit():
    drive = build(ImplicitActuatorCfg(joint_names_expr=NAMES, stiffness=1.0, damping=0.0, effort_limit=30.0))
    assert drive.effort_limit_sim.unique().item() == 30.0 and drive.effort_limit.unique().item() == 30.0
    assert drive.cfg.effort_limit_sim == 30.0  # the actuator's copy of the config, both names filled
    with pytest.raises(ValueError, match="one limit"):
        build(
            ImplicitActuatorCfg(joint_names_expr=NAMES, stiffness=1.0, damping=0.0, effort_limit=3, effort_limit_sim=4)
        )
