"""Navigation tasks (Isaac Lab's ``isaaclab_tasks.manager_based.navigation``): a high-level policy
steers a frozen low-level locomotion policy to a goal pose."""

from simlab.utils.assets import register_nucleus_file

ISAACLAB_POLICY_FILES = ("Policies/ANYmal-C/Blind/policy.pt",)
"""Isaac Lab's pre-trained policies under ``ISAACLAB_NUCLEUS_DIR`` that ``read_file`` gives as TorchScript
made from simlab's shipped weights (``mdp.pre_trained_policy_action.ISAACLAB_POLICIES`` says which), so
Isaac Lab's own navigation action term loads one as it does its file."""


def _policy_file(isaac_path: str):
    def make() -> bytes:
        from .mdp.pre_trained_policy_action import torchscript_policy  # torch and the managers, when read

        return torchscript_policy(isaac_path)

    return make


for _path in ISAACLAB_POLICY_FILES:
    register_nucleus_file(_path, _policy_file(_path))
