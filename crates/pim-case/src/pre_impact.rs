//! The `[pre_impact.vehicleN]` sections resolved: each vehicle's EDR records and its recorded
//! pre-crash table in m/s, its skid before the impact in metres and radians with every default
//! applied (a locked skid, a level road, the road's friction), each value checked against
//! what an EDR records and a road allows, once, with its place in the file for the message.
//!
//! An EDR speed `v` recorded `t` seconds before contact, with a mean deceleration `a` (in g)
//! between, is evidence on the speed along the heading at contact, `v - a g t`
//! ([`EdrRecord::at_contact`]).

use crate::case::Case;
use crate::fit_sections::SIGMA_MIN;
use crate::scene_sections::{EdrRow, EdrWritten, PreImpactVehicleSection};
use crate::Result;
use pim_runout::GRAVITY;

/// One EDR record as evidence, in SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdrRecord {
    /// Its index in the vehicle's `edr` list (its place in the file).
    pub record: usize,
    /// How long before contact it was recorded, s.
    pub time: f64,
    /// The recorded speed, m/s.
    pub speed: f64,
    /// The mean deceleration from the record to contact, in g (negative: accelerating).
    pub deceleration: f64,
    /// The record's standard deviation, m/s.
    pub sigma: f64,
}

impl EdrRecord {
    /// The speed along the heading at contact it gives, `v - a g t`, m/s.
    pub fn at_contact(&self) -> f64 {
        self.speed - self.deceleration * GRAVITY * self.time
    }
}

/// A row of the EDR's recorded pre-crash table, in SI (drawn, not evidence).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdrHistoryRow {
    /// How long before contact, s.
    pub time: f64,
    /// The recorded speed, m/s.
    pub speed: f64,
    /// The service brake: on or off, where recorded.
    pub brake: Option<bool>,
    /// The accelerator pedal, percent of full, where recorded.
    pub accelerator: Option<f64>,
}

/// A skid before the impact, in SI, every default applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreImpactSkid {
    /// The length of the marks up to contact, m.
    pub distance: f64,
    /// The share of the friction the braking used, 0 to 1 (1 unless stated: locked).
    pub braking: f64,
    /// The grade along the travel, rad (positive uphill; 0 unless stated).
    pub grade: f64,
    /// The friction under the marks: its own where stated, else the road's
    /// ([`Case::road_friction`]).
    pub friction: f64,
    /// True when the section states the friction under the marks apart from the road's (the
    /// skid then does not brake on the run-outs' fitted road friction).
    pub friction_stated: bool,
}

/// A vehicle's `[pre_impact.vehicleN]`, resolved.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PreImpactVehicle {
    /// Its EDR records, in the file's order.
    pub edr: Vec<EdrRecord>,
    /// Its EDR's pre-crash table, oldest row first.
    pub history: Vec<EdrHistoryRow>,
    /// Its skid before the impact.
    pub skid: Option<PreImpactSkid>,
}

impl Case {
    /// The road's friction: `[runout] friction`, else pim-runout's default (0.7).
    pub fn road_friction(&self) -> f64 {
        self.content
            .runout
            .as_ref()
            .and_then(|r| r.friction)
            .unwrap_or(pim_runout::DEFAULT_FRICTION)
    }

    /// Each vehicle's `[pre_impact.vehicleN]` resolved (`None` where the case has none).
    ///
    /// # Errors
    /// A located error: a barrier's pre-impact section, an EDR record or table row outside
    /// what an EDR records (a speed from 0 to 150 m/s, 0 to 30 s before contact, a
    /// deceleration from -1.5 to 1.5 g, a standard deviation above 0, an accelerator from 0
    /// to 100 %), or braking, grade or friction without the skid's length.
    pub fn pre_impact_vehicles(&self) -> Result<[Option<PreImpactVehicle>; 2]> {
        let mut out = [None, None];
        for (k, slot) in out.iter_mut().enumerate() {
            let Some(p) = self.content.pre_impact(k) else {
                continue;
            };
            let place = format!("pre_impact.vehicle{}", k + 1);
            if k == 1 && self.is_barrier() {
                return Err(self.error_at(&place, "a barrier does not move"));
            }
            *slot = Some(self.pre_impact_vehicle(&place, p)?);
        }
        Ok(out)
    }

