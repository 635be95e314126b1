//! What a fit needs to know of an impact model, asked once per question.
//!
//! The fit's inner problem, its search and its convex route never ask which model they fit;
//! they ask the model's [`Family`]: whether it has a moment impulse (and so moment branches and
//! a moment form), what its third coefficient means (PIM's equivalent friction, bounded by
//! mu_max, or a friction limit), how its sticking mode maps a contact state to separation, how
//! the friction sign is chosen, and whether the exact convex route is written for it.
//!
//! A model for the fit is one file here implementing [`Family`] and one registration in
//! [`FitModel::family`](crate::FitModel::family).

mod pim;
mod questions;
mod tangential;

pub(crate) use pim::Pim;
pub(crate) use questions::{Family, Friction, Sticking};
pub(crate) use tangential::Tangential;
