//! The values a case estimates where the file leaves them out, and how each is named (a note,
//! not a warning: an estimate is a stated choice, not a mistake).

use crate::case::Case;
use crate::inertia::{from_outline, RULE};
use crate::sections::{InertiaSource, VehicleSection};

impl VehicleSection {
    /// The vehicle's outline about its CG, m: its length and width as given, each left out
    /// estimated from its mass ([`pim_core::outline::typical_dimensions`]), its CG halfway
    /// along where `cg_to_front` is left out; and whether the length or the width was
    /// estimated. The one place these defaults are applied.
    pub fn outline(&self) -> (pim_core::outline::Outline, bool) {
        let (length, width) = match (self.length, self.width) {
            (Some(l), Some(w)) => (l, w),
            (l, w) => {
                let (tl, tw) = pim_core::outline::typical_dimensions(self.mass);
                (l.unwrap_or(tl), w.unwrap_or(tw))
            }
        };
        let front = self.cg_to_front.unwrap_or(length / 2.0);
        let outline = pim_core::outline::Outline {
            cg_to_front: front,
            cg_to_rear: length - front,
            width,
        };
        (outline, self.length.is_none() || self.width.is_none())
    }
}

impl Case {
    /// The spreads of the case's `[uncertainty]` as loaded (none where it has no such
    /// section): the one place its absence is read as "nothing drawn".
    pub fn spreads(&self) -> crate::spread::UncertaintySection {
        self.content.uncertainty.unwrap_or_default()
    }

    /// Gives each vehicle without a yaw inertia the estimate from its outline (in SI, after
    /// the units are converted; the loader has checked that such a vehicle writes its length
    /// and width) and records it as estimated.
    pub(crate) fn estimate_inertias(&mut self) {
        let c = &mut self.content;
        for v in [&mut c.vehicle1, &mut c.vehicle2] {
            if let (true, Some(length), Some(width)) = (v.yaw_inertia.is_nan(), v.length, v.width) {
                v.yaw_inertia = from_outline(v.mass, length, width);
                v.yaw_inertia_source = InertiaSource::Outline;
            }
        }
    }

    /// Each estimated value of the case, in words naming its rule and inputs in SI (for
    /// stderr and reports; not a warning: an estimate is a stated choice, not a mistake).
    pub fn estimated(&self) -> Vec<String> {
        let (c, u) = (&self.content, &self.written_units);
        let (mass, length) = (u.mass.to_si(), u.length.to_si());
        [("vehicle1", &c.vehicle1), ("vehicle2", &c.vehicle2)]
            .into_iter()
            .filter(|(_, v)| v.yaw_inertia_source == InertiaSource::Outline)
            .map(|(name, v)| {
                let side = |x: Option<f64>| x.unwrap_or(f64::NAN) / length;
                format!(
                    "{name}.yaw_inertia: not given, estimated as {:.0} {} from mass {:.0} {}, \
                     length {:.2} and width {:.2} {} as {RULE}, within 11 % of the RICSAC \
                     cars' listed inertias; give the measured value if known",
                    v.yaw_inertia / u.yaw_inertia.to_si(),
                    crate::units::unit_label(u.yaw_inertia),
                    v.mass / mass,
                    crate::units::unit_label(u.mass),
                    side(v.length),
                    side(v.width),
                    u.length.label(),
                )
            })
            .collect()
    }
}
