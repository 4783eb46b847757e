"""Stack cubes with the Franka arm, a random pick of cubes in each env, relative end-effector poses by
differential IK (Isaac Lab's ``stack_ik_rel_instance_randomize_env_cfg.py``): the actions of
``stack_ik_rel_env_cfg.py`` on the instance-randomized scene."""

from simlab.utils import configclass

from . import stack_ik_rel_env_cfg, stack_joint_pos_instance_randomize_env_cfg


@configclass
class FrankaCubeStackInstanceRandomizeEnvCfg(
    stack_joint_pos_instance_randomize_env_cfg.FrankaCubeStackInstanceRandomizeEnvCfg
):
    def __post_init__(self):
        super().__post_init__()
        # the stiffer PD arm and the IK action of the IK-Rel stack task
        ik_rel = stack_ik_rel_env_cfg.FrankaCubeStackEnvCfg()
        self.scene.robot = ik_rel.scene.robot
        self.actions.arm_action = ik_rel.actions.arm_action
