"""01: where NAO's right arm points for given joint angles."""

import numpy as np

from shared.robot import load_arm

arm = load_arm("right")  # the URDF, loaded with pinocchio
q = np.array([0.5, -0.3, 1.2, 0.8, 0.0])  # ShoulderPitch .. WristYaw [rad]
points = arm.fk(q)
for name, xyz in points._asdict().items():
    print(f"{name:8s} ({xyz[0]:+.4f}, {xyz[1]:+.4f}, {xyz[2]:+.4f}) m")
print(f"the wrist reaches {arm.reach[0]:.3f}..{arm.reach[1]:.3f} m from the shoulder")
