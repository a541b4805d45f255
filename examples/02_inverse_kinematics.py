"""02: a reach with the paper's method and with the two baselines."""

import numpy as np

from services.ik import solve
from shared.messages import Method
from shared.robot import load_arm

arm = load_arm("right")
target = np.array([0.12, -0.13, 0.05])  # wrist target, torso frame [m]
for method in Method:
    sol = solve(arm, target, method=method)  # starts from the arm hanging at rest
    angles = " ".join(f"{v:+.3f}" for v in sol.q)
    print(f"{method.value:10s} q = [{angles}] rad, error {sol.error * 1e3:.4f} mm")
