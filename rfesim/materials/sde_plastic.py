"""Elasto-plastic bending law of an SDE with memory (section 8.4.2, Figs. 8.15-8.16).

The SDE's bending moment is a function of its curvature vector
``kappa = (kappa_y, kappa_z) = (theta_y, theta_z) / Delta`` (relative rotation over the
SDE spacing) and of its committed plastic state. The law is a **section-level overlay
(Iwan / Mroz multi-surface) model in the curvature plane**:

    M = k_inf kappa + sum_j m_j,    m_j = k_j (kappa - kappa_p,j),    |m_j| <= r_j,

n sub-elements, each a 2-D elastic-perfectly-plastic element with a circular yield
surface of radius r_j in the moment plane (radial return), plus an unbreakable spring
k_inf. Its monotonic curve is the polyline through the fibre model's M(kappa)
(``rfesim.materials.section.moment_curvature``) at ``segments`` curvatures from the
yield curvature to ``max_curvature_ratio`` times it; under reversed planar bending it
is kinematic hardening with the Masing rule, which is exactly what the fibre model
with an overlay (kinematic) material gives in planar bending. The circles make it
isotropic in the plane: a pipe bent in y and then in z follows the same rule with the
vector kappa (docs/theory.md, "Elasto-plastic SDE").

The history of SDE i is ``hist[i] = [kp_y,1, kp_z,1, ..., kp_y,n, kp_z,n, D]``: the
plastic curvature of every sub-element (1/m) and the plastic dissipation per unit
length (J/m). The parameters are ``params[i] = [n, k_inf, k_1..k_n, r_1..r_n]``
(-, N*m^2, N*m^2, N*m); rows of different line types may be padded with zeros.

``plastic_bending_into`` is a pure function of the trial curvature and the committed
history; it writes the trial history. The caller copies trial -> committed after each
accepted step.

Stress outputs (eqs. 8.97-8.98, with hydrostatic pressure: docs/theory.md, "Stresses"):
``pipe_stress`` / ``pipe_stress_into``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from numba import njit

from .section import (PipeWall, bending_tangent, moment_curvature, plastic_moment, yield_curvature,
                      yield_moment)
from .stress_strain import StressStrainLaw, law_from_material, overlay_elements

N_OUT = 5          # plastic_bending_into output: [M_y, M_z, K_yy, K_yz, K_zz]
N_STRESS = 7       # pipe_stress_into output columns


# --------------------------------------------------------------------------- kernels

@njit(cache=True)
def plastic_bending_into(params, hist_committed, i, kappa_y, kappa_z, out, hist_trial):
    """Bending moment of SDE i with memory.

    params (nsde, 2 + 2n): [n, k_inf (N*m^2), k_j (N*m^2), r_j (N*m)];
    hist_committed, hist_trial (nsde, 2n + 1): plastic curvatures (1/m) and dissipation (J/m);
    kappa_y, kappa_z: trial curvature (1/m);
    out (5,): [M_y, M_z (N*m), K_yy, K_yz, K_zz (N*m^2)], K = dM/dkappa (consistent tangent).
    """
    p = params[i]
    n = int(p[0])
    k_inf = p[1]
    my_tot = k_inf * kappa_y
    mz_tot = k_inf * kappa_z
    kyy = k_inf
    kyz = 0.0
    kzz = k_inf
    diss = hist_committed[i, 2 * n]
    for j in range(n):
        k = p[2 + j]
        r = p[2 + n + j]
        py = hist_committed[i, 2 * j]
        pz = hist_committed[i, 2 * j + 1]
        my = k * (kappa_y - py)                  # trial moment of sub-element j
        mz = k * (kappa_z - pz)
        m = math.sqrt(my * my + mz * mz)
        if m <= r:                               # elastic (Fig. 8.15: elastic region, C_e)
            kyy += k
            kzz += k
        else:                                    # radial return onto the circle |m_j| = r_j
            ny = my / m
            nz = mz / m
            scale = r / m
            my = r * ny
            mz = r * nz
            py = kappa_y - my / k
            pz = kappa_z - mz / k
            diss += r * (m - r) / k              # r_j |d kappa_p,j|
            ks = k * scale
            kyy += ks * (1.0 - ny * ny)
            kyz -= ks * ny * nz
            kzz += ks * (1.0 - nz * nz)
        hist_trial[i, 2 * j] = py
        hist_trial[i, 2 * j + 1] = pz
        my_tot += my
        mz_tot += mz
    hist_trial[i, 2 * n] = diss
    out[0] = my_tot
    out[1] = mz_tot
    out[2] = kyy
    out[3] = kyz
    out[4] = kzz


@njit(cache=True, _nrt=True)
def plastic_bending_all_into(params, hist_committed, kappa, out, hist_trial):
    """``plastic_bending_into`` for every SDE: kappa (nsde, 2), out (nsde, 5)."""
    tmp = np.empty(N_OUT)
    for i in range(kappa.shape[0]):
        plastic_bending_into(params, hist_committed, i, kappa[i, 0], kappa[i, 1], tmp, hist_trial)
        for k in range(N_OUT):
            out[i, k] = tmp[k]


@njit(cache=True)
def plastic_bending_energy(params, hist, i, kappa_y, kappa_z):
    """Stored (free) energy per unit length (J/m) of SDE i at kappa with history hist:
    1/2 k_inf |kappa|^2 + sum_j 1/2 k_j |kappa - kappa_p,j|^2 (multiply by Delta for the SDE)."""
    p = params[i]
    n = int(p[0])
    e = 0.5 * p[1] * (kappa_y * kappa_y + kappa_z * kappa_z)
    for j in range(n):
        dy = kappa_y - hist[i, 2 * j]
        dz = kappa_z - hist[i, 2 * j + 1]
        e += 0.5 * p[2 + j] * (dy * dy + dz * dz)
    return e


@njit(cache=True)
def pipe_stress(fx, fy, fz, mx, my, mz, area, enclosed_area, outer_radius, inner_radius, inertia, t_min,
                p_ext, p_int, out):
    """Stresses of an SDE from its forces (N) and moments (N*m) in {i'} (eqs. 8.97-8.98)
    and the external and internal pressures p_ext, p_int (Pa) at the SDE.

    F_x is the effective tension (buoyancy acts on the closed outer volume, docs/theory.md
    section 4); the steel wall carries the true wall tension
    T = F_x + p_int A_i - p_ext A_e (A_e = pi r_o^2, A_i = pi r_i^2).

    out (6,): [sigma_x, sigma_g, tau_xy, tau_xz, sigma_eq_898, sigma_vm] (Pa):
    sigma_x = T/A the true-wall axial stress (= F_x/A without pressure);
    tau_g = M_x/(2 A_m t_min) (Bredt, A_m the area enclosed by the wall's mid-line);
    tau_xy = F_y/A + tau_g/2, tau_xz = F_z/A + tau_g/2 (eq. 8.97);
    sigma_g = |M_b| r_o / I the elastic-equivalent bending stress at the outer fibre;
    sigma_eq_898 = sqrt(3 J_2 + sigma_g^2) with J_2 of the tensor 8.97 (eq. 8.98 as written,
    no hoop or radial stress);
    sigma_vm: the largest von Mises stress of the full tensor (axial sigma_x + bending,
    Lame hoop and radial stresses of the thick wall, the shears above) at the outer and
    inner fibres, each where axial and bending stress add and where they subtract.
    Without pressure it is sqrt((|sigma_x| + sigma_g)^2 + 3 (tau_xy^2 + tau_xz^2)).
    """
    ro2 = outer_radius * outer_radius
    ri2 = inner_radius * inner_radius
    t_true = fx + p_int * math.pi * ri2 - p_ext * math.pi * ro2    # true wall tension
    sx = t_true / area                                    # eq. 8.97 with the true wall tension
    tg = mx / (2.0 * enclosed_area * t_min)               # eq. 8.97: torsion shear
    txy = fy / area + 0.5 * tg
    txz = fz / area + 0.5 * tg
    sg = math.sqrt(my * my + mz * mz) * outer_radius / inertia
    shear = 3.0 * (txy * txy + txz * txz)
    j2 = sx * sx / 3.0 + txy * txy + txz * txz            # J_2 of the tensor 8.97
    out[0] = sx
    out[1] = sg
    out[2] = txy
    out[3] = txz
    out[4] = math.sqrt(3.0 * j2 + sg * sg)                # eq. 8.98
    # Lame: sigma_r = a - b / r^2, sigma_h = a + b / r^2, sigma_r(r_i) = -p_int, sigma_r(r_o) = -p_ext
    den = ro2 - ri2
    a = (p_int * ri2 - p_ext * ro2) / den
    b = (p_int - p_ext) * ri2 * ro2 / den
    worst = 0.0
    for f in range(2):                                    # outer, inner fibre
        r2 = ro2 if f == 0 else ri2
        sh = a + b / r2
        sr = a - b / r2
        sb = sg if f == 0 else sg * inner_radius / outer_radius
        for side in range(2):                             # bending adds to / subtracts from sigma_x
            sxx = sx + sb if side == 0 else sx - sb
            v = sxx * sxx + sh * sh + sr * sr - sxx * sh - sh * sr - sr * sxx + shear
            if v > worst:
                worst = v
    out[5] = math.sqrt(worst)


@njit(cache=True, _nrt=True)
def pipe_stress_into(sigma, geometry, p_ext, p_int, out):
    """Stresses of every SDE. sigma (nsde, 6): [F_x, F_y, F_z, M_x, M_y, M_z] in {i'}
    (N, N*m), F_x the effective tension; geometry (nsde, 7): [A (m^2), A_m (m^2), r_o (m),
    I (m^4), t_min (m), sigma_0 (Pa), r_i (m)] (``stress_geometry``); p_ext, p_int (nsde,):
    external and internal pressure at the SDE (Pa); out (nsde, 7): ``pipe_stress`` columns
    and the utilisation sigma_vm / sigma_0 (yielding at 1)."""
    tmp = np.empty(6)
    for s in range(sigma.shape[0]):
        g = geometry[s]
        pipe_stress(sigma[s, 0], sigma[s, 1], sigma[s, 2], sigma[s, 3], sigma[s, 4], sigma[s, 5],
                    g[0], g[1], g[2], g[6], g[3], g[4], p_ext[s], p_int[s], tmp)
        for k in range(6):
            out[s, k] = tmp[k]
        out[s, 6] = tmp[5] / g[5]


# --------------------------------------------------------------------------- parameters

@dataclass(frozen=True)
class PlasticSection:
    """The overlay model of one pipe section and the numbers that define it."""

    params: np.ndarray            # (2 + 2n,) [n, k_inf, k_j, r_j] row for plastic_bending_into
    history_width: int            # 2n + 1
    bending_stiffness: float      # N*m^2, EI (= k_inf + sum k_j)
    yield_curvature: float        # 1/m
    yield_moment: float           # N*m
    plastic_moment: float         # N*m, sigma_y (D^3 - d^3)/6
    break_curvatures: np.ndarray  # (n,) 1/m, polyline break points
    break_moments: np.ndarray     # (n,) N*m, fibre-model M at the breaks
    stress_geometry: np.ndarray   # (7,) row for pipe_stress_into
    law: StressStrainLaw
    wall: PipeWall


def stress_geometry(wall: PipeWall, yield_stress: float) -> np.ndarray:
    """Row [A, A_m, r_o, I, t_min, sigma_0, r_i] of ``pipe_stress_into``."""
    mid = wall.outer_radius - 0.5 * wall.wall_thickness
    return np.array([wall.area, math.pi * mid * mid, wall.outer_radius, wall.inertia,
                     wall.wall_thickness, yield_stress, wall.outer_radius - wall.wall_thickness])


def break_curvatures(law: StressStrainLaw, wall: PipeWall, segments: int, max_curvature_ratio: float):
    """Break curvatures of the polyline: equidistributed in the measure sqrt(|M''(kappa)|) dkappa
    (the optimal placement for linear interpolation of a smooth curve), the first break
    at the yield curvature for a law with a linear range (from 0.02 kappa_y otherwise)."""
    ky = yield_curvature(law, wall)
    if law.has_linear_range:
        u = np.concatenate(([1.0], 1.0 + np.geomspace(1e-5, max_curvature_ratio - 1.0, 2000)))
    else:
        u = np.geomspace(0.02, max_curvature_ratio, 2000)
    kappa = ky * u
    tangent = bending_tangent(law, wall, kappa, n_radial=4, n_angular=360)
    density = np.sqrt(np.abs(np.diff(tangent) / np.diff(kappa)))
    measure = np.concatenate(([0.0], np.cumsum(density * np.diff(kappa))))
    if law.has_linear_range:
        targets = measure[-1] * np.arange(1, segments) / max(segments - 1, 1)
        kb = np.concatenate(([ky], np.interp(targets, measure, kappa)[:segments - 1]))
    else:
        targets = measure[-1] * np.arange(1, segments + 1) / segments
        kb = np.interp(targets, measure, kappa)
    kb[-1] = ky * max_curvature_ratio
    return np.unique(kb)


def plastic_section(law: StressStrainLaw, wall: PipeWall, segments: int = 40,
                    max_curvature_ratio: float = 100.0) -> PlasticSection:
    """Fit the overlay model to the fibre model's monotonic M(kappa): the polyline through
    M at ``segments`` break curvatures (``break_curvatures``) up to ``max_curvature_ratio``
    kappa_y, continued with the fibre model's tangent at the last break."""
    if segments < 2:
        raise ValueError("segments must be >= 2")
    if not max_curvature_ratio > 1.0:
        raise ValueError("max_curvature_ratio must be > 1")
    try:
        hash(law)
    except TypeError:       # a law with an unhashable field (a list table): no memo
        return _fit_section(law, wall, int(segments), float(max_curvature_ratio))
    # the fit integrates the fibre model at 2000 curvatures (about 18 ms for the reel-lay scenario's Ramberg-Osgood wall, most of its build):
    # every build of a scenario, and the recorder's stress rows, fit the same frozen law and
    # wall, so the fit is kept (a copy is handed out: callers may change its arrays)
    fit = _fit_section_memo(law, wall, int(segments), float(max_curvature_ratio))
    return replace(fit, params=fit.params.copy(), break_curvatures=fit.break_curvatures.copy(),
                   break_moments=fit.break_moments.copy(), stress_geometry=fit.stress_geometry.copy())


def _fit_section(law: StressStrainLaw, wall: PipeWall, segments: int, max_curvature_ratio: float) -> PlasticSection:
    ky = yield_curvature(law, wall)
    kb = break_curvatures(law, wall, segments, max_curvature_ratio)
    mb = moment_curvature(law, wall, kb)
    if law.has_linear_range:
        mb[0] = wall.bending_stiffness * kb[0]       # exact: every fibre is still elastic
    last = (mb[-1] - mb[-2]) / (kb[-1] - kb[-2])
    final = float(np.clip(bending_tangent(law, wall, kb[-1]), 0.0, last))
    k, r, k_inf = overlay_elements(kb, mb, final)
    n = k.size
    params = np.concatenate(([float(n), k_inf], k, r))
    return PlasticSection(params=params, history_width=2 * n + 1,
                          bending_stiffness=k_inf + float(k.sum()), yield_curvature=ky,
                          yield_moment=yield_moment(law, wall), plastic_moment=plastic_moment(law, wall),
                          break_curvatures=kb, break_moments=mb,
                          stress_geometry=stress_geometry(wall, law.yield_stress), law=law, wall=wall)


_fit_section_memo = lru_cache(maxsize=64)(_fit_section)


def wall_from_section(section) -> PipeWall:
    """The pipe wall of a compiled ``rfesim.model.sections.Section`` (pipe geometry only)."""
    D = section.outer_diameter
    A = section.steel_area
    if not (D > 0.0 and A > 0.0):
        raise ValueError("an elastoplastic material needs a pipe geometry (outer_diameter, wall_thickness, "
                         "youngs_modulus), not direct section properties")
    d = math.sqrt(max(D * D - 4.0 * A / math.pi, 0.0))
    inertia = math.pi / 64.0 * (D ** 4 - d ** 4)
    return PipeWall(D, 0.5 * (D - d), section.EIy / inertia)


def plastic_params(material, section, segments: int = 40, max_curvature_ratio: float = 100.0) -> PlasticSection:
    """Parameters of the SDE bending law for a scenario ``ElastoplasticMaterial`` and the
    compiled ``Section`` of its line type. ``result.params`` is the row of
    ``plastic_bending_into`` (same for every SDE of the line type; stack with
    ``pack_params``), ``result.history_width`` the history columns, zero initially."""
    wall = wall_from_section(section)
    law = law_from_material(material, wall.youngs_modulus)
    return plastic_section(law, wall, segments, max_curvature_ratio)


def pack_params(rows) -> tuple[np.ndarray, np.ndarray]:
    """Stack parameter rows (one per SDE, possibly of different n) into the (nsde, np)
    params array, padding with zeros; returns (params, zero history (nsde, nh))."""
    rows = [np.asarray(r, dtype=float) for r in rows]
    width = max(r.size for r in rows)
    params = np.zeros((len(rows), width))
    for i, r in enumerate(rows):
        params[i, :r.size] = r
    nh = max(2 * int(r[0]) + 1 for r in rows)
    return params, np.zeros((len(rows), nh))
