//! Normal and tangential restitution with a friction limit: e, et, friction.

use super::questions::{Family, Friction, Sticking};
use crate::certificate::Fallback;

/// The tangential model as the fit sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tangential;

impl Family for Tangential {
    fn name(&self) -> &'static str {
        "tangential"
    }
    fn description(&self) -> &'static str {
        "Normal and tangential restitution with a friction limit: e, et, friction (no moment \
         impulse; one branch)"
    }
    fn moment_impulse(&self) -> bool {
        false
    }
    fn friction(&self) -> Friction {
        Friction::Limit
    }
    fn sticking(&self) -> Sticking {
        Sticking::Restitution
    }
    fn sign_follows_sliding(&self) -> bool {
        false
    }
    fn convex_route(&self) -> Result<(), Fallback> {
        Ok(())
    }
}
