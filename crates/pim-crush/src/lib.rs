//! # pim-crush: crush energy from damage profiles (CRASH3's linear stiffness model)
//!
//! The structure of a vehicle's damaged face is modelled, per unit of damage width, as a
//! force linear in the residual crush depth `C` (Campbell 1974; McHenry's CRASH3):
//!
//! ```text
//! F / w = A + B C                                    (N/m, with A in N/m and B in N/m^2)
//! E / w = A C + B C^2 / 2 + G,   G = A^2 / (2 B)     (J/m)
//! ```
//!
//! `G` is the energy absorbed without residual crush (below the no-damage speed). The energy of
//! a damage profile is the integral of `E / w` over the damage width `L`, the crush depths
//! measured at `n >= 2` equally spaced points across it (CRASH3 measures 2, 4 or 6) and taken
//! as linear between them ([`crush_energy`]). For the usual counts this is CRASH3's
//! closed form; for six points:
//!
//! ```text
//! E = L/5 [ A/2 (C1 + 2 C2 + 2 C3 + 2 C4 + 2 C5 + C6)
//!         + B/6 (C1^2 + 2 C2^2 + 2 C3^2 + 2 C4^2 + 2 C5^2 + C6^2
//!                + C1 C2 + C2 C3 + C3 C4 + C4 C5 + C5 C6)
//!         + 5 G ]
//! ```
//!
//! ([`crash3_energy`] writes these forms out as published).
//!
//! **The direction of force.** The stiffness is measured in tests whose force is normal to the
//! face; CRASH3 scales the energy of an oblique impact by `1 + tan^2(alpha)`, alpha the
//! principal direction of force relative to the face's normal, held at 45 deg beyond that
//! ([`pdof_factor`]: 1 at 0 deg, 2 at 45 deg and beyond).
//!
//! **Stiffness from a barrier test.** In a full-width rigid-barrier test at speed `V` with
//! uniform residual crush `C` and a no-damage speed `b0`, the speed is taken as linear in the
//! crush, `V = b0 + b1 C`; equating the kinetic energy per unit width, `m V^2 / (2 w)`, with
//! `A C + B C^2 / 2 + G` for every `C` gives `A = m b0 b1 / w`, `B = m b1^2 / w` and
//! `G = m b0^2 / (2 w)` ([`Stiffness::from_barrier_test`]). The energy of that test's crush then
//! returns its speed exactly ([`barrier_equivalent_speed`]).
//!
//! **The other vehicle's crush.** Where only one vehicle's damage was measured, the force per
//! unit width is the same on both faces of the interface, `A1 + B1 C1 = A2 + B2 C2`, which gives
//! the other's depths point by point (CRASH3's rule; [`balanced_profile`]).
//!
//! **The energy's standard deviation** follows to first order from independent errors of A, B,
//! the width and each depth ([`crush_energy_sigma`], each partial derivative exact).
//!
//! **What the energy is compared with** ([`EnergyRelation`]). A stiffness calibrated on
//! `m V^2 / 2` in barrier tests measures the energy absorbed up to maximum crush. CRASH3 sets
//! that energy equal to the kinetic energy the collision loses (the default here); with
//! restitution e a central impact loses only `(1 - e^2)` of it, which is the other reading.
//!
//! **CRASH3's delta-V.** With no restitution and a common velocity of the contact points along
//! the impulse `P` at its end, the energy lost is `E = P^2 / 2 (1/(g1 m1) + 1/(g2 m2))`, where
//! `g = k^2 / (k^2 + h^2)` is the effective-mass factor of the impulse's moment arm `h` about the
//! CG (`k^2 = I / m`; [`effective_mass_factor`]): the struck point of a rigid body of mass m
//! responds to P like a particle of mass `g m`. So
//!
//! ```text
//! P = sqrt(2 E (g1 m1)(g2 m2) / (g1 m1 + g2 m2)),     dV_i = P / m_i   (of the CG)
//! ```
//!
//! ([`crash3_delta_v`]); with `h = 0` on both it is the point-mass delta-V of a central
//! collinear collision with e = 0, `dV1 = sqrt(2 E m2 / (m1 (m1 + m2)))`. Against a rigid
//! barrier `P = sqrt(2 E g1 m1)`.
//!
//! Units: SI throughout (m, kg, J, N, N/m, N/m^2). No I/O.

mod collision;
mod energy;

pub use collision::{
    balanced_profile, crash3_delta_v, crush_energy_sigma, effective_mass_factor, EnergyRelation,
    ProfileSigmas,
};

pub use energy::{
    barrier_equivalent_speed, crash3_energy, crush_energy, pdof_factor, CrushError, Profile,
    Stiffness, MAX_PDOF_CORRECTION_ANGLE,
};
