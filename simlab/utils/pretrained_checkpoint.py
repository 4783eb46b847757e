"""Isaac Lab's pretrained-checkpoint lookup over the policies simlab ships (``simlab/pretrained/``).

Isaac Lab's play scripts call ``get_published_pretrained_checkpoint(workflow, task)``, which fetches
NVIDIA's published checkpoint from Nucleus. Here it returns the checkpoint of the policy trained for
simlab and shipped with it, or None (saying so) when there is none. Task ids may be Isaac Lab's
(``Isaac-Cartpole-v0``) or simlab's (``simlab/Cartpole-v0``); a ``-Play`` variant gets its task's.
"""

from __future__ import annotations

from simlab.utils.string import simlab_task_id

WORKFLOWS = ["rl_games", "rsl_rl", "sb3", "skrl"]
"""The RL libraries ("workflows") with scripts in ``scripts/reinforcement_learning/``."""
WORKFLOW_TRAINER = {w: f"scripts/reinforcement_learning/{w}/train.py" for w in WORKFLOWS}
WORKFLOW_PLAYER = {w: f"scripts/reinforcement_learning/{w}/play.py" for w in WORKFLOWS}


def get_published_pretrained_checkpoint_path(workflow: str, task_name: str) -> str:
    """The folder of the shipped policy (raises, listing what is shipped, when there is none)."""
    from simlab.pretrained import pretrained_run_dir

    if workflow not in WORKFLOWS:
        raise ValueError(f"Unknown workflow '{workflow}'; one of {WORKFLOWS}.")
    return pretrained_run_dir(simlab_task_id(task_name), workflow)


def get_published_pretrained_checkpoint(workflow: str, task_name: str) -> str | None:
    """The checkpoint file of the policy simlab ships for ``task_name`` trained with ``workflow``, or None.

    As Isaac Lab's download does, it is written under ``.pretrained_checkpoints/`` in the working
    folder (where the play scripts export it), from the weights stored in the package."""
    from simlab.pretrained import unpack_pretrained_checkpoint

    try:
        get_published_pretrained_checkpoint_path(workflow, task_name)
    except FileNotFoundError as error:
        print(f"A pre-trained checkpoint is currently unavailable for this task. {error}")
        return None
    # the file written from the package's weights (never another one found in that folder)
    return unpack_pretrained_checkpoint(simlab_task_id(task_name), workflow, ".pretrained_checkpoints")


def has_pretrained_checkpoint(workflow: str, task_name: str) -> bool:
    """Whether simlab ships a ``workflow`` policy for ``task_name``."""
    try:
        get_published_pretrained_checkpoint_path(workflow, task_name)
    except FileNotFoundError:
        return False
    return True
