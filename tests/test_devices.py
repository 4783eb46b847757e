"""Teleoperation devices: the keyboard's key map and its keys from the viewers, the scripted device
driving the IK tasks, the gamepad and SpaceMouse read from stand-in hardware, and their errors."""

from __future__ import annotations

import importlib.util
import sys

import numpy as np
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.devices import (
    DevicesCfg,
    Se3Keyboard,
    Se3KeyboardCfg,
    Se3Scripted,
    Se3ScriptedCfg,
    Se3SpaceMouse,
    Se3SpaceMouseCfg,
    create_teleop_device,
)
from simlab.devices.keys import KeyEvent, key_hub
from simlab.devices.spacemouse.se3_spacemouse import axis_value
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.viewer.native import forward_key_to_listeners

# Isaac Lab's key map: key -> (index in the command, sign); position 0.4, rotation 0.8 by default
KEY_MAP = {"W": (0, 1), "S": (0, -1), "A": (1, 1), "D": (1, -1), "Q": (2, 1), "E": (2, -1),
           "Z": (3, 1), "X": (3, -1), "T": (4, 1), "G": (4, -1), "C": (5, 1), "V": (5, -1)}  # fmt: skip


@pytest.fixture
def keyboard():
    device = Se3Keyboard(Se3KeyboardCfg())
    yield device
    device.close()


def press(device: Se3Keyboard, key: str) -> None:
    device.on_key_event(KeyEvent(key, "press"))


def release(device: Se3Keyboard, key: str) -> None:
    device.on_key_event(KeyEvent(key, "release"))


# -- the keyboard ----------------------------------------------------------------------------------


@pytest.mark.parametrize("key", list(KEY_MAP))
def test_each_key_gives_isaac_labs_delta_while_held(keyboard, key):
    index, sign = KEY_MAP[key]
    press(keyboard, key)
    expected = torch.zeros(7)
    expected[index] = sign * (0.4 if index < 3 else 0.8)
    expected[6] = 1.0  # gripper open
    torch.testing.assert_close(keyboard.advance(), expected)
    torch.testing.assert_close(keyboard.advance(), expected)  # still held
    release(keyboard, key)
    torch.testing.assert_close(keyboard.advance(), torch.tensor([0.0] * 6 + [1.0]))


def test_rotation_keys_compose_as_intrinsic_xyz_euler_angles(keyboard):
    rotation = pytest.importorskip("scipy.spatial.transform").Rotation
    for key in "ZTV":  # roll +, pitch +, yaw -
        press(keyboard, key)
    expected = rotation.from_euler("XYZ", [0.8, 0.8, -0.8]).as_rotvec()
    np.testing.assert_allclose(keyboard.advance()[3:6].numpy(), expected, atol=1e-5)


def test_gripper_toggle_reset_and_layout(keyboard):
    press(keyboard, "K")
    release(keyboard, "K")
    assert keyboard.advance()[6] == -1.0  # closed
    press(keyboard, "W")
    press(keyboard, "K")
    assert keyboard.advance()[6] == 1.0  # open again
    press(keyboard, "L")  # reset: no motion, gripper open
    torch.testing.assert_close(keyboard.advance(), torch.tensor([0.0] * 6 + [1.0]))
    no_gripper = Se3Keyboard(Se3KeyboardCfg(gripper_term=False, pos_sensitivity=0.05), listen_to_viewer=False)
    press(no_gripper, "D")
    torch.testing.assert_close(no_gripper.advance(), torch.tensor([0.0, -0.05, 0.0, 0.0, 0.0, 0.0]))


def test_a_tap_holds_its_key_for_the_hold_time(keyboard):
    now = [100.0]
    keyboard._clock = lambda: now[0]
    keyboard.on_key_event(KeyEvent("Q", "tap"))
    assert keyboard.advance()[2] == pytest.approx(0.4)
    now[0] += 0.15
    keyboard.on_key_event(KeyEvent("Q", "tap"))  # a held web button repeats: the hold goes on
    now[0] += 0.15
    assert keyboard.advance()[2] == pytest.approx(0.4)
    now[0] += 0.1  # 0.25 s after the last tap
    assert keyboard.advance()[2] == 0.0