    fn pre_impact_vehicle(
        &self,
        place: &str,
        p: &PreImpactVehicleSection,
    ) -> Result<PreImpactVehicle> {
        let speed = self.written_units.speed.to_si();
        let length = self.written_units.length.to_si();
        let mut history = Vec::new();
        for (i, r) in p.edr_history.iter().enumerate() {
            history.push(self.history_row(&format!("{place}.edr_history[{i}]"), r, speed)?);
        }
        let mut edr = Vec::new();
        for (i, e) in p.edr.iter().enumerate() {
            self.check_edr(&format!("{place}.edr[{i}]"), e, speed)?;
            edr.push(EdrRecord {
                record: i,
                time: e.time,
                speed: e.speed * speed,
                deceleration: e.deceleration,
                sigma: e.sigma * speed,
            });
        }
        let skid = match p.skid {
            Some(d) => Some(PreImpactSkid {
                distance: d * length,
                braking: p.braking.unwrap_or(1.0),
                grade: (p.grade.unwrap_or(0.0) / 100.0).atan(),
                friction: p.friction.unwrap_or_else(|| self.road_friction()),
                friction_stated: p.friction.is_some(),
            }),
            None if p.braking.is_some() || p.grade.is_some() || p.friction.is_some() => {
                return Err(self.error_at(
                    place,
                    "braking, grade and friction describe a skid: give its length, `skid`",
                ));
            }
            None => None,
        };
        Ok(PreImpactVehicle { edr, history, skid })
    }

    /// A row of the EDR's table (`place` its path), checked as a record's time and speed, its
    /// accelerator a percentage.
    fn history_row(&self, place: &str, r: &EdrRow, speed: f64) -> Result<EdrHistoryRow> {
        let row = EdrWritten {
            speed: r.speed,
            time: r.time,
            deceleration: 0.0,
            sigma: 1.0,
        };
        self.check_edr(place, &row, speed)?;
        if let Some(a) = r.accelerator.filter(|a| !(0.0..=100.0).contains(a)) {
            return Err(self.error_at(place, format!("accelerator {a}: a percentage, 0 to 100")));
        }
        Ok(EdrHistoryRow {
            time: r.time,
            speed: r.speed * speed,
            brake: r.brake,
            accelerator: r.accelerator,
        })
    }

    /// Checks an EDR record (`place` its path in the file): its speed (in the file's unit,
    /// `speed` m/s each), time, deceleration and sigma.
    fn check_edr(&self, place: &str, e: &EdrWritten, speed: f64) -> Result<()> {
        let ok = |x: f64, lo: f64, hi: f64| x.is_finite() && x >= lo && x <= hi;
        if !ok(e.speed * speed, 0.0, pim_core::MAX_SPEED.min(150.0)) {
            return Err(self.error_at(place, format!("speed {}: from 0 to 150 m/s", e.speed)));
        }
        if !ok(e.time, 0.0, 30.0) {
            return Err(self.error_at(
                place,
                format!("time {}: seconds before contact, 0 to 30", e.time),
            ));
        }
        if !ok(e.deceleration, -1.5, 1.5) {
            return Err(self.error_at(
                place,
                format!("deceleration {}: in g, from -1.5 to 1.5", e.deceleration),
            ));
        }
        if !(e.sigma.is_finite() && e.sigma * speed >= SIGMA_MIN) {
            return Err(self.error_at(
                place,
                format!("sigma {}: a standard deviation above 0", e.sigma),
            ));
        }
        Ok(())
    }
}
