"""The planner: task in, trajectory out (wrist path, decision, IK, timing)."""