def test_a_dropped_keyboard_stops_listening():
    import gc

    device = Se3Keyboard(Se3KeyboardCfg())
    assert key_hub.wants("W")
    del device
    gc.collect()
    assert not key_hub.wants("W")


def test_callbacks_run_on_press_for_any_key(keyboard):
    calls = []
    keyboard.add_callback("R", lambda: calls.append("R"))
    keyboard.add_callback("K", lambda: calls.append("K"))
    key_hub.publish(KeyEvent("R", "tap"))  # the viewer now forwards R as well
    press(keyboard, "K")
    release(keyboard, "K")
    assert calls == ["R", "K"]
    with pytest.raises(TypeError, match="must be callable"):
        keyboard.add_callback("R", "not a function")


def test_native_viewer_keys_go_to_the_keyboard_only_while_it_listens(keyboard):
    assert forward_key_to_listeners(ord("W"))  # GLFW's key code of W
    assert keyboard.advance()[0] == pytest.approx(0.4)
    assert not forward_key_to_listeners(ord("["))  # the viewer's own key
    assert not forward_key_to_listeners(32)  # space: pause
    keyboard.close()
    assert not forward_key_to_listeners(ord("V"))  # no listener: V toggles the viewer's drawing again


@pytest.mark.skipif(
    importlib.util.find_spec("viser") is None or importlib.util.find_spec("mjviser") is None,
    reason="simlab[viewer] (viser, mjviser) is not installed",
)
def test_web_viewer_teleop_buttons_send_keys_to_the_keyboard(keyboard):
    import socket

    import mujoco

    from simlab.viewer import SimSource, open_viewer

    class StillPhysics:
        def __init__(self, model):
            self.model = model

        def data(self, name):
            return torch.zeros(1, getattr(mujoco.MjData(self.model), name).shape[0])

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    ground = mujoco.MjModel.from_xml_string('<mujoco><worldbody><geom type="plane" size="0 0 1"/></worldbody></mujoco>')
    viewer = open_viewer(SimSource(ground, StillPhysics(ground), torch.zeros(1, 3), 0.02), "web", port)
    try:
        buttons = viewer._teleop_buttons
        assert set(KEY_MAP) | {"K", "L"} <= set(buttons)
        assert buttons["W"].label == "W: +x" and buttons["K"].label == "K: gripper"
        # what viser runs while the W button is held, and when K is clicked
        (hold_w,) = buttons["W"]._button_impl.hold_cbs_from_freq[10.0]
        hold_w(None)
        (click_k,) = buttons["K"]._impl.update_cb
        click_k(None)
        command = keyboard.advance()
        assert command[0] == pytest.approx(0.4) and command[6] == -1.0
        keyboard.add_callback("R", lambda: None)  # a key added later gets its button too
        assert "R" in viewer._teleop_buttons
    finally:
        viewer.close()


# -- the scripted device and the factory -----------------------------------------------------------


def test_scripted_device_replays_its_segments():
    device = Se3Scripted(Se3ScriptedCfg(script=[("WQ", 2), ("", 1), ("K", 1)], pos_sensitivity=0.1))
    commands = [device.advance() for _ in range(5)]
    assert [c[0].item() for c in commands] == pytest.approx([0.1, 0.1, 0.0, 0.0, 0.0])
    assert [c[2].item() for c in commands] == pytest.approx([0.1, 0.1, 0.0, 0.0, 0.0])
    assert [c[6].item() for c in commands] == [1.0, 1.0, 1.0, -1.0, -1.0]
    assert device.finished and device.num_steps == 4
    device.reset()
    assert not device.finished and device.advance()[0] == pytest.approx(0.1)


@pytest.mark.parametrize(
    ("script", "message"),
    [([("P", 3)], "outside the key map"), ([("W", 0)], "int >= 1"), (["W"], "must be \\(keys, steps\\)")],
)
def test_scripted_device_refuses_a_bad_script(script, message):
    with pytest.raises(ValueError, match=message):
        Se3Scripted(Se3ScriptedCfg(script=script))


