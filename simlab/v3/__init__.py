"""Isaac Lab 3.0's conventions at simlab's boundary: code written for 3.0 imports from here.

Isaac Lab 3.0 writes quaternions ``(x, y, z, w)``; 2.x, MuJoCo and the rest of simlab ``(w, x, y, z)``.
The order is never guessed from a value: it is the order of the namespace a name comes from.

* :mod:`simlab.v3.utils.math`: the quaternion functions in (x, y, z, w);
* :mod:`simlab.v3.assets`: asset configs whose ``init_state.rot`` is (x, y, z, w), and the asset
  classes that convert them to simlab's order when built;
* :mod:`simlab.v3.sensors`: sensor configs whose ``offset.rot`` is (x, y, z, w);
* :mod:`simlab.v3.sim`: the spawners, whose ``orientation=`` is (x, y, z, w);
* :mod:`simlab.v3.scene`, :mod:`simlab.v3.envs`: the scene and env classes, which convert the 3.0
  configs they are given (``gym.register(entry_point="simlab.v3.envs:ManagerBasedRLEnv")``) and resolve
  their presets; :mod:`simlab.v3.envs.mdp`, the terms whose orientations 3.0 code gives or reads;
* :mod:`simlab.v3.robots` (and ``.<robot>``): simlab's robot configs in 3.0's convention;
* :mod:`simlab.v3.cloner`: a direct env's cloning calls, checked against the scene's layout;
* :mod:`simlab.v3.controllers`, :mod:`simlab.v3.markers`: the differential IK controller and the markers,
  whose poses are (x, y, z, w).

Every other module is simlab's own, as for 2.x code (docs/porting_3.md has the whole mapping). Code for
2.x and code for 3.0 run side by side in one process: each config class carries its order.
"""
