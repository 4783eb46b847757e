"""The navigation tasks' MDP terms: simlab's term library, the pre-trained-policy action and the
pose-tracking rewards (Isaac Lab's ``navigation.mdp``)."""

from simlab.envs.mdp import *  # noqa: F403

from .pre_trained_policy_action import PreTrainedPolicyAction  # noqa: F401
from .pre_trained_policy_action_cfg import PreTrainedPolicyActionCfg  # noqa: F401
from .rewards import heading_command_error_abs, position_command_error_tanh  # noqa: F401
