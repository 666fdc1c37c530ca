"""The chapter's other RFE formulations on shared kinematics, and kinematic chains.

* `transforms`: ZYX Euler angles, homogeneous matrices and their derivatives (eqs. 8.5-8.9, 8.36);
* `tree`: poses, composite-body mass matrix and velocity terms of a tree of bodies (trace form);
* `classical`: classical RFE links (section 8.1), nonlinear (eq. 8.7) or linear (eq. 8.8);
* `modified`: modified RFE links with joint coordinates (section 8.2);
* `chain`: chains of rigid and flexible links on a moving base, statics, modes, dynamics.

The absolute formulation (section 8.4) is `rfesim.model` / `rfesim.solvers`.
"""
from .chain import (
                    BaseMotion,
                    Chain,
                    ChainModel,
                    ChainResult,
                    ChainStatics,
                    Joint,
                    JointForce,
                    Prescribed,
                    accelerations,
                    chain_energy,
                    chain_modes,
                    chain_statics,
                    compile_chain,
                    equations,
                    point_motion,
                    simulate_chain,
)
from .classical import ClassicalLink, linear_matrices, linear_modes
from .links import BeamProperties, RigidLink
from .modified import ModifiedLink

__all__ = ["BaseMotion", "BeamProperties", "Chain", "ChainModel", "ChainResult", "ChainStatics", "ClassicalLink",
           "Joint", "JointForce", "ModifiedLink", "Prescribed", "RigidLink", "accelerations", "chain_energy",
           "chain_modes", "chain_statics", "compile_chain", "equations", "linear_matrices", "linear_modes",
           "point_motion", "simulate_chain"]
