//! The physical range of every kind of number the toolkit reads, written once: an input outside
//! its range is refused with the range in the message (it is a mistake of units, a typo or a
//! careless script, never a crash to reconstruct).

/// A closed range of accepted values, with its unit and what it covers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Smallest accepted value.
    pub lo: f64,
    /// Largest accepted value.
    pub hi: f64,
    /// Unit of both ends.
    pub unit: &'static str,
}

/// Vehicle mass, kg: from a light motorcycle to a rail vehicle or a heavy-haul combination
/// (1,000 t). Above a loaded heavy truck's 60 t a case draws a plausibility warning
/// ([`crate::plausibility::PLAUSIBLE_MASS`]), not an error.
pub const MASS: Range = Range {
    lo: 100.0,
    hi: 1.0e6,
    unit: "kg",
};

/// Yaw moment of inertia, kg m^2: up to the largest mass with the radius of gyration of a
/// 50 m long vehicle (`k^2 = L^2 / 12`, about 210 m^2).
pub const YAW_INERTIA: Range = Range {
    lo: 10.0,
    hi: 2.5e8,
    unit: "kg m^2",
};

/// Distance from a CG to the impact centre, m.
pub const DISTANCE: Range = Range {
    lo: 0.0,
    hi: 30.0,
    unit: "m",
};

/// An angle, degrees (headings, impact-centre angles, the crush-surface angle): one turn either
/// way; larger values are a mistake, not an angle to wrap.
pub const ANGLE: Range = Range {
    lo: -360.0,
    hi: 360.0,
    unit: "deg",
};

/// A tyre-road friction coefficient: from 0.01 (a tenth of wet ice's) to 1.5 (above a racing
/// tyre's on dry asphalt). Written once for the road, a surface, a vehicle and a skid.
pub const FRICTION: Range = Range {
    lo: 0.01,
    hi: 1.5,
    unit: "",
};

/// A velocity component, m/s (360 km/h).
pub const SPEED: Range = Range {
    lo: -100.0,
    hi: 100.0,
    unit: "m/s",
};

/// A yaw rate, rad/s (about 860 deg/s).
pub const YAW_RATE: Range = Range {
    lo: -15.0,
    hi: 15.0,
    unit: "rad/s",
};

/// A measured delta-V (a magnitude), m/s.
pub const DELTA_V: Range = Range {
    lo: 0.0,
    hi: 100.0,
    unit: "m/s",
};

/// Largest number of draws a run accepts (each draw is a full fit: a million Q3 draws take about
/// a minute on two cores, and the draws' results are kept in memory).
pub const MAX_DRAWS: usize = 1_000_000;

/// Largest number of worker threads accepted (more only adds overhead on any machine this
/// runs on; the default is the machine's cores).
pub const MAX_THREADS: usize = 256;

/// A number outside its [`Range`] (or not a number): the message says the range and the value
/// ("must be a number between lo and hi unit, got x").
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("must be a number between {} and {}{}, got {}", .range.lo, .range.hi, unit_after(.range.unit), short(*.got))]
pub struct OutOfRange {
    /// The range it should lie in.
    pub range: Range,
    /// The value given.
    pub got: f64,
}

/// A unit after a number: a space before it, nothing for none.
fn unit_after(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}

impl Range {
    /// [`OutOfRange`] when `x` is not a finite number in the range.
    pub fn check(&self, x: f64) -> Result<(), OutOfRange> {
        if x.is_finite() && x >= self.lo && x <= self.hi {
            Ok(())
        } else {
            Err(OutOfRange {
                range: *self,
                got: x,
            })
        }
    }
}

/// A number as a person reads it: plain when moderate, in exponent form when huge or tiny.
pub fn short(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-3..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_accept_their_ends_and_refuse_beyond_and_non_finite() {
        assert!(MASS.check(100.0).is_ok() && MASS.check(1.0e6).is_ok());
        for bad in [99.9, 1e-300, f64::NAN, f64::INFINITY, -1.0, 1.000001e6] {
            assert!(MASS.check(bad).is_err(), "{bad}");
        }
        let e = SPEED.check(1e308).unwrap_err();
        assert_eq!(e.range, SPEED);
        assert_eq!(
            e.to_string(),
            "must be a number between -100 and 100 m/s, got 1e308"
        );
        assert_eq!(
            MASS.check(f64::NAN).unwrap_err().to_string(),
            "must be a number between 100 and 1000000 kg, got NaN"
        );
        assert!(DELTA_V.check(-3.0).is_err());
    }
}
