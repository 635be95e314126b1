//! Which side of the crush surface each vehicle is on, and what that rests on: the geometry,
//! the mobility-weighted reading, the case's statement, or the case's estimated contact
//! velocities.

use crate::model::{Impact, SideBasis, Velocities};

impl Impact {
    /// The impact with vehicle 1 stated on the `+n` (`side` = +1) or `-n` (-1) side.
    pub fn with_side(mut self, side: f64) -> Self {
        self.side = side.signum();
        self.side_basis = SideBasis::Case;
        self
    }

    /// Where the geometry leaves the side open ([`SideBasis::Mobility`]): the side under which
    /// the contact velocities `v` approach at C, when exactly one of the two does; otherwise
    /// the impact unchanged (both or neither approach: mobility decides).
    pub fn with_side_from_velocities(self, v: &Velocities) -> Self {
        if self.side_basis != SideBasis::Mobility {
            return self;
        }
        let approaches = |side: f64| {
            let mut i = self;
            i.side = side;
            i.check_approach(v).is_ok()
        };
        match (approaches(1.0), approaches(-1.0)) {
            (true, false) | (false, true) => {
                let mut i = self;
                i.side = if approaches(1.0) { 1.0 } else { -1.0 };
                i.side_basis = SideBasis::Velocities;
                i
            }
            _ => self,
        }
    }

    /// True when the side is fixed for every geometry of a fit (stated by the case, or read
    /// from its contact-velocity estimates), not read anew from each geometry.
    pub fn side_is_fixed(&self) -> bool {
        matches!(self.side_basis, SideBasis::Case | SideBasis::Velocities)
    }
}
