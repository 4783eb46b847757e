"""Checks of the physics backends (simlab/sim/backends) against base.py's documented semantics.

Every behavioural test runs on each backend: ``cpu`` (mjbatch) always, ``cuda`` (MuJoCo Warp) only
where a GPU and mujoco_warp exist (marked ``gpu``). The parity test compares the two backends.
Setting ``SIMLAB_TEST_WARP_DEVICE=cpu`` runs the ``cuda`` cases on MuJoCo Warp's CPU device, which
is slow but checks the backend's logic without a GPU (graph capture works there too).
"""

from __future__ import annotations

import os

import mujoco
import numpy as np
import pytest
import torch

from simlab.sim.backends import CpuBackend, PhysicsBackend, make_backend

WARP_DEVICE = os.environ.get("SIMLAB_TEST_WARP_DEVICE", "cuda")

# A cartpole: a motor-driven cart on a limited slider, a damped hinged pole. No contacts.
CARTPOLE = """
<mujoco>
  <option timestep="0.01"/>
  <worldbody>
    <body name="cart">
      <joint name="slider" type="slide" axis="1 0 0" limited="true" range="-3 3"/>
      <geom type="box" size=".2 .1 .1" mass="1" contype="0" conaffinity="0"/>
      <body name="pole">
        <joint name="hinge" type="hinge" axis="0 1 0" damping="0.01"/>
        <geom type="capsule" fromto="0 0 0 0 0 .6" size=".04" mass=".2" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="slider" gear="10" ctrlrange="-1 1" ctrllimited="true"/></actuator>
</mujoco>
"""

# Spheres dropped on a plane: contacts, to exercise the contact buffer and its overflow check.
SPHERES = """
<mujoco>
  <option timestep="0.005"/>
  <worldbody>
    <geom type="plane" size="5 5 .1"/>
    {bodies}
  </worldbody>
</mujoco>
"""


def _spheres(n: int) -> mujoco.MjModel:
    bodies = "".join(
        f'<body pos="{0.3 * i} 0 0.2"><freejoint/><geom type="sphere" size=".1"/></body>' for i in range(n)
    )
    return mujoco.MjModel.from_xml_string(SPHERES.format(bodies=bodies))


def _cuda_unavailable() -> str | None:
    """Why the cuda backend cannot run here, or None when it can."""
    from simlab.sim.backends.cuda import require_cuda_backend

    try:
        require_cuda_backend(WARP_DEVICE)
    except RuntimeError as err:
        return str(err)
    return None


CUDA_SKIP = _cuda_unavailable()
needs_cuda = pytest.mark.skipif(CUDA_SKIP is not None, reason=f"no cuda backend: {CUDA_SKIP}")
cuda_only = [pytest.mark.gpu, needs_cuda]
BACKENDS = ["cpu", pytest.param("cuda", marks=cuda_only)]


def make(kind: str, model: mujoco.MjModel, num_envs: int, **options) -> PhysicsBackend:
    if kind == "cpu":
        return make_backend(model, num_envs, "cpu")
    if WARP_DEVICE == "cpu":  # MuJoCo Warp on the CPU, for debugging (see module docstring)
        from simlab.sim.backends.cuda import CudaBackend

        return CudaBackend(model, num_envs, device="cpu", **options)
    return make_backend(model, num_envs, WARP_DEVICE, **options)


@pytest.fixture(scope="module")
def cartpole() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(CARTPOLE)


def reference_kinematics(model: mujoco.MjModel, qpos: torch.Tensor) -> mujoco.MjData:
    """MuJoCo C (float64) kinematics at ``qpos``."""
    data = mujoco.MjData(model)
    data.qpos[:] = qpos.detach().cpu().double().numpy()
    mujoco.mj_kinematics(model, data)
    return data


@pytest.mark.parametrize("kind", BACKENDS)
def test_live_tensors(kind: str, cartpole: mujoco.MjModel) -> None:
    sim = make(kind, cartpole, 3)
    qpos, xipos = sim.data("qpos"), sim.data("xipos")
    assert qpos.shape == (3, cartpole.nq) and qpos.dtype == torch.float32
    assert xipos.shape == (3, cartpole.nbody, 3) and sim.data("xmat").shape == (3, cartpole.nbody, 9)
    assert sim.data("qpos") is qpos  # cached, same live tensor
    sim.forward()
    before = xipos.clone()

    qpos[1] = torch.tensor([0.5, 0.7])
    sim.forward()

    assert torch.equal(xipos[0], before[0]) and torch.equal(xipos[2], before[2])
    ref = reference_kinematics(cartpole, qpos[1])
    np.testing.assert_allclose(xipos[1].cpu().numpy(), ref.xipos, atol=1e-5)