def test_create_teleop_device_from_named_configs():
    calls = []
    devices = DevicesCfg(devices={"demo": Se3ScriptedCfg(script=[("R", 1)])})
    with pytest.raises(ValueError, match="outside the key map"):  # R is no key of the map
        create_teleop_device("demo", devices.devices)
    devices.devices["demo"] = Se3ScriptedCfg(script=[("K", 1)])
    device = create_teleop_device("demo", devices.devices, {"K": lambda: calls.append(1)})
    assert isinstance(device, Se3Scripted)
    device.advance()
    assert calls == [1]
    with pytest.raises(ValueError, match="configured: \\['demo'\\]"):
        create_teleop_device("spacemouse", devices.devices)


# -- the scripted device driving the IK tasks ------------------------------------------------------


def _hand_position(env) -> torch.Tensor:
    """The frame the IK action moves: 0.107 m along the hand's z axis (its body offset)."""
    from simlab.utils.math import quat_apply

    robot = env.scene["robot"]
    hand = robot.find_bodies("panda_hand")[0][0]
    offset = torch.tensor([0.0, 0.0, 0.107]).repeat(env.num_envs, 1)
    tip = robot.data.body_pos_w[:, hand] + quat_apply(robot.data.body_quat_w[:, hand], offset)
    return (tip - env.scene.env_origins).clone()


def test_scripted_keys_move_the_reach_end_effector_in_the_commanded_directions():
    import gymnasium as gym

    cfg = parse_env_cfg("simlab/Reach-Franka-IK-Rel-v0", device="cpu", num_envs=2)
    cfg.seed = 0
    # start from the default pose: a random reset can fold the elbow against its limit
    cfg.events.reset_robot_joints.params["position_range"] = (1.0, 1.0)
    env = gym.make("simlab/Reach-Franka-IK-Rel-v0", cfg=cfg).unwrapped
    env.reset()
    # the teleop script's keyboard settings: 5 cm a step, scaled by the action's 0.5
    script = [("", 10), ("W", 15), ("", 10), ("E", 15), ("", 10), ("A", 15), ("", 10)]
    device = Se3Scripted(Se3ScriptedCfg(script=script, pos_sensitivity=0.05, rot_sensitivity=0.05, gripper_term=False))
    positions = []
    for _, steps in script:
        for _ in range(steps):
            env.step(device.advance().repeat(env.num_envs, 1))
        positions.append(_hand_position(env))
    env.close()
    moves = {keys: positions[i] - positions[i - 1] for i, (keys, _) in enumerate(script) if keys}
    for key, axis, sign in (("W", 0, 1), ("E", 2, -1), ("A", 1, 1)):
        move = moves[key]
        assert (sign * move[:, axis] > 0.02).all(), (key, move)  # at least 2 cm the right way
        others = [i for i in range(3) if i != axis]
        assert (move[:, others].abs().max(dim=-1).values < 0.5 * sign * move[:, axis]).all(), (key, move)


def test_scripted_gripper_key_closes_the_lift_gripper():
    import gymnasium as gym

    cfg = parse_env_cfg("simlab/Lift-Cube-Franka-IK-Rel-v0", device="cpu", num_envs=2)
    env = gym.make("simlab/Lift-Cube-Franka-IK-Rel-v0", cfg=cfg).unwrapped
    env.reset()
    device = Se3Scripted(Se3ScriptedCfg(script=[("Q", 10), ("K", 25)], pos_sensitivity=0.05))
    robot = env.scene["robot"]
    fingers = robot.find_joints("panda_finger_joint.*")[0]
    for _ in range(35):
        env.step(device.advance().repeat(env.num_envs, 1))
    closed = robot.data.joint_pos[:, fingers].clone()
    env.close()
    assert (closed < 0.005).all(), closed  # from 0.04 open, nothing between the fingers


# -- gamepad and SpaceMouse ------------------------------------------------------------------------


class _FakePad:
    """Stands in for an SDL game controller: axes and buttons as a person holds them."""

    def __init__(self, pygame):
        self.pygame = pygame
        self.axes: dict[str, int] = {}
        self.buttons: set[str] = set()
        self.name = "stand-in pad"

    def get_axis(self, axis: int) -> int:
        for name, value in self.axes.items():
            if getattr(self.pygame, f"CONTROLLER_AXIS_{name}") == axis:
                return value
        return 0

    def get_button(self, button: int) -> bool:
        return any(getattr(self.pygame, f"CONTROLLER_BUTTON_{name}") == button for name in self.buttons)


