"""03: the ten movement primitives, their matrices and active joints."""

from shared.primitives import PRIMITIVES

for p in PRIMITIVES:
    rows = " / ".join("".join(str(v) for v in row) for row in p.matrix)
    print(
        f"{p.name:15s} e = {rows}  {p.kind.value}  joints {', '.join(p.active_joints)}"
    )
