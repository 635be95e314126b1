//! The frictions a case states for its run-outs and which of them the reconstruction fits:
//! the road's (`[runout] friction`, with its spread `friction_sigma`), a vehicle's own surface
//! (`[runout.vehicleN] friction`) and each friction zone's (`[[runout.zones]]`).

use crate::case::Case;

/// A friction zone's friction as the reconstruction may fit it.
#[derive(Debug, Clone, PartialEq)]
pub struct ZoneFriction {
    /// The zone's index in `[[runout.zones]]`, from 0.
    pub zone: usize,
    /// Its name for the tables (its own, else `zone N`).
    pub name: String,
    /// Its stated friction.
    pub friction: f64,
    /// Its standard deviation, where the case gives one (then the friction is fitted).
    pub sigma: Option<f64>,
}

impl Case {
    /// The standard deviation of the road friction (`[runout] friction_sigma`): the
    /// reconstruction fits the road's friction (and a vehicle's own surface's) with it.
    pub fn road_friction_sigma(&self) -> Option<f64> {
        self.content.runout.as_ref().and_then(|r| r.friction_sigma)
    }

    /// True when vehicle `k` (0 or 1) runs out on a surface of its own
    /// (`[runout.vehicleN] friction`), not on the road's friction.
    pub fn runs_on_own_surface(&self, k: usize) -> bool {
        self.content.runout.as_ref().is_some_and(|r| {
            if k == 0 { &r.vehicle1 } else { &r.vehicle2 }
                .as_ref()
                .is_some_and(|v| v.friction.is_some())
        })
    }

    /// The case with its road friction `mu` (`[runout] friction`; nothing without a
    /// `[runout]`): a run-out drawn on a fitted friction.
    pub fn set_road_friction(&mut self, mu: f64) {
        if let Some(r) = self.content.runout.as_mut() {
            r.friction = Some(mu);
        }
    }

    /// The case with friction zone `k`'s friction `mu` (nothing where it has no such zone).
    pub fn set_zone_friction(&mut self, k: usize, mu: f64) {
        if let Some(z) = self
            .content
            .runout
            .as_mut()
            .and_then(|r| r.zones.get_mut(k))
        {
            z.friction = mu;
        }
    }

    /// The friction zones, in the file's order.
    pub fn zone_frictions(&self) -> Vec<ZoneFriction> {
        self.content.runout.as_ref().map_or_else(Vec::new, |r| {
            r.zones
                .iter()
                .enumerate()
                .map(|(k, z)| ZoneFriction {
                    zone: k,
                    name: z.display_name(k),
                    friction: z.friction,
                    sigma: z.friction_sigma,
                })
                .collect()
        })
    }
}
