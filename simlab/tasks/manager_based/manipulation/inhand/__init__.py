"""In-hand object reorientation, manager-based (Isaac Lab's ``manager_based/manipulation/inhand``)."""