@pytest.mark.parametrize("kind", BACKENDS)
def test_step_leaves_derived_fields_current(kind: str, cartpole: mujoco.MjModel) -> None:
    sim = make(kind, cartpole, 2)
    xipos, xquat = sim.data("xipos"), sim.data("xquat")
    sim.data("qpos")[:, 1] = 0.4
    sim.forward()
    sim.data("ctrl")[:] = torch.tensor([[1.0], [-1.0]])
    sim.step(3)

    qpos = sim.data("qpos")
    assert not torch.allclose(qpos[0], qpos[1])
    for env in range(2):  # xipos/xquat belong to the new qpos, not to the previous substep's
        ref = reference_kinematics(cartpole, qpos[env])
        np.testing.assert_allclose(xipos[env].cpu().numpy(), ref.xipos, atol=1e-5)
        np.testing.assert_allclose(xquat[env].cpu().numpy(), ref.xquat, atol=1e-5)


@pytest.mark.parametrize("kind", BACKENDS)
def test_field_first_read_after_a_step_is_current(kind: str, cartpole: mujoco.MjModel) -> None:
    """A field first asked for after physics already ran holds the current values at once."""
    sim = make(kind, cartpole, 2)
    sim.data("qpos")[:, 1] = 0.4
    sim.forward()
    sim.step(2)
    ref = reference_kinematics(cartpole, sim.data("qpos")[0])
    np.testing.assert_allclose(sim.data("xipos")[0].cpu().numpy(), ref.xipos, atol=1e-5)


@pytest.mark.parametrize("kind", BACKENDS)
def test_reset_selected_worlds_only(kind: str, cartpole: mujoco.MjModel) -> None:
    sim = make(kind, cartpole, 3)
    xipos = sim.data("xipos")
    sim.data("ctrl")[:] = 0.8
    sim.data("qfrc_applied")[:, 1] = 0.1
    sim.data("xfrc_applied")[:, 2, 0] = 0.5
    sim.step(10)
    names = ("qpos", "qvel", "ctrl", "qfrc_applied", "xfrc_applied")
    state = {name: sim.data(name).clone() for name in names}
    assert state["qvel"].abs().sum() > 0

    sim.reset(torch.tensor([1], device=sim.device))

    for name, old in state.items():
        now = sim.data(name)
        assert torch.equal(now[[0, 2]], old[[0, 2]]), name  # untouched worlds
        expected = torch.as_tensor(cartpole.qpos0, dtype=torch.float32) if name == "qpos" else 0.0
        assert torch.all(now[1].cpu() == expected), name
    ref = reference_kinematics(cartpole, sim.data("qpos")[1])
    np.testing.assert_allclose(xipos[1].cpu().numpy(), ref.xipos, atol=1e-6)

    sim.reset([0, 2])  # plain lists work too
    assert torch.all(sim.data("qvel") == 0)


def test_an_episode_started_by_mark_reset_follows_from_the_written_state_alone() -> None:
    """Two worlds with different pasts, given the same state by an env reset, step alike to the bit.
    Without ``mark_reset`` they do not: the world that never moved keeps its float64 height (0.0234,
    not a float32), which a write of the float32 value it already shows leaves in place; and the
    other world's solver warm start is its last acceleration. Each alone leaves them apart."""
    model = mujoco.MjModel.from_xml_string(
        '<mujoco><option timestep="0.005"/><worldbody><geom type="plane" size="1 1 .1"/>'
        '<body pos="0 0 0.0234"><freejoint/><geom type="box" size=".0234 .0234 .0234"/></body>'
        "</worldbody></mujoco>"
    )
    sim = make("cpu", model, 2)
    sim.data("qfrc_applied")[1, :3] = torch.tensor([3.0, 1.0, -2.0])  # world 1 is pushed about
    sim.step(20)
    sim.data("qpos")[:] = sim.data("qpos")[0].clone()  # world 0 rests where it started: both rest there
    sim.data("qvel")[:] = 0.0
    sim.data("qfrc_applied")[:] = 0.0
    sim.mark_reset(torch.tensor([True, True]))
    sim.step(20)
    for name in ("qpos", "qvel"):
        assert torch.equal(sim.data(name)[0], sim.data(name)[1]), name


