//! # pim-fit: least-squares estimation of the PIM coefficients
//!
//! Finds the impact coefficients (e, mu, e_m) and the twelve velocity components that satisfy
//! the six Planar Impact Mechanics equations of [`pim_core`] and come closest, in weighted least
//! squares, to measured or estimated velocities.
