"""Stack three cubes, each env with its own pick of cubes (Isaac Lab's ``stack_instance_randomize_env_cfg.py``).

Each of ``cube_1``, ``cube_2`` and ``cube_3`` is a rigid object collection of candidate cubes: every
env's model holds all candidates, and a reset event (``randomize_rigid_objects_in_focus``) brings one of
each into focus per env and parks the rest out of reach. The policy group is the stack task's, its
terms reading the cubes in focus (Isaac Lab's ``instance_randomize_*`` terms). 1/100 s physics,
decimation 5, 30 s episodes, no rewards.

Beyond Isaac Lab's config (which has the policy group and the time limit only), simlab keeps the stack
task's ``subtask_terms`` group and ``success`` termination on the cubes in focus, so demonstration
tools read the same signals and the stacking criterion judges it. Scene as simlab's stack task.
"""

from dataclasses import MISSING

from simlab.assets import ArticulationCfg, RigidObjectCollectionCfg
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.sensors import FrameTransformerCfg
from simlab.utils import configclass

from . import mdp
from .stack_env_cfg import ObjectTableSceneCfg, ObservationsCfg, StackEnvCfg


@configclass
class InstanceRandomizeSceneCfg(ObjectTableSceneCfg):
    """The stack scene with each cube a collection of candidates (set by the robot's config)."""

    robot: ArticulationCfg = MISSING
    ee_frame: FrameTransformerCfg = MISSING
    cube_1: RigidObjectCollectionCfg = MISSING
    cube_2: RigidObjectCollectionCfg = MISSING
    cube_3: RigidObjectCollectionCfg = MISSING


@configclass
class InstanceRandomizeObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        actions = ObsTerm(func=mdp.last_action)
        joint_pos = ObsTerm(func=mdp.joint_pos_rel)
        joint_vel = ObsTerm(func=mdp.joint_vel_rel)
        object = ObsTerm(func=mdp.instance_randomize_object_obs)
        cube_positions = ObsTerm(func=mdp.instance_randomize_cube_positions_in_world_frame)
        cube_orientations = ObsTerm(func=mdp.instance_randomize_cube_orientations_in_world_frame)
        eef_pos = ObsTerm(func=mdp.ee_frame_pos)
        eef_quat = ObsTerm(func=mdp.ee_frame_quat)
        gripper_pos = ObsTerm(func=mdp.gripper_pos)

        def __post_init__(self):
            self.enable_corruption = False
            self.concatenate_terms = False

    policy: PolicyCfg = PolicyCfg()
    subtask_terms: ObservationsCfg.SubtaskCfg = ObservationsCfg.SubtaskCfg()


@configclass
class InstanceRandomizeTerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)
    success = DoneTerm(func=mdp.cubes_stacked)


@configclass
class StackInstanceRandomizeEnvCfg(StackEnvCfg):
    scene: InstanceRandomizeSceneCfg = InstanceRandomizeSceneCfg(
        num_envs=4096, env_spacing=2.5, replicate_physics=False
    )
    observations: InstanceRandomizeObservationsCfg = InstanceRandomizeObservationsCfg()
    terminations: InstanceRandomizeTerminationsCfg = InstanceRandomizeTerminationsCfg()

    def __post_init__(self):
        super().__post_init__()
        self.sim.render_interval = self.decimation
