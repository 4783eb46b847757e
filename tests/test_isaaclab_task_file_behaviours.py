"""What Isaac Lab's own task files needed of simlab (tests/test_isaaclab_task_files.py runs the files):
each behaviour as Isaac Lab has it, on small configs written here."""

from __future__ import annotations

import io

import numpy as np
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.assets import RigidObjectCfg
from simlab.envs import ManagerBasedRLEnv
from simlab.managers import ActionTerm, ManagerTermBase, ObservationGroupCfg, SceneEntityCfg
from simlab.managers import RewardTermCfg as RewTerm
from simlab.markers import GREEN_ARROW_X_MARKER_CFG, VisualizationMarkers
from simlab.sim import SimulationCfg
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.utils import configclass
from simlab.utils.assets import ISAACLAB_NUCLEUS_DIR, check_file_path, read_file
from simlab.utils.errors import ConfigError

N = 2


def cartpole_cfg():
    cfg = parse_env_cfg("simlab/Cartpole-v0", device="cpu", num_envs=N)
    cfg.seed = 0
    return cfg


class scaled_cart_speed(ManagerTermBase):  # noqa: N801 - a term class reads like a function, as in Isaac Lab
    """Like Isaac Lab's power_consumption: its __init__ fills in the asset_cfg the config leaves out."""

    def __init__(self, cfg, env):
        super().__init__(cfg, env)
        cfg.params.setdefault("asset_cfg", SceneEntityCfg("robot", joint_names=["slider_to_cart"]))

    def __call__(self, env, scale: float, asset_cfg: SceneEntityCfg) -> torch.Tensor:
        return scale * env.scene[asset_cfg.name].data.joint_vel[:, asset_cfg.joint_ids].abs().sum(dim=1)


class needs_a_gain(ManagerTermBase):  # noqa: N801
    def __call__(self, env, gain: float) -> torch.Tensor:
        return torch.zeros(env.num_envs, device=env.device)


def test_a_class_term_may_fill_in_its_parameters_when_built():
    cfg = cartpole_cfg()
    cfg.rewards.cart_speed = RewTerm(func=scaled_cart_speed, weight=1.0, params={"scale": 2.0})
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        env.scene["robot"].write_joint_state_to_sim(torch.tensor([[0.0, 0.0]] * N), torch.tensor([[0.5, 0.0]] * N))
        term = env.reward_manager.get_term_cfg("cart_speed")
        assert term.params["asset_cfg"].joint_ids == [0]  # added by the class, resolved like the config's
        value = term.func(env, **term.params)
        torch.testing.assert_close(value, torch.full((N,), 1.0))
    finally:
        env.close()


def test_a_class_term_still_missing_a_parameter_once_built_is_refused():
    cfg = cartpole_cfg()
    cfg.rewards.broken = RewTerm(func=needs_a_gain, weight=1.0)
    with pytest.raises(ConfigError, match=r"term 'broken'.*needs_a_gain needs parameter\(s\) \['gain'\]"):
        ManagerBasedRLEnv(cfg)


def test_an_empty_group_kept_as_a_dict_observes_nothing_and_an_empty_concatenated_one_is_refused():
    cfg = cartpole_cfg()

    @configclass
    class ImagesCfg(ObservationGroupCfg):  # Isaac Lab's stack task declares such a group for its cameras
        def __post_init__(self):
            self.concatenate_terms = False

    cfg.observations.rgb_camera = ImagesCfg()
    env = ManagerBasedRLEnv(cfg)
    try:
        obs, _ = env.reset()
        assert obs["rgb_camera"] == {} and obs["policy"].shape == (N, 4)
        obs, *_ = env.step(torch.zeros(N, 1))
        assert obs["rgb_camera"] == {}
    finally:
        env.close()
    cfg = cartpole_cfg()
    cfg.observations.empty = ObservationGroupCfg()
    with pytest.raises(ValueError, match="group 'empty' has no terms to concatenate.*concatenate_terms=False"):
        ManagerBasedRLEnv(cfg)


def test_an_entity_a_config_adds_in_post_init_is_in_the_scene():
    """Isaac Lab's stack config sets scene.cube_1 ... in __post_init__, undeclared in its scene class."""
    import simlab.sim as sim_utils

    cfg = cartpole_cfg()
    cfg.scene.box = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Box",
        spawn=sim_utils.CuboidCfg(
            size=(0.1, 0.1, 0.1),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(),
            mass_props=sim_utils.MassPropertiesCfg(mass=0.1),
            collision_props=sim_utils.CollisionPropertiesCfg(),
        ),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(1.0, 1.0, 0.05)),
    )
    assert "box" not in type(cfg.scene).__dataclass_fields__
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        assert "box" in env.scene.rigid_objects
        origin = env.scene.env_origins
        torch.testing.assert_close(env.scene["box"].data.root_pos_w[:, :2] - origin[:, :2], torch.ones(N, 2))
    finally:
        env.close()


