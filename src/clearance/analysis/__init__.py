"""Analysis above the dynamics: assembly (position analysis), velocity and acceleration
analysis, the rank check (physics.md e.1, c.5) and inverse kinematics from platform
trajectories (physics.md e.2)."""
