//! Why the optimum over the geometry box is not proved: the bound is written for a class of
//! problems, and a box's centre must be a collision.

/// Why [`super::prove`] gives no proof ([`crate::ProofStatus::NotAttempted`], its reason the
/// message).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Unproved {
    /// A barrier impact.
    #[error("a barrier")]
    Barrier,
    /// A model other than PIM's friction.
    #[error("the bound over the geometry is written for PIM only")]
    NotPim,
    /// The `mu <= mu_max` condition off.
    #[error("the mu <= mu_max condition is off")]
    NoMuMax,
    /// The crush surface's side fixed by the case or its estimates.
    #[error(
        "the case states the side of the crush surface, or its estimates fix it (the bound \
         reads it from the geometry)"
    )]
    SideFixed,
    /// A cost that couples components or leaves a free one unweighted.
    #[error("the cost couples components (observations) or leaves a free component unweighted")]
    CostNotSeparable,
    /// A box's centre that is no valid collision.
    #[error("a box's centre is not a valid collision")]
    InvalidCentre,
}
