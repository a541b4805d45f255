"""The IK's hot path on plain floats.

A 5-joint arm is small: each numpy call on a 3-vector or a 3x3 matrix costs a
few microseconds of overhead, far more than its arithmetic (measured here: a
3x3 inverse 14 us, an SVD 21 us, one pinocchio-to-numpy copy 3 us). The IK
follows a path at 100 Hz and must plan a one-second reach in a few
milliseconds, so its inner loop works on Python floats and tuples; numpy and
pinocchio stay at the boundaries and serve as the reference the tests check
this code against.
"""

from services.ik.kernel.chain import Chain, ChainState, chain_for

__all__ = ["Chain", "ChainState", "chain_for"]
