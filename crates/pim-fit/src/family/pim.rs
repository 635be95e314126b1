//! Planar Impact Mechanics: e, mu, e_m.

use super::questions::{Family, Friction, Sticking};
use crate::certificate::Fallback;

/// PIM as the fit sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pim;

impl Family for Pim {
    fn name(&self) -> &'static str {
        "pim"
    }
    fn description(&self) -> &'static str {
        "Planar Impact Mechanics: e, mu, em (both moment branches)"
    }
    fn moment_impulse(&self) -> bool {
        true
    }
    fn friction(&self) -> Friction {
        Friction::Equivalent
    }
    fn sticking(&self) -> Sticking {
        Sticking::NoSlip
    }
    fn sign_follows_sliding(&self) -> bool {
        true
    }
    fn convex_route(&self) -> Result<(), Fallback> {
        Ok(())
    }
}
