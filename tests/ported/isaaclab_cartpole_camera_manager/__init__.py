# Isaac Lab's manager_based/classic/cartpole/cartpole_camera_env_cfg.py (release 2.x text), ported by the
# README's import mapping alone: no other line differs. Its sibling cartpole_env_cfg, which it imports
# relatively, is simlab's at the mapped path (cartpole_env_cfg.py here re-exports it).
# tests/test_cartpole_showcase.py builds and steps its RGB and depth configs.