@pytest.mark.parametrize("kind", BACKENDS)
def test_per_world_gravity(kind: str, cartpole: mujoco.MjModel) -> None:
    sim = make(kind, cartpole, 2)
    sim.data("qpos")[:, 1] = 0.3  # tilted pole: falls under gravity
    sim.forward()
    sim.step()  # on cuda this captures the step graph before the field becomes per-world

    gravity = sim.model_field("opt.gravity")
    assert gravity.shape == (2, 3)
    np.testing.assert_allclose(gravity.cpu().numpy(), np.tile(cartpole.opt.gravity, (2, 1)))
    gravity[1] = 0.0
    sim.data("qvel")[:] = 0.0
    sim.step(20)

    hinge_vel = sim.data("qvel")[:, 1]
    assert hinge_vel[0].abs() > 0.1  # falls
    assert hinge_vel[1].abs() < 1e-6  # weightless: stays put


@pytest.mark.parametrize("kind", BACKENDS)
def test_per_world_body_mass(kind: str, cartpole: mujoco.MjModel) -> None:
    sim = make(kind, cartpole, 2)
    mass = sim.model_field("body_mass")
    assert mass.shape == (2, cartpole.nbody)
    cart = cartpole.body("cart").id
    mass[1, cart] = 4.0 * cartpole.body_mass[cart]
    sim.data("ctrl")[:] = 1.0
    sim.step(20)

    x = sim.data("qpos")[:, 0]
    assert x[0] > 1.5 * x[1] > 0  # same force, heavier cart: slower


@pytest.mark.parametrize("kind", BACKENDS)
def test_set_const_per_world(kind: str, cartpole: mujoco.MjModel) -> None:
    sim = make(kind, cartpole, 2)
    mass, subtree = sim.model_field("body_mass"), sim.model_field("body_subtreemass")
    cart, pole = cartpole.body("cart").id, cartpole.body("pole").id
    mass[1, pole] = 3.0 * cartpole.body_mass[pole]
    sim.set_const()

    expected = [cartpole.body_mass[cart] + k * cartpole.body_mass[pole] for k in (1.0, 3.0)]
    np.testing.assert_allclose(subtree[:, cart].cpu().numpy(), expected, rtol=1e-6)


@pytest.mark.parametrize("kind", BACKENDS)
def test_derived_constants_read_after_set_const(kind: str, cartpole: mujoco.MjModel) -> None:
    """The constants set_const writes can be read as per-world fields after it ran (on the CPU they
    were made per world in float64 by set_const, and reading them in float32 then failed)."""
    sim = make(kind, cartpole, 2)
    mass = sim.model_field("body_mass")
    cart, pole = cartpole.body("cart").id, cartpole.body("pole").id
    mass[1, pole] = 3.0 * cartpole.body_mass[pole]
    sim.set_const()
    subtree, invweight = sim.model_field("body_subtreemass"), sim.model_field("dof_invweight0")
    expected = [cartpole.body_mass[cart] + k * cartpole.body_mass[pole] for k in (1.0, 3.0)]
    np.testing.assert_allclose(subtree[:, cart].cpu().numpy(), expected, rtol=1e-6)
    assert invweight.dtype == torch.float32 and invweight.shape[0] == 2


@pytest.mark.parametrize("kind", BACKENDS)
def test_unknown_field_names(kind: str, cartpole: mujoco.MjModel) -> None:
    sim = make(kind, cartpole, 2)
    with pytest.raises(ValueError, match="no_such_field"):
        sim.data("no_such_field")
    with pytest.raises(ValueError, match="no_such_field"):
        sim.model_field("no_such_field")
    with pytest.raises(ValueError, match="no_such_field"):
        sim.model_field("opt.no_such_field")


def test_make_backend_rejects_unknown_device(cartpole: mujoco.MjModel) -> None:
    with pytest.raises(ValueError, match="'cpu', 'cuda' or 'cuda:N'"):
        make_backend(cartpole, 2, "tpu")
    assert isinstance(make_backend(cartpole, 2, "cpu"), CpuBackend)