def test_a_command_term_resamples_by_ids_as_isaac_labs_terms_call_it():
    cfg = parse_env_cfg("simlab/Reach-Franka-v0", device="cpu", num_envs=N)
    cfg.seed = 0
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        term = env.command_manager.get_term("ee_pose")
        before = term.command.clone()
        term._resample(torch.tensor([1]))  # Isaac Lab's in-hand goal term resamples the envs that succeeded
        after = term.command
        torch.testing.assert_close(after[0], before[0])
        assert not torch.allclose(after[1], before[1])
        assert int(term.command_counter[1]) == int(term.command_counter[0]) + 1
    finally:
        env.close()


class ArrowAction(ActionTerm):
    """A joint-effort action that draws an arrow above each cart, the way Isaac Lab's navigation action does."""

    def __init__(self, cfg, env):
        super().__init__(cfg, env)
        self._raw = torch.zeros(env.num_envs, 1)

    action_dim = 1

    @property
    def raw_actions(self):
        return self._raw

    @property
    def processed_actions(self):
        return self._raw

    def process_actions(self, actions):
        self._raw[:] = actions

    def apply_actions(self):
        self._asset.set_joint_effort_target(self._raw, joint_ids=[0])

    def _set_debug_vis_impl(self, debug_vis: bool):
        if debug_vis and not hasattr(self, "arrows"):
            self.arrows = VisualizationMarkers(GREEN_ARROW_X_MARKER_CFG.replace(prim_path="/Visuals/Actions/arrow"))
        if hasattr(self, "arrows"):
            self.arrows.set_visibility(debug_vis)

    def _debug_vis_callback(self, event):
        self.arrows.visualize(translations=self._asset.data.root_pos_w + torch.tensor([0.0, 0.0, 1.0]))


def test_an_action_term_that_draws_itself_takes_debug_vis_and_one_that_does_not_is_refused():
    from simlab.managers import ActionTermCfg

    cfg = cartpole_cfg()
    cfg.actions.joint_effort = ActionTermCfg(class_type=ArrowAction, asset_name="robot", debug_vis=True)
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        assert env.action_manager.has_debug_vis_implementation
        term = env.action_manager.get_term("joint_effort")
        term._draw_debug_vis()  # what a rendered frame calls
        assert term.arrows._translations.shape == (N, 3)
    finally:
        env.close()
    cfg = cartpole_cfg()
    cfg.actions.joint_effort.debug_vis = True
    with pytest.raises(ConfigError, match=r"JointEffortActionCfg.debug_vis=True .*JointEffortAction draws no debug"):
        ManagerBasedRLEnv(cfg)


def test_every_config_class_has_a_post_init_to_call():
    @configclass
    class RunnerCfg:  # Isaac Lab's agent configs: Flat(Rough) calls super().__post_init__(), Rough has none
        iterations: int = 1500

    @configclass
    class FlatRunnerCfg(RunnerCfg):
        def __post_init__(self):
            super().__post_init__()
            self.iterations = 300

    assert FlatRunnerCfg().iterations == 300 and RunnerCfg().iterations == 1500


def test_isaac_lab_2_0s_disable_contact_processing_is_accepted():
    assert SimulationCfg(disable_contact_processing=True).disable_contact_processing


def test_isaac_labs_blind_anymal_c_policy_file_reads_as_torchscript_of_simlabs_policy():
    from simlab.tasks.manager_based.navigation.mdp import PreTrainedPolicyActionCfg
    from simlab.tasks.manager_based.navigation.mdp.pre_trained_policy_action import load_policy

    path = f"{ISAACLAB_NUCLEUS_DIR}/Policies/ANYmal-C/Blind/policy.pt"
    assert check_file_path(path) == 2  # Isaac Lab's answer for a Nucleus file
    scripted = torch.jit.load(read_file(path))  # what Isaac Lab's own navigation action does
    ours = load_policy(PreTrainedPolicyActionCfg(asset_name="robot", policy_path=path), "cpu")
    obs = torch.randn(4, 48, generator=torch.Generator().manual_seed(0))
    torch.testing.assert_close(scripted(obs), ours(obs))
    # a frozen policy: its output takes no gradient, so Isaac Lab's action term, which writes it into its
    # buffers, steps outside torch.inference_mode too (simlab's action terms write with out=)
    assert not scripted(obs).requires_grad
    # any other Nucleus file stays unreadable
    assert check_file_path(f"{ISAACLAB_NUCLEUS_DIR}/Policies/ANYmal-D/Blind/policy.pt") == 0
    with pytest.raises(FileNotFoundError, match="Nucleus"):
        read_file(f"{ISAACLAB_NUCLEUS_DIR}/Policies/ANYmal-D/Blind/policy.pt")
    assert isinstance(read_file(path), io.BytesIO)


