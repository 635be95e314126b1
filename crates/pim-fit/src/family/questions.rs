//! The questions a fit asks of a model, and the kinds of their answers.

use crate::certificate::Fallback;
use crate::problem::MomentBranch;
use pim_core::MomentForm;

/// What the third coefficient of a model means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Friction {
    /// PIM's equivalent friction: `mu = Pt / Pn` within the mu bounds and between 0 and mu_max.
    Equivalent,
    /// A friction limit: `|Pt| <= friction |Pn|` (sliding at the limit, sticking within it, with
    /// `et` the second coefficient of the sticking mode).
    Limit,
}

/// How the sticking mode maps a contact state to separation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sticking {
    /// PIM's no-slip condition through its six equations (equation 5a).
    NoSlip,
    /// Tangential restitution `vt' = -et vt` through pim-core's `stick_transfer`.
    Restitution,
}

/// The questions a fit asks of a model.
pub(crate) trait Family: Sync {
    /// The model's name in case files and on the command line.
    fn name(&self) -> &'static str;
    /// What the model fits, in a line.
    fn description(&self) -> &'static str;
    /// Whether the model has a moment impulse (PIM's e_m and its branches).
    fn moment_impulse(&self) -> bool;
    /// What the third coefficient means.
    fn friction(&self) -> Friction;
    /// How the sticking mode maps a contact state.
    fn sticking(&self) -> Sticking;
    /// Whether the friction sign follows the sliding direction of a known contact state that
    /// slides (PIM), or is always searched on both sides (a friction limit whose sign is the
    /// side of the sticking impulse).
    fn sign_follows_sliding(&self) -> bool;
    /// Why the exact convex route does not solve this model, if it does not.
    fn convex_route(&self) -> Result<(), Fallback>;

    /// The moment branches fitted, of those asked: all of them with a moment impulse, else only
    /// the zero branch (the one place this rule is written).
    fn branches(&self, asked: &[MomentBranch]) -> Vec<MomentBranch> {
        if self.moment_impulse() {
            asked.to_vec()
        } else {
            vec![MomentBranch::Zero]
        }
    }

    /// The moment form of the equations: the one asked with a moment impulse; without one,
    /// the sliding mode is PIM's with e_m = 1, where the forms agree, so the corrected one.
    fn moment_form(&self, asked: MomentForm) -> MomentForm {
        if self.moment_impulse() {
            asked
        } else {
            MomentForm::Corrected
        }
    }
}
