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
//! Units: SI throughout (m, kg, J, N). No I/O.

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