@pytest.mark.skipif(CUDA_SKIP is None, reason="the cuda backend is available here")
def test_cuda_unavailable_is_a_clear_error(cartpole: mujoco.MjModel) -> None:
    with pytest.raises(RuntimeError, match=r'pip install "simlab\[gpu\]"'):
        make_backend(cartpole, 2, "cuda")


@pytest.mark.gpu
@needs_cuda
def test_cpu_cuda_parity(cartpole: mujoco.MjModel) -> None:
    """Same model, state and controls for 200 steps: MuJoCo C (float64) vs MuJoCo Warp (float32).

    Measured worst qpos gap over the 200 steps: 2.3e-6 on an H200, 4.8e-6 on MuJoCo Warp's CPU
    device (|qpos| up to 3.3): float32 rounding accumulated over a non-chaotic 2-s swing. The bound,
    1e-4 scaled by the magnitude, leaves a 20-40x margin for other GPUs and compilers, yet a
    semantic slip such as one substep too many or too few moves qpos by ~1e-2 and fails.
    """
    num_envs, steps = 4, 200
    cpu, gpu = make("cpu", cartpole, num_envs), make("cuda", cartpole, num_envs)
    init = torch.tensor([[0.0, 0.1], [0.2, -0.3], [-0.5, 0.8], [1.0, 3.0]])
    gen = torch.Generator().manual_seed(0)
    controls = torch.rand(steps, num_envs, 1, generator=gen) * 2 - 1
    for sim in (cpu, gpu):
        sim.data("qpos")[:] = init.to(sim.device)
        sim.forward()

    worst = 0.0
    for t in range(steps):
        for sim in (cpu, gpu):
            sim.data("ctrl")[:] = controls[t].to(sim.device)
            sim.step()
        gap = (cpu.data("qpos") - gpu.data("qpos").cpu()).abs().max().item()
        worst = max(worst, gap)
    scale = cpu.data("qpos").abs().max().item()
    print(f"parity: worst |qpos_cpu - qpos_cuda| over {steps} steps = {worst:.2e} (|qpos| <= {scale:.2f})")
    assert worst < 1e-4 * max(1.0, scale)


@pytest.mark.gpu
@needs_cuda
def test_cuda_contact_buffers_and_overflow() -> None:
    model = _spheres(4)  # 4 spheres resting on the plane: 4 contacts per world
    sim = make("cuda", model, 8)  # default buffers: enough
    sim.step(100)
    sim.check_overflow()
    assert torch.all(sim.data("qpos")[:, 2::7] < 0.11)  # the spheres rest on the plane

    small = make("cuda", model, 8, nconmax=1, overflow_check_interval=0)
    small.step(100)
    with pytest.raises(RuntimeError, match=r"raise SimulationCfg\.mujoco\.nconmax"):
        small.check_overflow()


@pytest.mark.gpu
@needs_cuda
def test_cuda_reports_its_device_memory(cartpole: mujoco.MjModel) -> None:
    small, large = make("cuda", cartpole, 16).device_memory_bytes(), make("cuda", cartpole, 256).device_memory_bytes()
    assert small >= 16 * cartpole.nq * 4  # at least the positions of every world
    assert large > small


@pytest.mark.gpu
@needs_cuda
def test_cuda_orders_with_torch_side_stream(cartpole: mujoco.MjModel) -> None:
    """Writes, steps and reads issued on a non-default torch stream see each other in order."""
    if WARP_DEVICE == "cpu":
        pytest.skip("CUDA streams only")
    runs = []
    for use_side_stream in (False, True):
        sim = make("cuda", cartpole, 64)
        ctrl, qpos = sim.data("ctrl"), sim.data("qpos")
        stream = torch.cuda.Stream() if use_side_stream else torch.cuda.current_stream()
        with torch.cuda.stream(stream):
            for t in range(50):
                ctrl.fill_(float(np.sin(0.1 * t)))  # must land before this step's replay
                sim.step()
            runs.append(qpos.clone())
        torch.cuda.synchronize()
    torch.testing.assert_close(runs[0], runs[1], rtol=0, atol=0)


