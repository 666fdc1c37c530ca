"""Modified RFE formulation (section 8.2): joint coordinates along the beam.

A beam link of length L with n = m_p elements is divided as in the classical method
(Fig. 8.2): RFE 0 (length d/2) carries the link's joint coordinates; RFE i (i = 1..n) is
joined to RFE i-1 at SDE i by three relative rotations (phi_x, phi_y, phi_z) — torsion and
two bendings (eq. 8.37) — with the ZYX matrix of eq. 8.36.1 placed at the end of RFE i-1
(the translation l(p,i-1) of eq. 8.36.1). The frame of RFE i has its origin at SDE i
(Fig. 8.5); poses chain as T(p,i) = T(p,i-1) T~(p,i) (eq. 8.38). There is no axial or shear
flexibility. The elastic energy is V = 1/2 sum c q~^2 (eqs. 8.47-8.48) with
c = (GJ, EI_y, EI_z) / d, the forces C q~ (eq. 8.49).

The mass matrix of eq. 8.51 is dense over the chain. It is assembled by the composite-body
recursion of `tree.mass_matrix` in O(n^2) (each of the n^2/2 entries costs one 4x4 trace)
instead of the trace form per entry, O(n) bodies x O(n) matrix products each; the
velocity terms e (eq. 8.43) by one forward and one backward pass (`tree.forward_pass`,
`tree.composite_pass`), O(n). The naive trace form is the test reference.
"""
from __future__ import annotations

import numpy as np

from .links import (
    BeamProperties,
    BodySpec,
    Link,
    body_placement,
    check_dofs,
    rfe_lengths,
)
from .transforms import FIXED, SPHERICAL, pseudo_inertia

MODIFIED_DOFS = ("rx", "ry", "rz")
COORD_NAMES = ("phi_x", "phi_y", "phi_z")


class ModifiedLink(Link):
    """A flexible beam link in the modified RFE formulation (section 8.2).

    length m; elements n (= m_p); props: `BeamProperties` (EA, GA unused); dofs: the
    relative rotations that are free, a subset of ("rx", "ry", "rz") (torsion, bending
    about y, bending about z); the others are held at zero.
    """
    formulation = "modified"

    def __init__(self, length: float, elements: int, props: BeamProperties, *, dofs=None):
        self.length = float(length)
        self.elements = int(elements)
        self.props = props
        self.dofs = check_dofs(dofs, MODIFIED_DOFS)
        if "rx" in self.dofs and not props.polar > 0.0:
            raise ValueError("a free torsion coordinate ('rx' in dofs) needs polar_inertia > 0")
        self.ell = rfe_lengths(self.length, self.elements)
        self.spacing = self.length / self.elements
        self.origins = np.concatenate([[0.0], (np.arange(1, self.elements + 1) - 0.5) * self.spacing])
        self._bodies = self._build()

    def _build(self):
        d = self.spacing
        props = self.props
        c = np.array([props.GJ, props.EIy, props.EIz]) / d                  # eq. 8.48
        locked = tuple(name not in self.dofs for name in MODIFIED_DOFS)
        out = []
        for i, ell in enumerate(self.ell):
            m, J = props.element_inertia(ell)
            H = pseudo_inertia(m, (0.5 * ell, 0.0, 0.0), J)
            lo = self.origins[i]
            hi = lo + ell
            if i == 0:
                out.append(BodySpec(parent=-1, kind=FIXED, axis=np.zeros(3), placement=np.eye(4), inertia=H,
                                    undeformed=np.eye(4), s_range=(lo, hi)))
                continue
            out.append(BodySpec(parent=i - 1, kind=SPHERICAL, axis=np.zeros(3),
                                placement=body_placement(self.ell[i - 1]),              # eq. 8.36.1
                                inertia=H, undeformed=body_placement(lo), s_range=(lo, hi), locked=locked,
                                names=tuple(f"rfe{i}.{n}" for n in COORD_NAMES), stiffness=c.copy(),
                                damping=props.damping * c))
        return out

    def bodies(self):
        return self._bodies
