//! `[[runout.zones]]`: areas of the ground with a friction of their own, read into
//! pim-runout's [`Zone`]s (SI, the natural frame), each wheel of either run-out on the
//! friction under it.
//!
//! ```toml
//! [[runout.zones]]
//! name = "parking lot"          # optional, for the figures
//! friction = 0.45
//! friction_sigma = 0.05         # optional: fit the zone's friction about it, this sd its prior
//! corners = [ [20.0, -5.0], [40.0, -5.0], [40.0, 12.0], [20.0, 12.0] ]   # length unit
//! ```
//!
//! The corners are in the case's fixed frame and length unit, in order (either sense); a later
//! zone lies over an earlier one where they overlap. Outside every zone the wheels run on the
//! road's friction (`[runout] friction`, or the vehicle's own). The fit holds a zone's friction
//! as stated; with `friction_sigma` it fits it with the speeds, as `[runout] friction_sigma`
//! fits the road's (the stated value a prior of that deviation), and the uncertainty study
//! draws the prior's centre by it.

use crate::case::Case;
use crate::error::Result;
use crate::scene_sections::ZoneSection;
use pim_runout::Zone;

impl Case {
    /// The zones `written`, lengths by `length` and y mirrored by `flip`, each checked; the
    /// error names the zone's field.
    pub(crate) fn zones_of(
        &self,
        written: &[ZoneSection],
        (length, flip): (f64, f64),
    ) -> Result<Vec<Zone>> {
        written
            .iter()
            .enumerate()
            .map(|(k, z)| {
                let zone = Zone {
                    corners: z
                        .corners
                        .iter()
                        .map(|c| [c[0] * length, flip * c[1] * length])
                        .collect(),
                    friction: z.friction,
                };
                zone.check().map_err(|(field, why)| {
                    self.error_at(&format!("runout.zones[{k}].{field}"), why)
                })?;
                if let Some(sd) = z.friction_sigma.filter(|sd| !(sd.is_finite() && *sd > 0.0)) {
                    return Err(self.error_at(
                        &format!("runout.zones[{k}].friction_sigma"),
                        format!("{sd}: must be a number above 0"),
                    ));
                }
                Ok(zone)
            })
            .collect()
    }
}
