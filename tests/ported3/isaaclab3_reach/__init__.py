# Isaac Lab 3.0's isaaclab_tasks/core/reach (develop), written out under the 3.0 mapping of docs/porting_3.md.