def test_gamepad_sticks_and_buttons_give_isaac_labs_commands(monkeypatch):
    pygame = pytest.importorskip("pygame")
    from simlab.devices import Se3Gamepad, Se3GamepadCfg

    pad = _FakePad(pygame)

    def open_fake(self, index):
        self._pygame = pygame
        return pad

    monkeypatch.setattr(Se3Gamepad, "_open_controller", open_fake)
    gamepad = Se3Gamepad(Se3GamepadCfg(pos_sensitivity=1.0, rot_sensitivity=1.0))
    torch.testing.assert_close(gamepad.advance(), torch.tensor([0.0] * 6 + [1.0]))
    pad.axes = {"LEFTY": -32767, "RIGHTX": 16384, "LEFTX": 100}  # left stick up, right stick half right
    command = gamepad.advance()
    assert command[0] == pytest.approx(1.0) and command[1] == 0.0  # LEFTX inside the dead zone
    assert command[5] == pytest.approx(0.5, abs=1e-3)  # yaw
    pad.axes = {}
    pad.buttons = {"DPAD_UP", "X"}
    command = gamepad.advance()
    assert command[4] == pytest.approx(-0.8) and command[6] == -1.0  # pitch -, gripper closed
    assert gamepad.advance()[6] == -1.0  # X still held: no second toggle
    calls = []
    gamepad.add_callback("START", lambda: calls.append("START"))
    pad.buttons = {"START"}
    gamepad.advance()
    assert calls == ["START"]


def test_gamepad_without_a_pad_says_so():
    pytest.importorskip("pygame")
    from simlab.devices import Se3Gamepad, Se3GamepadCfg

    with pytest.raises(OSError, match="No gamepad at index 3"):
        Se3Gamepad(Se3GamepadCfg(device_index=3))


class _FakeHidDevice:
    def read(self, size, timeout_ms=0):
        return []

    def close(self):
        pass


def test_spacemouse_reports_give_isaac_labs_commands(monkeypatch):
    monkeypatch.setattr(Se3SpaceMouse, "_open_device", lambda self: (_FakeHidDevice(), "SpaceMouse Compact"))
    mouse = Se3SpaceMouse(Se3SpaceMouseCfg(pos_sensitivity=1.0, rot_sensitivity=1.0))
    try:
        assert axis_value(0x5E, 0x01) == pytest.approx(350 / 350.0)  # 0x015e = 350: full deflection
        assert axis_value(0xA2, 0xFE) == pytest.approx(-1.0)  # -350
        mouse.handle_report([1, 0x5E, 0x01, 0, 0, 0xA2, 0xFE])  # translation: y +1, x 0, z -1 (device frame)
        mouse.handle_report([2, 0, 0, 0xAF, 0x00, 0, 0])  # rotation: x +0.5
        command = mouse.advance()
        np.testing.assert_allclose(command[:3].numpy(), [0.0, 1.0, 1.0], atol=1e-6)
        assert command[3] == pytest.approx(0.5) and command[6] == 1.0
        calls = []
        mouse.add_callback("R", lambda: calls.append("R"))
        mouse.handle_report([3, 1])  # left button: gripper
        assert mouse.advance()[6] == -1.0
        mouse.handle_report([3, 2])  # right button: reset
        torch.testing.assert_close(mouse.advance(), torch.tensor([0.0] * 6 + [1.0]))
        assert calls == ["R"]
    finally:
        mouse.close()


def test_spacemouse_without_a_device_says_what_it_saw():
    pytest.importorskip("hid")
    with pytest.raises(OSError, match="No SpaceMouse found .*HID devices seen"):
        Se3SpaceMouse(Se3SpaceMouseCfg())


@pytest.mark.parametrize(
    ("module", "make"),
    [("hid", lambda: Se3SpaceMouse(Se3SpaceMouseCfg())), ("pygame", lambda: _make_gamepad())],
)
def test_a_missing_library_names_the_extra_to_install(monkeypatch, module, make):
    monkeypatch.setitem(sys.modules, module, None)  # import now fails as if not installed
    with pytest.raises(ImportError, match='pip install "simlab\\[teleop\\]"'):
        make()


def _make_gamepad():
    from simlab.devices import Se3Gamepad, Se3GamepadCfg

    return Se3Gamepad(Se3GamepadCfg())
