"""Config of the pre-trained-policy action term (Isaac Lab's ``PreTrainedPolicyActionCfg``)."""

from dataclasses import MISSING

from simlab.managers import ActionTermCfg, ObservationGroupCfg
from simlab.utils import configclass

from .pre_trained_policy_action import PreTrainedPolicyAction


@configclass
class PreTrainedPolicyActionCfg(ActionTermCfg):
    class_type: type = PreTrainedPolicyAction
    asset_name: str = MISSING
    policy_path: str = MISSING
    """The low-level policy's weights (see :mod:`.pre_trained_policy_action` for the forms read)."""
    low_level_decimation: int = 4
    """Physics steps per low-level policy step (a divisor of the env's decimation)."""
    low_level_actions: ActionTermCfg = MISSING
    """The action term the low-level policy drives (its task's, e.g. joint position targets)."""
    low_level_observations: ObservationGroupCfg = MISSING
    """The observation group the low-level policy was trained with, in its order."""
    policy_activation: str = "elu"
    """Activation between the layers of a policy read as weights (rsl_rl's ``activation``)."""
    trust_policy_file: bool = False
    """Load a TorchScript file or a full pickle as Isaac Lab does (it may run code from the file)."""
    debug_vis: bool = False
    """simlab's action terms draw no debug visualization (Isaac Lab's default here is True)."""