def test_warp_contact_overflow_names_the_setting_on_the_cpu() -> None:
    """The GPU backend's buffer-overflow error (MuJoCo Warp on Warp's CPU device, so CI runs it):
    4 resting spheres per world against a contact buffer of 1 per world."""
    try:
        from simlab.sim.backends.cuda import CudaBackend
    except ImportError as err:
        pytest.skip(f"mujoco-warp is not installed: {err}")
    small = CudaBackend(_spheres(4), 2, device="cpu", nconmax=1, overflow_check_interval=0)
    small.step(50)
    with pytest.raises(RuntimeError, match=r"nconmax \* num_envs; raise SimulationCfg\.mujoco\.nconmax \(now 1 per"):
        small.check_overflow()


TWO_BOXES = """
<mujoco>
  <worldbody>
    <geom type="plane" size="5 5 0.1"/>
    <body name="feet" pos="0 0 0.052"><freejoint/>
      <geom type="box" size=".1 .05 .05" pos="0 -.1 0" mass="1"/>
      <geom type="box" size=".1 .05 .05" pos="0 .1 0" mass="1"/>
    </body>
  </worldbody>
  <sensor><contact body2="feet" data="force" reduce="netforce"/></sensor>
</mujoco>
"""


def test_warp_contact_sensor_slots_follow_nconmax_and_overflow_raises_on_the_cpu() -> None:
    """Each MuJoCo contact sensor keeps nconmax contacts per world (rounded up to a power of two, at most
    MuJoCo Warp's 64), and more matches than that raise instead of dropping force silently (Warp's CPU
    device). A body of two boxes lands on the plane with 8 contacts in world 0 and flies in world 1, so the
    two worlds' shared pool of 2 x 4 holds them while world 0's sensor, with 4 slots, does not."""
    try:
        from simlab.sim.backends.cuda import CudaBackend
    except ImportError as err:
        pytest.skip(f"mujoco-warp is not installed: {err}")
    model = mujoco.MjModel.from_xml_string(TWO_BOXES)
    weight = 2.0 * 9.81
    for nconmax, slots in ((8, 8), (24, 32)):
        sim = CudaBackend(model, 2, device="cpu", nconmax=nconmax, overflow_check_interval=0)
        assert sim.wp_model.opt.contact_sensor_maxmatch == slots
        sim.data("qpos")[1, 2] = 2.0  # world 1 in the air
        sim.step(100)
        sim.check_overflow()
        force = sim.data("sensordata")
        assert float(force[0, 2].abs()) == pytest.approx(weight, rel=1e-3) and float(force[1].abs().max()) == 0.0
    few = CudaBackend(model, 2, device="cpu", nconmax=4, overflow_check_interval=0)
    few.data("qpos")[1, 2] = 2.0
    few.step(100)
    with pytest.raises(RuntimeError, match=r"matched more contacts than its slots .*mujoco\.nconmax \(now 4"):
        few.check_overflow()


def test_warp_kinematics_pass_gives_the_forward_pass_body_poses_on_the_cpu() -> None:
    """Reading body poses runs MuJoCo Warp's kinematics, centre-of-mass and velocity passes only
    (Warp's CPU device, so CI runs it): bit for bit the poses and velocities a forward pass gives;
    the rest of the forward pass waits for ensure_forward."""
    try:
        from simlab.sim.backends.cuda import CudaBackend
    except ImportError as err:
        pytest.skip(f"mujoco-warp is not installed: {err}")
    sim = CudaBackend(_spheres(3), 2, device="cpu", overflow_check_interval=0)
    sim.data("qvel")[:, 0:6] = torch.tensor([0.3, 0.0, 0.0, 0.0, 2.0, 1.0])  # one sphere moving and turning
    fields = ("xpos", "xquat", "xipos", "subtree_com", "cvel")
    for _ in range(3):
        sim.step(5, forward=False)
        assert sim.kinematics_stale and sim.is_stale
        sim.ensure_kinematics()
        assert not sim.kinematics_stale and sim.is_stale  # no collision or constraints yet
        poses = {name: sim.data(name).clone() for name in fields}
        sim.ensure_forward()
        assert not sim.is_stale
        for name in fields:
            torch.testing.assert_close(sim.data(name), poses[name], rtol=0, atol=0, msg=name)
    sim.step(1, forward=False)
    calls = []
    sim._run = lambda key, body: calls.append(key)
    sim.ensure_kinematics()
    sim.ensure_kinematics()  # current: nothing runs
    sim.ensure_forward()
    assert calls == ["kinematics", "forward"]