def test_isaac_labs_height_scan_anymal_c_policy_reads_as_torchscript_of_simlabs_rough_policy(tmp_path):
    """Isaac Lab's quadruped tutorial (``create_quadruped_base_env.py``) reads ``Policies/ANYmal-C/HeightScan/
    policy.pt`` with ``read_file`` and ``torch.jit.load``, importing no task package (a fresh process here):
    the file is simlab's shipped rough ANYmal-C policy, 235 observations (height scan last) to 12 actions."""
    import subprocess
    import sys

    from simlab.pretrained import POLICY_FILE, pretrained_run_dir
    from simlab.tasks.manager_based.navigation.mdp import PreTrainedPolicyActionCfg
    from simlab.tasks.manager_based.navigation.mdp.pre_trained_policy_action import load_policy

    path = f"{ISAACLAB_NUCLEUS_DIR}/Policies/ANYmal-C/HeightScan/policy.pt"
    obs = torch.randn(4, 235, generator=torch.Generator().manual_seed(0))
    torch.save(obs, tmp_path / "obs.pt")
    script = (
        "import sys, torch\n"
        "from simlab.utils.assets import check_file_path, read_file\n"
        f"assert check_file_path({path!r}) == 2\n"
        f"policy = torch.jit.load(read_file({path!r})).eval()\n"
        f"torch.save(policy(torch.load({str(tmp_path / 'obs.pt')!r})), {str(tmp_path / 'act.pt')!r})\n"
        "assert 'simlab.tasks' not in sys.modules\n"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr[-2000:]
    shipped = pretrained_run_dir("simlab/Velocity-Rough-Anymal-C-v0", "rsl_rl") + "/" + POLICY_FILE
    ours = load_policy(PreTrainedPolicyActionCfg(asset_name="robot", policy_path=shipped), "cpu")
    torch.testing.assert_close(torch.load(tmp_path / "act.pt"), ours(obs))


@pytest.mark.parametrize("given", [None, 100.0])
def test_implicit_gains_left_none_are_the_robot_files_own(given):
    """Isaac Lab's AMP humanoid keeps its USD's drive gains (stiffness=None); simlab's MJCF of it has
    them as the joints' stiffness and damping, which then drive the joint instead of springing it."""
    import simlab.sim as sim_utils
    from simlab.actuators import ImplicitActuatorCfg
    from simlab.robots import HUMANOID_28_CFG
    from simlab.scene import InteractiveScene, InteractiveSceneCfg

    actuators = {"body": ImplicitActuatorCfg(joint_names_expr=[".*"], stiffness=given, damping=given)}
    scene_cfg = InteractiveSceneCfg(num_envs=1, env_spacing=2.0)
    scene_cfg.robot = HUMANOID_28_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot", actuators=actuators)
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.01, device="cpu"))
    scene = InteractiveScene(scene_cfg)
    sim.reset()
    robot = scene["robot"]
    ids, names = robot.find_joints(["abdomen_x", "neck_y", "right_elbow", "left_ankle_z"])
    kp, kd = robot.data.default_joint_stiffness[0, ids], robot.data.default_joint_damping[0, ids]
    model = sim.model
    springs = [float(model.jnt_stiffness[model.joint(robot.prefix + n).id]) for n in names]
    dampers = [float(model.dof_damping[model.jnt_dofadr[model.joint(robot.prefix + n).id]]) for n in names]
    if given is None:  # the file's 600/60, 50/5, 150/15, 200/20 drive the joints; no passive spring is left
        torch.testing.assert_close(kp, torch.tensor([600.0, 50.0, 150.0, 200.0]))
        torch.testing.assert_close(kd, torch.tensor([60.0, 5.0, 15.0, 20.0]))
        assert springs == [0.0] * 4 and dampers == [0.0] * 4
    else:  # given gains drive; the file's springs stay as they are
        torch.testing.assert_close(kp, torch.full((4,), given))
        assert springs == [600.0, 50.0, 150.0, 200.0] and dampers == [60.0, 5.0, 15.0, 20.0]
    # the joint's MuJoCo actuator is the drive with those gains
    bias = [model.actuator(robot.prefix + n).biasprm[1:3] for n in names]
    torch.testing.assert_close(torch.tensor(np.array(bias), dtype=torch.float32), -torch.stack([kp, kd], dim=1))
    assert len(robot.data.body_names) == 15 and robot.num_joints == 28
