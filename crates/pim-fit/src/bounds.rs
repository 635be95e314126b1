//! Which of a fit's active constraints are search bounds: limits of the search that a user
//! chooses in `[bounds]` (or that a default chooses for them), as opposed to the physics.
//!
//! An answer that rests on a search bound is decided by that bound, not by the data: widening
//! it moves the answer. The ends of a coefficient's physical range are not search bounds (e = 0,
//! a perfectly plastic impact; |et| = 1; a friction limit of 0), nor are the conditions of the
//! model itself (approach at C, no energy created, mu <= mu_max, em in [-1, 0]).

use crate::report::ActiveConstraint;
use crate::settings::FitSettings;
use serde::Serialize;

/// A limit of the search that a fitted answer can rest on; named as its `[bounds]` key.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum SearchBound {
    /// The range of e.
    E,
    /// The range of mu.
    Mu,
    /// The range of the tangential model's et.
    Et,
    /// The range of the tangential model's friction limit.
    Friction,
    /// The bound on every linear velocity component, m/s.
    Velocity,
    /// The bound on every yaw rate, rad/s.
    YawRate,
}

impl SearchBound {
    /// Every search bound, in `[bounds]` order.
    pub const ALL: [SearchBound; 6] = [
        SearchBound::E,
        SearchBound::Mu,
        SearchBound::Et,
        SearchBound::Friction,
        SearchBound::Velocity,
        SearchBound::YawRate,
    ];

    /// The key of the bound in a case file's `[bounds]`.
    pub fn name(self) -> &'static str {
        match self {
            SearchBound::E => "e",
            SearchBound::Mu => "mu",
            SearchBound::Et => "et",
            SearchBound::Friction => "friction",
            SearchBound::Velocity => "velocity",
            SearchBound::YawRate => "yaw_rate",
        }
    }
}

impl std::fmt::Display for SearchBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl ActiveConstraint {
    /// The search bound this active constraint is, with the limit it reached under `settings`
    /// (SI: m/s, rad/s, or the coefficient), or `None` when the constraint is physics or the end
    /// of a coefficient's physical range (see the module docs).
    pub fn search_bound(&self, settings: &FitSettings) -> Option<(SearchBound, f64)> {
        use ActiveConstraint as A;
        use SearchBound as B;
        let s = settings;
        let (bound, limit, physical) = match *self {
            A::VelocityBound(k) if k.0 % 3 == 2 => (B::YawRate, s.yaw_rate_bound, false),
            A::VelocityBound(_) => (B::Velocity, s.velocity_bound, false),
            A::ELow => (B::E, s.e[0], s.e[0] <= 0.0),
            A::EHigh => (B::E, s.e[1], s.e[1] >= 1.0),
            A::MuLow => (B::Mu, s.mu[0], s.mu[0] <= 0.0),
            A::MuHigh | A::StickingMuBound => (B::Mu, s.mu[1], false),
            A::EtLow => (B::Et, s.et[0], s.et[0] <= -1.0),
            A::EtHigh => (B::Et, s.et[1], s.et[1] >= 1.0),
            A::FrictionLow => (B::Friction, s.friction[0], s.friction[0] <= 0.0),
            A::FrictionHigh | A::FrictionBound => (B::Friction, s.friction[1], false),
            A::MinimumApproach
            | A::SlidingDirection
            | A::MuMax
            | A::StickSlide
            | A::Energy
            | A::EmLow
            | A::EmHigh
            | A::MuZero => return None,
        };
        (!physical).then_some((bound, limit))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Component;

    #[test]
    fn physical_ends_are_not_search_bounds() {
        let s = FitSettings::default();
        assert_eq!(ActiveConstraint::ELow.search_bound(&s), None);
        assert_eq!(
            ActiveConstraint::EHigh.search_bound(&s),
            Some((SearchBound::E, s.e[1]))
        );
        assert_eq!(ActiveConstraint::MuMax.search_bound(&s), None);
        assert_eq!(ActiveConstraint::EmLow.search_bound(&s), None);
        let narrowed = FitSettings {
            e: [0.1, 1.0],
            ..FitSettings::default()
        };
        assert_eq!(
            ActiveConstraint::ELow.search_bound(&narrowed),
            Some((SearchBound::E, 0.1))
        );
        assert_eq!(ActiveConstraint::EHigh.search_bound(&narrowed), None);
    }

    #[test]
    fn a_yaw_component_is_the_yaw_rate_bound() {
        let s = FitSettings::default();
        assert_eq!(
            ActiveConstraint::VelocityBound(Component(8)).search_bound(&s),
            Some((SearchBound::YawRate, s.yaw_rate_bound))
        );
        assert_eq!(
            ActiveConstraint::VelocityBound(Component(6)).search_bound(&s),
            Some((SearchBound::Velocity, s.velocity_bound))
        );
    }
}
