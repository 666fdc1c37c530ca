"""Frozen model arrays, mutable workspace and attachment kinematics passed to the kernels.

Shapes and units are written where each field is declared. ``n`` is the number of RFEs
of the whole scene (all lines back to back), ``nsde`` the number of SDEs, ``nload`` the
number of point loads, ``natt`` the number of attachments (0 is the fixed global frame,
then one per vessel).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

KIND_FREE = 0      # 6 coordinates: position of the centre and ZYX angles from R0
KIND_PINNED = 1    # 3 coordinates: ZYX angles; the end point follows its attachment
KIND_CLAMPED = 2   # no coordinates: the pose follows its attachment


class KernelModel(NamedTuple):
    # --- RFEs (secondary division, Fig. 8.2b)
    rfe_mass: np.ndarray            # (n,) kg
    rfe_inertia: np.ndarray         # (n, 3) kg*m^2, principal inertia about the centre, body axes x (along), y, z
    rfe_length: np.ndarray          # (n,) m
    rfe_kind: np.ndarray            # (n,) int64, KIND_FREE | KIND_PINNED | KIND_CLAMPED
    rfe_attach: np.ndarray          # (n,) int64, attachment index for pinned/clamped RFEs, -1 otherwise
    rfe_attach_offset: np.ndarray   # (n, 3) m, the attached end point in the attachment frame
    rfe_pin_arm: np.ndarray         # (n, 3) m, body-frame vector from the centre to the attached end point
    rfe_clamp_R: np.ndarray         # (n, 3, 3) orientation of a clamped RFE in its attachment frame
    rfe_diameter: np.ndarray        # (n,) m, hydrodynamic outer diameter (0: no sea loads)
    rfe_disp_area: np.ndarray       # (n,) m^2, displaced area per unit length (buoyancy, added mass)
    rfe_cdn: np.ndarray             # (n,) normal drag coefficient
    rfe_cdt: np.ndarray             # (n,) axial drag coefficient
    rfe_can: np.ndarray             # (n,) normal added-mass coefficient
    rfe_cat: np.ndarray             # (n,) axial added-mass coefficient
    rfe_contact_radius: np.ndarray  # (n,) m, seabed contact radius (outer radius)
    rfe_seabed_c: np.ndarray        # (n,) N*s/m/m, seabed normal damping per unit length
    rfe_seabed_ct: np.ndarray       # (n,) N*s/m/m, damping of the seabed friction's stick spring per unit length
    # --- SDEs (primary division, eqs. 8.86-8.89)
    sde_left: np.ndarray            # (nsde,) int64, RFE i-1
    sde_right: np.ndarray           # (nsde,) int64, RFE i
    sde_arm_left: np.ndarray        # (nsde, 3) m, body vector from centre of RFE i-1 to its right end (8.76)
    sde_arm_right: np.ndarray       # (nsde, 3) m, body vector from centre of RFE i to its left end (8.79)
    sde_stiffness: np.ndarray       # (nsde, 6) N/m x3, N*m/rad x3: [axial, shear y, shear z, torsion, bend y, bend z]
    sde_damping: np.ndarray         # (nsde, 6) N*s/m x3, N*m*s/rad x3
    sde_length: np.ndarray          # (nsde,) m, primary element length Delta
    # --- point loads (eq. 8.93)
    load_rfe: np.ndarray            # (nload,) int64
    load_arm: np.ndarray            # (nload, 3) m, body vector from the RFE centre to the point of application
    load_force: np.ndarray          # (nload, 3) N
    load_moment: np.ndarray         # (nload, 3) N*m
    load_local: np.ndarray          # (nload,) int64, 1: given in the RFE frame (follower)
    # --- rollers of supports (rfesim.loads.rollers); nr = 0 without supports
    roller_attach: np.ndarray       # (nr,) int64, attachment index (0: fixed)
    roller_point: np.ndarray        # (nr, 3) m, centre of the roller's contact line in the attachment frame
    roller_axis: np.ndarray         # (nr, 3) unit roller axis in the attachment frame
    roller_half_width: np.ndarray   # (nr,) m, half length of the contact line
    roller_radius: np.ndarray       # (nr,) m
    roller_k: np.ndarray            # (nr,) N/m, contact stiffness
    roller_c: np.ndarray            # (nr,) N*s/m, contact damping
    roller_mu: np.ndarray           # (nr,) friction coefficient along the roller axis
    roller_kt: np.ndarray           # (nr,) N/m, stick-spring stiffness of the friction
    roller_onset: np.ndarray        # (nr,) m, depth over which the contact force ramps in (0: sharp)
    roller_lo: np.ndarray           # (nr,) int64, first RFE of the roller's line
    roller_hi: np.ndarray           # (nr,) int64, one past its last RFE
    # --- environment
    gravity: float                  # m/s^2
    water_density: float            # kg/m^3
    water_level: float              # m, z of the still surface
    seabed_z: float                 # m, seabed z under the global origin
    seabed_k: float                 # N/m/m, normal stiffness per unit length
    bed_s: np.ndarray               # (np,) m, seabed profile distances along bed_dir (a plane: 2 points)
    bed_z: np.ndarray               # (np,) m, seabed z at those distances
    bed_dir: np.ndarray             # (2,) horizontal unit direction of the profile axis
    seabed_mu: np.ndarray           # (2,) friction coefficients [axial, lateral]
    seabed_kt: float                # N/m/m, stick-spring stiffness per unit length in contact
    # --- what the scene contains (a term it does not contain costs nothing)
    has_water: bool
    has_morison: bool
    has_seabed: bool
    has_loads: bool
    has_friction: bool
    has_rollers: bool
    has_roller_friction: bool
    sde_plastic: np.ndarray         # (nsde,) int64, 1: elasto-plastic bending (section 8.4.2)
    plastic_params: np.ndarray      # (nsde, np) rows of rfesim.materials.sde_plastic.plastic_bending_into
    has_plastic: bool
    # --- tensioners (rfesim.loads.tensioner), one row per tensioner
    tens_att: np.ndarray            # (nt,) int64 attachment
    tens_point: np.ndarray          # (nt, 3) m, track entry in the attachment frame
    tens_axis: np.ndarray           # (nt, 3) unit payout direction in the attachment frame
    tens_length: np.ndarray         # (nt,) m
    tens_kl: np.ndarray             # (nt,) N/m/m, lateral pad stiffness
    tens_kg: np.ndarray             # (nt,) N/m/m, axial grip stiffness
    tens_cap: np.ndarray            # (nt,) N, grip capacity
    tens_line_lo: np.ndarray        # (nt,) int64, RFE range of the held line
    tens_line_hi: np.ndarray        # (nt,) int64
    tens_mode: np.ndarray           # (nt,) int64: 0 payout table, 1 constant tension
    tens_table_t: np.ndarray        # (nt, K) s
    tens_table_d: np.ndarray        # (nt, K) m
    tens_table_v: np.ndarray        # (nt, K) m/s, monotone cubic slopes at the rows
    tens_count: np.ndarray          # (nt,) int64 rows of the table
    tens_set: np.ndarray            # (nt,) N, set tension
    tens_band: np.ndarray           # (nt,) N, dead band
    tens_gain: np.ndarray           # (nt,) N*s/m
    tens_vmax: np.ndarray           # (nt,) m/s
    has_tensioners: bool
    has_sea: bool                   # waves or current: water kinematics evaluated at the RFEs
    sea: object                     # rfesim.sea.kernel.SeaSpec (wave components, current profile)
    sea_still: object               # the same without waves (statics: still water plus current)
    # --- ropes and rigid bodies (rfesim.loads.tension_only, rfesim.loads.bodies); nb = number of bodies
    sde_tension_only: np.ndarray = np.zeros(0, np.int64)   # (nsde,) int64, 1: axial force max(0, .) (a rope)
    has_tension_only: bool = False
    body_rfe: np.ndarray = np.zeros(0, np.int64)     # (nb,) int64, the RFE that is the body
    body_volume: np.ndarray = np.zeros(0)            # (nb,) m^3, displaced volume fully submerged
    body_height: np.ndarray = np.zeros(0)            # (nb,) m, vertical extent (submerged fraction)
    body_cob: np.ndarray = np.zeros((0, 3))          # (nb, 3) m, centre of buoyancy from the centre, body axes
    body_box: np.ndarray = np.zeros((0, 3))          # (nb, 3) m, half-sizes of a box body about the centre of
    #                                                  buoyancy, body axes (zeros: no box, body_height's model)
    body_drag: np.ndarray = np.zeros((0, 3))         # (nb, 3) m^2, cd * projected area per body axis
    body_added_mass: np.ndarray = np.zeros((0, 3))   # (nb, 3) kg, added mass per body axis, fully submerged
    body_added_inertia: np.ndarray = np.zeros((0, 3))  # (nb, 3) kg*m^2, added rotational inertia, body axes
    body_slam: np.ndarray = np.zeros(0)              # (nb,) m^2, slamming coefficient * slamming area
    has_bodies: bool = False
    body_deck_att: np.ndarray = np.zeros(0, np.int64)  # (nb,) int64, attachment whose deck carries the body, -1: none
    body_deck_z: np.ndarray = np.zeros(0)            # (nb,) m, deck level in the attachment frame
    body_deck_corner: np.ndarray = np.zeros((0, 4, 3))  # (nb, 4, 3) m, corners of the footprint (body frame)
    body_deck_k: np.ndarray = np.zeros(0)            # (nb,) N/m, contact stiffness
    body_deck_c: np.ndarray = np.zeros(0)            # (nb,) N*s/m, contact damping
    body_deck_mu: np.ndarray = np.zeros(0)           # (nb,) friction coefficient
    body_deck_anchor: np.ndarray = np.zeros((0, 4, 3))  # (nb, 4, 3) m, statics: the corners at the initial state (vessel frame)
    has_deck: bool = False                           # rfesim.loads.deck
    # --- reels (rfesim.loads.reel), one row per reel; nl = number of reels
    reel_att: np.ndarray = np.zeros(0, np.int64)     # (nl,) int64 attachment
    reel_centre: np.ndarray = np.zeros((0, 3))       # (nl, 3) m, drum centre in the attachment frame
    reel_axis: np.ndarray = np.zeros((0, 3))         # (nl, 3) unit drum axis in the attachment frame
    reel_dir: np.ndarray = np.zeros((0, 3))          # (nl, 3) unit payout direction at the take-off
    reel_radius: np.ndarray = np.zeros(0)            # (nl,) m, radius of the pipe axis on the drum
    reel_wrap: np.ndarray = np.zeros(0)              # (nl,) rad, wrap window from the take-off
    reel_kr: np.ndarray = np.zeros(0)                # (nl,) N/m/m, radial contact stiffness
    reel_kl: np.ndarray = np.zeros(0)                # (nl,) N/m/m, lateral (flange) stiffness
    reel_kg: np.ndarray = np.zeros(0)                # (nl,) N/m/m, tangential grip stiffness
    reel_cap: np.ndarray = np.zeros(0)               # (nl,) N, grip capacity
    reel_line_lo: np.ndarray = np.zeros(0, np.int64)  # (nl,) int64, RFE range of the stored line
    reel_line_hi: np.ndarray = np.zeros(0, np.int64)  # (nl,) int64
    reel_mode: np.ndarray = np.zeros(0, np.int64)    # (nl,) int64: 0 payout table, 1 constant tension
    reel_table_t: np.ndarray = np.zeros((0, 2))      # (nl, K) s
    reel_table_d: np.ndarray = np.zeros((0, 2))      # (nl, K) m
    reel_table_v: np.ndarray = np.zeros((0, 2))      # (nl, K) m/s
    reel_count: np.ndarray = np.zeros(0, np.int64)   # (nl,) int64 rows of the table
    reel_set: np.ndarray = np.zeros(0)               # (nl,) N, set tension
    reel_band: np.ndarray = np.zeros(0)              # (nl,) N, dead band
    reel_gain: np.ndarray = np.ones(0)               # (nl,) N*s/m
    reel_vmax: np.ndarray = np.zeros(0)              # (nl,) m/s
    has_reels: bool = False
    # --- rest rotations and drives of SDEs (joints between lines, rfesim.loads.drives);
    # zero-size defaults mean "every SDE straight at rest" (build them with ``joint_arrays``)
    sde_rest: np.ndarray = np.zeros((0, 3, 3))       # (nsde, 3, 3) rest rotation R0: R_a* = R_a R0 (identity: none)
    sde_has_rest: np.ndarray = np.zeros(0, np.int64)  # (nsde,) int64: 0 identity, 1 constant R0, 2 driven R0(t)
    drive_sde: np.ndarray = np.zeros(0, np.int64)    # (nd,) int64, SDE of each drive (rows of one SDE consecutive)
    drive_axis: np.ndarray = np.zeros((0, 3))        # (nd, 3) unit axis in the left (parent) RFE's body frame
    drive_t: np.ndarray = np.zeros((0, 2))           # (nd, K) s, angle table times
    drive_angle: np.ndarray = np.zeros((0, 2))       # (nd, K) rad, angle table
    drive_slope: np.ndarray = np.zeros((0, 2))       # (nd, K) rad/s, monotone cubic (PCHIP) slopes at the rows
    drive_count: np.ndarray = np.zeros(0, np.int64)  # (nd,) int64 rows of the table
    drive_phi0: np.ndarray = np.zeros(0)             # (nd,) rad, table value at t = 0 (dphi = phi(t) - phi0)
    has_drives: bool = False
    # --- torque-limited servo motors on coaxial clamped joins (rfesim.loads.drives.motor_forces); nm motors
    motor_sde: np.ndarray = np.zeros(0, np.int64)    # (nm,) int64, the joint SDE (torsion axis = motor axis)
    motor_t: np.ndarray = np.zeros((0, 2))           # (nm, K) s, angle table times
    motor_angle: np.ndarray = np.zeros((0, 2))       # (nm, K) rad, set angle
    motor_slope: np.ndarray = np.zeros((0, 2))       # (nm, K) rad/s, its PCHIP slopes
    motor_count: np.ndarray = np.zeros(0, np.int64)  # (nm,) int64 rows of the table
    motor_stiffness: np.ndarray = np.zeros(0)        # (nm,) N*m/rad, servo k_p (= the SDE's torsional stiffness)
    motor_damping: np.ndarray = np.zeros(0)          # (nm,) N*m*s/rad, servo k_d (= the SDE's torsional damping)
    motor_torque: np.ndarray = np.zeros(0)           # (nm,) N*m, torque limit
    motor_shift: np.ndarray = np.zeros(0)            # (nm,) rad, twist moved into the joint's rest rotation so far
                                                     #   (rfesim.model.joins.rebase_motors; written between steps)
    has_motors: bool = False
    # --- tugger lines from a vessel's deck to a body (rfesim.loads.tugger); ng tuggers
    tug_rfe: np.ndarray = np.zeros(0, np.int64)      # (ng,) int64, the body's RFE
    tug_att: np.ndarray = np.zeros(0, np.int64)      # (ng,) int64, attachment (vessel) of the deck point
    tug_deck: np.ndarray = np.zeros((0, 3))          # (ng, 3) m, deck point in the vessel frame
    tug_point: np.ndarray = np.zeros((0, 3))         # (ng, 3) m, body point in the body frame
    tug_kind: np.ndarray = np.zeros(0, np.int64)     # (ng,) int64, 0 constant tension (table), 1 elastic
    tug_t: np.ndarray = np.zeros((0, 1))             # (ng, K) s, set-tension table times
    tug_v: np.ndarray = np.zeros((0, 1))             # (ng, K) N, set tension
    tug_count: np.ndarray = np.zeros(0, np.int64)    # (ng,) int64 rows of the table
    tug_k: np.ndarray = np.zeros(0)                  # (ng,) N/m, elastic: axial stiffness of the line; force: end-stop stiffness
    tug_L0: np.ndarray = np.zeros(0)                 # (ng,) m, elastic: unstretched length; force: shortest length
    tug_c: np.ndarray = np.zeros(0)                  # (ng,) N*s/m, elastic: axial damping; force: longest length (m)
    has_tuggers: bool = False
    # --- reeving: a sheave's rope run toward its winch (rfesim.loads.reeving); nv reevings
    rv_sde: np.ndarray = np.zeros(0, np.int64)       # (nv,) int64, the pinned join SDE (the sheave)
    rv_kind: np.ndarray = np.zeros(0, np.int64)      # (nv,) int64, lead: 0 a point of an attachment, 1 a line end
    rv_att: np.ndarray = np.zeros(0, np.int64)       # (nv,) int64, kind 0: the attachment (vessel or fixed)
    rv_rfe: np.ndarray = np.zeros(0, np.int64)       # (nv,) int64, kind 1: the line end's RFE
    rv_point: np.ndarray = np.zeros((0, 3))          # (nv, 3) m, lead point: attachment frame (0), arm in the RFE frame (1)
    rv_slip: np.ndarray = np.zeros(0, np.int64)      # (nv,) int64, 1: the rope slips over the sheave (a vessel lead)
    rv_len: np.ndarray = np.zeros(0)                 # (nv,) m, run length at the initial positions (slip 0 there)
    rv_arm_written: np.ndarray = np.zeros(0)         # (nv,) m, the join's arm on the rope as slip_arms last wrote it
    rv_arm_offset: np.ndarray = np.zeros(0)          # (nv,) m, the offset it added to the base arm
    has_reeving: bool = False
    # --- closing joins: an SDE from end B of a line to end B of another (a portal's crossbeam,
    # rfesim.model.joins); its two RFEs are not neighbours, so the Jacobian is block tridiagonal
    # plus two off-band blocks per closure (rfesim.solvers.banded.bt_factor_closed)
    cl_sde: np.ndarray = np.zeros(0, np.int64)       # (nc,) int64, the closing SDE
    has_closures: bool = False
    # --- further off-band Jacobian blocks: a rope led along a line couples the lead's RFE with
    # the sheave's, which are not neighbours (rfesim.loads.reeving.reeving_tangent); solved with
    # the closures' (rfesim.solvers.banded.bt_factor_closed)
    ob_row: np.ndarray = np.zeros(0, np.int64)       # (nob,) int64, the block's row RFE
    ob_col: np.ndarray = np.zeros(0, np.int64)       # (nob,) int64, its column RFE (|row - col| > 1, pairs unique)
    has_offband: bool = False


class Workspace(NamedTuple):
    """Buffers written by one evaluation of the equations of motion (allocated once)."""

    R: np.ndarray           # (n, 3, 3) RFE orientation (global)
    r: np.ndarray           # (n, 3) m, RFE centre (global)
    rbase: np.ndarray       # (n, 3) m, r = rbase + roff with rbase the reference position (free RFEs)
    roff: np.ndarray        # (n, 3) m, displacement part of r (differenced exactly in the SDE gaps)
    v: np.ndarray           # (n, 3) m/s
    w: np.ndarray           # (n, 3) rad/s, global angular velocity
    wb: np.ndarray          # (n, 3) rad/s, body angular velocity
    E: np.ndarray           # (n, 3, 3) Euler-rate matrix, wb = E * angle rates
    Edot: np.ndarray        # (n, 3) rad/s^2, velocity part of d(wb)/dt
    F: np.ndarray           # (n, 3) N, resultant force on each RFE (global)
    M: np.ndarray           # (n, 3) N*m, resultant moment about each RFE centre (global)
    Ma: np.ndarray          # (n, 3, 3) kg, added mass (global)
    Ja: np.ndarray          # (n, 3) kg*m^2, added rotational inertia (body axes)
    eps: np.ndarray         # (nsde, 6) SDE deformation [m x3, rad x3] in {i'}
    sigma: np.ndarray       # (nsde, 6) SDE forces [N x3] and moments [N*m x3] in {i'}
    sde_point: np.ndarray   # (nsde, 3) m, SDE position
    surface_z: np.ndarray   # (n,) m, water surface above each RFE
    water_vel: np.ndarray   # (n, 3) m/s, water particle velocity at each RFE
    water_acc: np.ndarray   # (n, 3) m/s^2
    sub_frac: np.ndarray    # (n,) submerged fraction of each RFE
    sub_point: np.ndarray   # (n, 3) m, centroid of the submerged part
    contact_force: np.ndarray   # (n,) N, seabed normal force on each RFE
    contact_length: np.ndarray  # (n,) m, length of each RFE in seabed contact (0 where the seabed pushes nothing)
    Mgen: np.ndarray        # (n, 6, 6) generalised mass block of each RFE
    fgen: np.ndarray        # (n, 6) generalised force (applied - velocity terms)
    tmp3: np.ndarray        # (8, 3) scratch
    v3: np.ndarray          # (32, 3) scratch vectors of the kernels (no allocation in hot loops)
    m33: np.ndarray         # (16, 3, 3) scratch matrices of the kernels
    # --- history (committed at accepted steps) and its trial values written by an evaluation
    fric_anchor: np.ndarray          # (n, 3) m, committed seabed friction anchor of each RFE
    fric_anchored: np.ndarray        # (n,) int64, 1 when the committed anchor is valid
    fric_anchor_trial: np.ndarray    # (n, 3) m
    fric_anchored_trial: np.ndarray  # (n,) int64
    fric_mode: np.ndarray            # (1,) int64: 0 stick/slip, 1 mobilised towards end A (statics), 2 off
    friction_force: np.ndarray       # (n, 3) N, seabed friction force on each RFE
    plastic_hist: np.ndarray         # (nsde, nh) committed plastic state of the SDEs
    plastic_hist_trial: np.ndarray   # (nsde, nh)
    k_tangent: np.ndarray            # (nsde, 6) SDE stiffness with the plastic bending tangent
    out5: np.ndarray                 # (5,) scratch of the plastic law
    grip_a: np.ndarray               # (n,) m, committed tensioner grip anchors (material coordinate)
    grip_on: np.ndarray              # (n,) int64
    grip_a_trial: np.ndarray         # (n,)
    grip_on_trial: np.ndarray        # (n,) int64
    tens_D: np.ndarray               # (ntens,) m, committed paid-out length of driven tensioners
    tens_force: np.ndarray           # (ntens,) N, axial force each tensioner holds
    tens_time: np.ndarray            # (2,) s: [time of the last commit, time of the last evaluation]
    roller_hint: np.ndarray          # (nr,) int64, RFE nearest to each roller at the last evaluation (-1: none)
    roller_force: np.ndarray         # (nr, 3) N, force of the line on each roller (global)
    roller_normal: np.ndarray        # (nr,) N, total normal force of each roller
    roller_anchor: np.ndarray        # (nr,) m, committed friction anchor along the roller axis
    roller_anchored: np.ndarray      # (nr,) int64
    roller_anchor_trial: np.ndarray  # (nr,) m
    roller_anchored_trial: np.ndarray  # (nr,) int64
    roller_scratch: np.ndarray       # (32,) scratch of the roller kernel
    waves_off: np.ndarray            # (1,) int64, 1: still water plus current (statics), 0: waves on
    point1: np.ndarray               # (1, 3) m, scratch point for one-point sea kinematics
    sea_frozen: np.ndarray           # (1,) int64, 1: keep the water kinematics of the last evaluation
    reel_grip_a: np.ndarray = np.zeros(0)            # (n,) m, committed reel grip anchors (material coordinate)
    reel_grip_on: np.ndarray = np.zeros(0, np.int64)  # (n,) int64
    reel_grip_a_trial: np.ndarray = np.zeros(0)      # (n,)
    reel_grip_on_trial: np.ndarray = np.zeros(0, np.int64)  # (n,) int64
    reel_D: np.ndarray = np.zeros(1)                 # (nreel,) m, committed paid-out length of driven reels
    reel_force: np.ndarray = np.zeros(1)             # (nreel,) N, tangential force each reel holds
    reel_time: np.ndarray = np.zeros(2)              # (2,) s: [time of the last commit, of the last evaluation]
    tens_D_trial: np.ndarray = np.zeros(1)           # (ntens,) m, driven tensioners' payout solved in the last
                                                     #   evaluation (committed by commit_history; the model's
                                                     #   tables stay constant)
    reel_D_trial: np.ndarray = np.zeros(1)           # (nreel,) m, the same for driven reels
    reel_offset: np.ndarray = np.zeros(1)            # (nreel,) N, Delta: a driven reel's law acts on its grip force
                                                     #   less Delta (grip - back tension, set by statics; 0 without)
    sde_rest_eff: np.ndarray = np.zeros((0, 3, 3))   # (nsde, 3, 3) rest rotation R0(t) of the driven SDEs (evaluation time)
    sde_rest_rate: np.ndarray = np.zeros((0, 3))     # (nsde, 3) rad/s, its angular velocity omega0 (left RFE's body frame)
    motor_sat: np.ndarray = np.zeros(0, np.int64)    # (nm,) int64, 1: the motor is at its torque limit
    c_tangent: np.ndarray = np.zeros((0, 6))         # (nsde, 6) SDE damping for the Jacobian (motors at the limit: 0)
    deck_normal: np.ndarray = np.zeros(0)            # (nb,) N, normal force of each body's deck (rfesim.loads.deck)
    tug_tension: np.ndarray = np.zeros(0)            # (ng,) N, tension of each tugger line (rfesim.loads.tugger)
    tug_length: np.ndarray = np.zeros(0)             # (ng,) m, its length
    rv_tension: np.ndarray = np.zeros(0)             # (nv,) N, tension at each reeving's sheave (rfesim.loads.reeving)
    rv_dir: np.ndarray = np.zeros((0, 3))            # (nv, 3) unit direction from the sheave to the lead
    rv_fdir: np.ndarray = np.zeros((0, 3))           # (nv, 3) unit direction of the join's force on the parent
    rv_slip_out: np.ndarray = np.zeros(0)            # (nv,) m, the rope's slip over each sheave (rfesim.loads.reeving)
    sea_reach: np.ndarray = np.zeros(0)              # (n,) m, how far below its centre each RFE (or body) can be wet
    step_state: np.ndarray = np.zeros(1, np.int64)   # (1,) int64, 1: the workspace holds the evaluation of the state
                                                     #   a generalised-alpha step just converged to (outputs reuse it)
    cl_J: np.ndarray = np.zeros((0, 2, 6, 6))       # (nc, 2, 6, 6) off-band Jacobian blocks of the closures:
                                                     #   [c, 0] row: left RFE, column: right RFE; [c, 1] the other
    cl_Z: np.ndarray = np.zeros((0, 1, 6))           # (12 nc, n, 6) B^-1 U of the factorised band B (Woodbury)
    cl_S: np.ndarray = np.zeros((0, 0))              # (12 nc, 12 nc) inverse of the capacitance I + W^T B^-1 U
    cl_work: np.ndarray = np.zeros((0, 0))           # (12 nc, 12 nc) scratch of its inversion
    cl_rhs: np.ndarray = np.zeros((1, 6))            # (n, 6) scratch right-hand side
    cl_w: np.ndarray = np.zeros(0)                   # (12 nc,) scratch of the solve (bt_solve_closed)
    #   (with further off-band blocks, 12 nc + 6 nob for cl_Z, cl_S, cl_work, cl_w: 6 columns per block)
    ob_J: np.ndarray = np.zeros((0, 6, 6))           # (nob, 6, 6) the further off-band blocks (km.ob_row, km.ob_col)
    rv_K: np.ndarray = np.zeros((0, 12, 18))         # (nv, 12, 18) the pulls' stiffness tangent (rfesim.loads.reeving)
    rv_Kd: np.ndarray = np.zeros((0, 12, 18))        # (nv, 12, 18) their damping tangent


class Reference(NamedTuple):
    """Per-RFE reference pose the coordinates are measured from (re-based as the run goes):
    orientation R = R0 Rzyx(angles), centre r = X0 + displacement. Keeping the coordinates
    small keeps the SDE gaps free of the round-off of large absolute positions."""

    R: np.ndarray       # (n, 3, 3) reference rotation R0
    X: np.ndarray       # (n, 3) m, reference position X0


class AttachmentState(NamedTuple):
    """Kinematics of every attachment at one time (0: fixed global frame)."""

    p: np.ndarray       # (natt, 3) m, origin
    R: np.ndarray       # (natt, 3, 3)
    v: np.ndarray       # (natt, 3) m/s
    w: np.ndarray       # (natt, 3) rad/s
    a: np.ndarray       # (natt, 3) m/s^2
    alpha: np.ndarray   # (natt, 3) rad/s^2
    time: np.ndarray    # (1,) s, the time these kinematics are for (time-dependent loads read it)
    scratch: np.ndarray  # (16, 3) work space of the compiled kinematics


def new_workspace(n: int, nsde: int, nh: int = 1, nroller: int = 0, ntens: int = 0, nreel: int = 0,
                  nmotor: int = 0, nbody: int = 0, ntug: int = 0, nreeve: int = 0, nclosure: int = 0,
                  noffband: int = 0) -> Workspace:
    m = 12 * nclosure + 6 * noffband
    return Workspace(
        R=np.zeros((n, 3, 3)), r=np.zeros((n, 3)), rbase=np.zeros((n, 3)), roff=np.zeros((n, 3)), v=np.zeros((n, 3)), w=np.zeros((n, 3)),
        wb=np.zeros((n, 3)), E=np.zeros((n, 3, 3)), Edot=np.zeros((n, 3)), F=np.zeros((n, 3)),
        M=np.zeros((n, 3)), Ma=np.zeros((n, 3, 3)), Ja=np.zeros((n, 3)), eps=np.zeros((nsde, 6)),
        sigma=np.zeros((nsde, 6)), sde_point=np.zeros((nsde, 3)), surface_z=np.zeros(n),
        water_vel=np.zeros((n, 3)), water_acc=np.zeros((n, 3)), sub_frac=np.zeros(n),
        sub_point=np.zeros((n, 3)), contact_force=np.zeros(n), contact_length=np.zeros(n),
        Mgen=np.zeros((n, 6, 6)), fgen=np.zeros((n, 6)), tmp3=np.zeros((8, 3)),
        v3=np.zeros((32, 3)), m33=np.zeros((16, 3, 3)),
        fric_anchor=np.zeros((n, 3)), fric_anchored=np.zeros(n, np.int64), fric_anchor_trial=np.zeros((n, 3)),
        fric_anchored_trial=np.zeros(n, np.int64), fric_mode=np.zeros(1, np.int64),
        friction_force=np.zeros((n, 3)), plastic_hist=np.zeros((nsde, nh)), plastic_hist_trial=np.zeros((nsde, nh)),
        k_tangent=np.zeros((nsde, 6)), out5=np.zeros(5), grip_a=np.zeros(n), grip_on=np.zeros(n, np.int64),
        grip_a_trial=np.zeros(n), grip_on_trial=np.zeros(n, np.int64), tens_D=np.zeros(max(ntens, 1)),
        tens_force=np.zeros(max(ntens, 1)), tens_time=np.zeros(2), roller_hint=np.full(nroller, -1, np.int64),
        roller_force=np.zeros((nroller, 3)), roller_normal=np.zeros(nroller), roller_anchor=np.zeros(nroller),
        roller_anchored=np.zeros(nroller, np.int64), roller_anchor_trial=np.zeros(nroller),
        roller_anchored_trial=np.zeros(nroller, np.int64), roller_scratch=np.zeros(32), waves_off=np.zeros(1, np.int64), point1=np.zeros((1, 3)), sea_frozen=np.zeros(1, np.int64),
        reel_grip_a=np.zeros(n), reel_grip_on=np.zeros(n, np.int64), reel_grip_a_trial=np.zeros(n),
        reel_grip_on_trial=np.zeros(n, np.int64), reel_D=np.zeros(max(nreel, 1)), reel_force=np.zeros(max(nreel, 1)),
        reel_time=np.zeros(2), tens_D_trial=np.zeros(max(ntens, 1)), reel_D_trial=np.zeros(max(nreel, 1)),
        reel_offset=np.zeros(max(nreel, 1)),
        sde_rest_eff=_identities(nsde), sde_rest_rate=np.zeros((nsde, 3)),
        sea_reach=np.zeros(n), step_state=np.zeros(1, np.int64), motor_sat=np.zeros(nmotor, np.int64),
        c_tangent=np.zeros((nsde, 6)), deck_normal=np.zeros(nbody), tug_tension=np.zeros(ntug), tug_length=np.zeros(ntug),
        rv_tension=np.zeros(nreeve), rv_dir=np.zeros((nreeve, 3)), rv_fdir=np.zeros((nreeve, 3)),
        rv_slip_out=np.zeros(nreeve), cl_J=np.zeros((nclosure, 2, 6, 6)), cl_Z=np.zeros((m, n, 6)),
        cl_S=np.zeros((m, m)), cl_work=np.zeros((m, m)), cl_rhs=np.zeros((n, 6)), cl_w=np.zeros(m),
        ob_J=np.zeros((noffband, 6, 6)), rv_K=np.zeros((nreeve, 12, 18)), rv_Kd=np.zeros((nreeve, 12, 18)))


def _identities(m: int) -> np.ndarray:
    out = np.zeros((m, 3, 3))
    out[:] = np.eye(3)
    return out


def joint_arrays(nsde: int, rest=None, drives=()) -> dict:
    """KernelModel fields of the SDE rest rotations and drives (rfesim.loads.drives).

    rest: None, an (nsde, 3, 3) array or a dict {SDE index: (3, 3) rotation}; identity
    elsewhere. drives: dicts {"sde": s, "axis": unit axis (3,) in the body frame of the
    SDE's left RFE at t = 0, "table": [[t (s), angle (rad)], ...]} in the order their
    rotations compose (R0(t) = Rot(a_1, dphi_1) Rot(a_2, dphi_2) ... sde_rest[s]); the rows
    are sorted stably by SDE. ``sde_has_rest`` is 2 for driven SDEs, 1 for a constant rest
    rotation that is not the identity, 0 otherwise."""
    from .supports import drive_slopes
    from ..loads.drives import drive_table
    R0 = _identities(nsde)
    if rest is not None:
        if isinstance(rest, dict):
            for s, Rs in rest.items():
                R0[int(s)] = np.asarray(Rs, float)
        else:
            R0[:] = np.asarray(rest, float).reshape(nsde, 3, 3)
    flags = rest_flags(R0, np.zeros(0, np.int64))
    rows = sorted(enumerate(drives), key=lambda kv: (int(kv[1]["sde"]), kv[0]))
    nd = len(rows)
    K = max([2] + [len(d["table"]) for _, d in rows])
    out = dict(drive_sde=np.zeros(nd, np.int64), drive_axis=np.zeros((nd, 3)), drive_t=np.zeros((nd, K)),
               drive_angle=np.zeros((nd, K)), drive_slope=np.zeros((nd, K)), drive_count=np.zeros(nd, np.int64),
               drive_phi0=np.zeros(nd))
    for j, (_, d) in enumerate(rows):
        s = int(d["sde"])
        if not 0 <= s < nsde:
            raise ValueError(f"drive {j}: SDE index {s} outside 0..{nsde - 1}")
        ax = np.asarray(d["axis"], float)
        norm = float(np.linalg.norm(ax))
        if not norm > 0.0:
            raise ValueError(f"drive {j}: axis must not be zero")
        table = np.asarray(d["table"], float).reshape(-1, 2)
        if table.shape[0] < 1 or np.any(np.diff(table[:, 0]) <= 0.0):
            raise ValueError(f"drive {j}: table times must increase")
        if table.shape[0] == 1:
            table = np.vstack([table, table + [1.0, 0.0]])
        c = table.shape[0]
        flags[s] = 2
        out["drive_sde"][j] = s
        out["drive_axis"][j] = ax / norm
        out["drive_t"][j, :c] = table[:, 0]
        out["drive_angle"][j, :c] = table[:, 1]
        out["drive_slope"][j, :c] = drive_slopes(table[:, 0], table[:, 1])
        out["drive_count"][j] = c
        out["drive_phi0"][j] = drive_table(table[:, 0], table[:, 1], out["drive_slope"][j, :c], 0.0)[0]
    out.update(sde_rest=R0, sde_has_rest=flags, has_drives=nd > 0)
    return out


def rest_flags(sde_rest: np.ndarray, drive_sde: np.ndarray) -> np.ndarray:
    """``sde_has_rest`` from the rest rotations and the drive rows: 2 for a driven SDE, 1
    for a constant rest rotation other than the identity, 0 otherwise."""
    eye = np.eye(3)
    flags = np.array([0 if np.array_equal(Rs, eye) else 1 for Rs in sde_rest], np.int64).reshape(-1)
    flags[np.asarray(drive_sde, np.int64)] = 2
    return flags


def complete_joint_arrays(km):
    """The KernelModel with ``sde_has_rest`` derived from ``sde_rest`` and the drive rows
    (a compile step that fills only those gets the flags the kernels read), checked."""
    nsde = km.sde_left.shape[0]
    if km.sde_rest.shape[0] == 0 and not km.has_drives:
        return km
    if km.sde_rest.shape != (nsde, 3, 3):
        raise ValueError(f"sde_rest must be ({nsde}, 3, 3), got {km.sde_rest.shape}")
    km = km._replace(sde_rest=np.ascontiguousarray(km.sde_rest, dtype=float),
                     sde_has_rest=rest_flags(km.sde_rest, km.drive_sde))
    check_joint_arrays(km)
    return km


def check_joint_arrays(km) -> None:
    """Raise ValueError when the rest-rotation arrays of a KernelModel disagree (a rest
    rotation the kernels would skip, a driven SDE without drives, bad shapes)."""
    nsde = km.sde_left.shape[0]
    if km.sde_rest.shape[0] == 0 and km.sde_has_rest.shape[0] == 0 and not km.has_drives:
        return
    if km.sde_rest.shape != (nsde, 3, 3) or km.sde_has_rest.shape != (nsde,):
        raise ValueError(f"sde_rest must be ({nsde}, 3, 3) and sde_has_rest ({nsde},): got "
                         f"{km.sde_rest.shape} and {km.sde_has_rest.shape} (build them with joint_arrays)")
    eye = np.eye(3)
    driven = set(int(s) for s in km.drive_sde)
    if km.has_drives != bool(driven):
        raise ValueError("has_drives must be True exactly when there are drive rows")
    for s in range(nsde):
        f = int(km.sde_has_rest[s])
        if f == 0 and not np.array_equal(km.sde_rest[s], eye):
            raise ValueError(f"SDE {s} has a rest rotation but sde_has_rest[{s}] = 0 (build with joint_arrays)")
        if (f == 2) != (s in driven):
            raise ValueError(f"sde_has_rest[{s}] = {f} disagrees with the drive rows (2 exactly for driven SDEs)")


def new_attachment_state(natt: int) -> AttachmentState:
    R = np.zeros((natt, 3, 3))
    R[:] = np.eye(3)
    return AttachmentState(p=np.zeros((natt, 3)), R=R, v=np.zeros((natt, 3)), w=np.zeros((natt, 3)),
                           a=np.zeros((natt, 3)), alpha=np.zeros((natt, 3)), time=np.zeros(1), scratch=np.zeros((16, 3)))


def motor_arrays(motors: list[dict]) -> dict:
    """KernelModel fields of the servo motors: dicts {"sde", "table": [[t s, angle rad], ...],
    "stiffness", "damping", "max_torque"}."""
    from .supports import drive_slopes
    nm = len(motors)
    K = max([2] + [len(m["table"]) for m in motors])
    out = dict(motor_sde=np.zeros(nm, np.int64), motor_t=np.zeros((nm, K)), motor_angle=np.zeros((nm, K)),
               motor_slope=np.zeros((nm, K)), motor_count=np.zeros(nm, np.int64), motor_stiffness=np.zeros(nm),
               motor_damping=np.zeros(nm), motor_torque=np.zeros(nm), motor_shift=np.zeros(nm), has_motors=nm > 0)
    for j, m in enumerate(motors):
        table = np.asarray(m["table"], float).reshape(-1, 2)
        if table.shape[0] == 1:
            table = np.vstack([table, table + [1.0, 0.0]])
        c = table.shape[0]
        out["motor_sde"][j] = int(m["sde"])
        out["motor_t"][j, :c] = table[:, 0]
        out["motor_angle"][j, :c] = table[:, 1]
        out["motor_slope"][j, :c] = drive_slopes(table[:, 0], table[:, 1])
        out["motor_count"][j] = c
        out["motor_stiffness"][j] = float(m["stiffness"])
        out["motor_damping"][j] = float(m["damping"])
        out["motor_torque"][j] = float(m["max_torque"])
    return out


def append_sde(sde: dict, plastic_rows: list, plastic_flags: list, tension_flags: list, left: int, right: int,
               arm_left, arm_right, stiffness, damping, length: float) -> None:
    """Append one elastic SDE (no plastic law, not tension-only) to the compile's SDE lists:
    a joint between lines, a closing join, a body's connection (rfesim.model.compile)."""
    sde["left"].append(left)
    sde["right"].append(right)
    sde["arm_left"].append(list(arm_left))
    sde["arm_right"].append(list(arm_right))
    sde["stiffness"].append(stiffness)
    sde["damping"].append(damping)
    sde["length"].append(length)
    plastic_rows.append(np.zeros(2))
    plastic_flags.append(0)
    tension_flags.append(0)
