"""The Bayesian network of the motion decision: its nodes and arrows.

The paper prints the network (Fig. 5) without its arrows. This one follows
the arm's serial chain, shoulder -> elbow -> wrist (Fig. 1), with each node's
two attributes (Fig. 2) as that node's variables, and adds the primitive:

    M -> S, M -> E, M -> W      the primitive moving the arm (8 states, one
                                per motion primitive the demonstrations show)
                                shapes every node;
    S = (S_R)                   the shoulder: its rotation only (it does not
                                move, Section II.A);
    S_R -> E = (E_P, E_R)       the shoulder's rotation carries the elbow
                                (R_former => P_latter, extraction form 5);
    E_R -> W = (W_P, W_R)       the elbow's rotation moves the wrist, and the
                                forearm's roll is the wrist's orientation
                                relative to the elbow;
    M_prev -> M                 the primitive before (Fig. 3: primitives
                                follow each other in series).

The factorisation (eq. 4) is

    P(m, z | m_prev) = P(m | m_prev) P(s_r | m) P(e_p, e_r | s_r, m)
                       P(w_p, w_r | e_r, m),

with z the five variables' states. Each conditional is a table learned from
the demonstrations by counting (``conditionals``).
"""

from __future__ import annotations

from services.fit.variables import E_P, E_R, S_R, VARIABLES, W_P, W_R

#: The nodes along the chain: (node, its variables, the variable it hangs on).
NODES: tuple[tuple[str, tuple[int, ...], int | None], ...] = (
    ("shoulder", (S_R,), None),
    ("elbow", (E_P, E_R), S_R),
    ("wrist", (W_P, W_R), E_R),
)


def describe() -> list[str]:
    """One line per arrow of the network, for documentation and the CLI."""
    lines = ["M_prev -> M"]
    for name, variables, parent in NODES:
        names = ", ".join(VARIABLES[v] for v in variables)
        lines.append(f"M -> {name} ({names})")
        if parent is not None:
            lines.append(f"{VARIABLES[parent]} -> {name} ({names})")
    return lines
