"""In-hand reorientation env shared by the hand tasks (Isaac Lab's ``direct/inhand_manipulation``)."""
