//! The fit sections of a case resolved: `[estimates]`, `[known]`, `[sigma]` / `[weights]`,
//! `[[observations]]` and `[bounds]` into the fit problem of `pim fit`, its settings and the
//! geometry it estimates, each default applied and each range checked here, once.

use crate::case::Case;
use crate::{InputError, Result};
use pim_core::VehicleId;
use pim_fit::{
    FitProblem, FitSettings, GeometryBound, Knowledge, MomentBranch, Observation, COMPONENT_NAMES,
};

/// What `--cost` selects: a preset, or the case's own known / estimated components.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CostChoice {
    /// Q1, Q2 or Q3 from `[estimates]`.
    Preset(pim_fit::CostPreset),
    /// `[known]` held fixed, `[estimates]` estimated, everything else unknown.
    Custom,
}

impl CostChoice {
    /// `q1`, `q2`, `q3`, or `custom` for the case's own cost.
    pub fn name(self) -> &'static str {
        match self {
            CostChoice::Preset(p) => p.name(),
            CostChoice::Custom => "custom",
        }
    }
}

impl serde::Serialize for CostChoice {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

pim_core::json_schema_as!(CostChoice, {"type": "string", "description": "The cost function: its name as the case file writes it."});

fn input(case: &Case, what: String) -> InputError {
    InputError::new(&case.file, what)
}

/// Smallest standard deviation accepted, m/s or rad/s: below it the inverse-variance weights
/// lose their meaning in floating point (a sigma of 1e-300 would be an infinite weight).
pub const SIGMA_MIN: f64 = 1e-6;

/// When the case gives standard deviations (`[sigma]`, `sigma` on observations): the common
/// unit `u` of its inverse-variance weights `w = u / sigma^2`, the smallest sigma squared
/// (m^2/s^2 or rad^2/s^2), so that every weight is in (0, 1] and the cost over `u` is a
/// chi-square. `None` without sigmas.
pub fn sigma_unit(case: &Case) -> Result<Option<f64>> {
    let c = &case.content;
    let sig = c.sigma.unwrap_or_default().components();
    let all: Vec<(String, f64)> = sig
        .iter()
        .enumerate()
        .filter_map(|(k, s)| s.map(|s| (format!("sigma.{}", COMPONENT_NAMES[k]), s)))
        .chain(
            c.observations
                .iter()
                .enumerate()
                .filter_map(|(i, o)| o.sigma.map(|s| (format!("observations[{i}].sigma"), s))),
        )
        .collect();
    if all.is_empty() {
        return Ok(None);
    }
    for (what, s) in &all {
        if !(s.is_finite() && *s >= SIGMA_MIN) {
            return Err(case.error_at(
                what,
                format!(
                    "{}: a standard deviation must be a number of at least {SIGMA_MIN} (m/s or \
                     rad/s)",
                    crate::ranges::short(*s)
                ),
            ));
        }
    }
    if let Some(w) = c.weights {
        // Name the entry given both ways, where there is one.
        let given = w.components();
        let both = (0..12).find(|&k| given[k].is_some() && sig[k].is_some());
        return Err(match both {
            Some(k) => case.error_at(
                &format!("weights.{}", COMPONENT_NAMES[k]),
                format!(
                    "given as a weight here and as a standard deviation in [sigma] \
                     ({}): give one of the two (a standard deviation makes the weight \
                     1/sigma^2)",
                    case.at(&format!("sigma.{}", COMPONENT_NAMES[k]))
                ),
            ),
            None => case.error_at(
                "weights",
                "give [sigma] (standard deviations) or [weights], not both",
            ),
        });
    }
    Ok(Some(
        all.iter().map(|(_, s)| s * s).fold(f64::INFINITY, f64::min),
    ))
}

/// The fit problem of a case.
pub fn problem(case: &Case, choice: CostChoice) -> Result<FitProblem> {
    let impact = case.impact()?;
    let c = &case.content;
    let est = c.estimates.unwrap_or_default().components();
    let unit = sigma_unit(case)?;
    let sig = c.sigma.unwrap_or_default().components();
    let weights = match unit {
        Some(u) => {
            let mut w = [None; 12];
            for k in 0..12 {
                w[k] = sig[k].map(|s| u / (s * s));
            }
            w
        }
        None => c.weights.unwrap_or_default().components(),
    };
    let known = c.known.unwrap_or_default().components();
    check_weights(case, choice, (&weights, &est), (unit, &sig))?;
    for (k, v) in est.iter().chain(known.iter()).enumerate() {
        if let Some(v) = v {
            if !v.is_finite() {
                let sec = if k < 12 { "estimates" } else { "known" };
                return Err(input(
                    case,
                    format!(
                        "[{sec}] {}: must be a finite number, got {v}",
                        COMPONENT_NAMES[k % 12]
                    ),
                ));
            }
        }
    }
    let barrier = case.is_barrier();
    if barrier {
        check_barrier(case, (&est, &known, &sig))?;
    }
    let components = components_of(case, choice, (&est, &known, &weights), barrier)?;
    let observations = observations_of(case, unit)?;
    if unit.is_some() {
        for k in 0..12 {
            if matches!(components[k], Knowledge::Estimated { .. }) && sig[k].is_none() {
                return Err(input(
                    case,
                    format!(
                        "[sigma] {}: missing; with [sigma] every estimate needs a standard deviation",
                        COMPONENT_NAMES[k]
                    ),
                ));
            }
        }
    }
    let problem = FitProblem {
        impact,
        components,
        observations,
        combinations: Vec::new(),
    };
    problem.check().map_err(|e| input(case, e.to_string()))?;
    Ok(problem)
}

/// The weights (or standard deviations) checked: each within (0, 1] and, outside the presets,
/// of an estimate.
fn check_weights(
    case: &Case,
    choice: CostChoice,
    (weights, est): (&Components, &Components),
    (unit, sig): (Option<f64>, &Components),
) -> Result<()> {
    for (k, w) in weights.iter().enumerate() {
        if let Some(w) = w {
            if !(w.is_finite() && *w > 0.0 && *w <= 1.0) {
                return Err(match (unit, sig[k]) {
                    // A weight from a standard deviation: say it of what the file wrote.
                    (Some(u), Some(s)) => case.error_at(
                        &format!("sigma.{}", COMPONENT_NAMES[k]),
                        format!(
                            "a standard deviation of {} is {:.1e} times the smallest of the \
                             case ({}): its weight 1/sigma^2 underflows to 0. Give a standard \
                             deviation within 1e100 of the smallest, or leave the estimate out",
                            crate::ranges::short(s),
                            s / u.sqrt(),
                            crate::ranges::short(u.sqrt())
                        ),
                    ),
                    _ => case.error_at(
                        &format!("weights.{}", COMPONENT_NAMES[k]),
                        format!("weight {w} must be in (0, 1]"),
                    ),
                });
            }
            if est[k].is_none() && !matches!(choice, CostChoice::Preset(_)) {
                return Err(input(
                    case,
                    format!(
                        "[weights] / [sigma] {}: a weight or sigma without an estimate",
                        COMPONENT_NAMES[k]
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A barrier case gives vehicle 2 no velocities and no observations.
fn check_barrier(
    case: &Case,
    (est, known, sig): (&Components, &Components, &Components),
) -> Result<()> {
    let c = &case.content;
    let given_weights = c.weights.unwrap_or_default().components();
    for k in [3, 4, 5, 9, 10, 11] {
        for (sec, given) in [
            ("estimates", est[k].is_some()),
            ("known", known[k].is_some()),
            ("sigma", sig[k].is_some()),
            ("weights", given_weights[k].is_some()),
        ] {
            if given {
                return Err(input(
                    case,
                    format!(
                        "[{sec}] {}: vehicle 2 is a fixed barrier (barrier = true), at rest \
                         before and after the impact; leave its velocities out",
                        COMPONENT_NAMES[k]
                    ),
                ));
            }
        }
    }
    if let Some(i) = c.observations.iter().position(|o| o.vehicle == 2) {
        return Err(case.error_at(
            &format!("observations[{i}].vehicle"),
            "vehicle = 2 is a fixed barrier, which has no delta-V or speed to observe",
        ));
    }
    Ok(())
}

/// What the fit knows of each component: known, estimated (with its weight) or unknown, by
/// the preset or as the case says.
fn components_of(
    case: &Case,
    choice: CostChoice,
    (est, known, weights): (&Components, &Components, &Components),
    barrier: bool,
) -> Result<[Knowledge; 12]> {
    let mut components = [Knowledge::Unknown; 12];
    match choice {
        CostChoice::Preset(preset) => {
            if known.iter().any(Option::is_some) {
                return Err(input(case, format!(
                    "[known] is for fits without --cost; with --cost {} the preset decides what is known",
                    preset.name()
                )));
            }
            // A barrier's components are held at 0 by the fit itself.
            let needed: Vec<usize> = (0..12).filter(|k| !barrier || k % 6 < 3).collect();
            for k in needed {
                let Some(value) = est[k] else {
                    let whose = if barrier {
                        " (of vehicle 1: vehicle 2 is a barrier)"
                    } else {
                        ""
                    };
                    return Err(input(case, format!(
                        "--cost {} needs every component of [estimates.initial] and [estimates.final]{whose}; {} is missing",
                        preset.name(),
                        COMPONENT_NAMES[k]
                    )));
                };
                components[k] = if preset.holds_fixed(k) {
                    Knowledge::Known { value }
                } else {
                    Knowledge::Estimated {
                        value,
                        weight: weights[k].unwrap_or(1.0),
                    }
                };
            }
        }
        CostChoice::Custom => {
            for k in 0..12 {
                components[k] = match (known[k], est[k]) {
                    (Some(_), Some(_)) => {
                        return Err(input(
                            case,
                            format!(
                                "{} is both in [known] and in [estimates]; it can only be one",
                                COMPONENT_NAMES[k]
                            ),
                        ))
                    }
                    (Some(value), None) => Knowledge::Known { value },
                    (None, Some(value)) => Knowledge::Estimated {
                        value,
                        weight: weights[k].unwrap_or(1.0),
                    },
                    (None, None) => Knowledge::Unknown,
                };
            }
        }
    }
    Ok(components)
}

/// The case's observations, each weighted by its standard deviation where the case gives
/// `[sigma]`.
fn observations_of(case: &Case, unit: Option<f64>) -> Result<Vec<Observation>> {
    let mut observations = Vec::new();
    for (i, o) in case.content.observations.iter().enumerate() {
        let vehicle = match o.vehicle {
            1 => VehicleId::One,
            2 => VehicleId::Two,
            n => {
                return Err(case.error_at(
                    &format!("observations[{i}].vehicle"),
                    format!("{n}; accepted: 1 or 2"),
                ))
            }
        };
        let weight = match (unit, o.sigma) {
            (Some(u), Some(s)) => u / (s * s),
            (Some(_), None) => {
                return Err(case.error_at(
                    &format!("observations[{i}]"),
                    "sigma missing; with [sigma] every estimate and observation needs a \
                     standard deviation",
                ))
            }
            (None, _) => o.weight,
        };
        observations.push(Observation {
            kind: o.kind,
            vehicle,
            value: o.value,
            weight,
        });
    }
    Ok(observations)
}

/// One optional value per component of the twelve.
type Components = [Option<f64>; 12];

/// The settings of a case (`[bounds]`), with the command-line choices.
pub fn settings(
    case: &Case,
    model: pim_fit::FitModel,
    moment_form: pim_core::MomentForm,
    branches: Vec<MomentBranch>,
) -> Result<pim_fit::ValidSettings> {
    settings_from(
        case,
        FitSettings {
            model,
            moment_form,
            branches,
            ..Default::default()
        },
    )
}

/// The case's observations as the tables name them: `NAME (KIND of vehicleN)`, or
/// `observation N (KIND of vehicleN)` for one without a name.
pub fn observation_labels(case: &Case) -> Vec<String> {
    case.content
        .observations
        .iter()
        .enumerate()
        .map(|(i, o)| match &o.name {
            Some(n) => format!("{n} ({} of vehicle{})", o.kind.name(), o.vehicle),
            None => format!(
                "observation {} ({} of vehicle{})",
                i + 1,
                o.kind.name(),
                o.vehicle
            ),
        })
        .collect()
}

/// True when the case gives estimates or observations: evidence whose weights need standard
/// deviations in a chi-square (a reconstruction's).
pub fn has_weighed_evidence(case: &Case) -> bool {
    let c = &case.content;
    c.estimates.is_some() || !c.observations.is_empty()
}

/// The search bounds the case's `[bounds]` sets itself.
pub fn set_bounds(case: &Case) -> Vec<pim_fit::SearchBound> {
    pim_fit::SearchBound::ALL
        .into_iter()
        .filter(|&b| sets_bound(case, b))
        .collect()
}

/// The weights and standard deviations a case gives for components that the cost function
/// holds fixed at their estimates, which therefore have no effect (said, not ignored in silence).
pub fn ignored_weights(case: &Case, preset: pim_fit::CostPreset) -> Vec<String> {
    let c = &case.content;
    let mut out = Vec::new();
    for (section, given) in [("weights", c.weights), ("sigma", c.sigma)] {
        let Some(given) = given else { continue };
        let fixed: Vec<&str> = given
            .components()
            .iter()
            .enumerate()
            .filter(|(k, w)| w.is_some() && preset.holds_fixed(*k))
            .map(|(k, _)| pim_fit::COMPONENT_NAMES[k])
            .collect();
        if !fixed.is_empty() {
            out.push(format!(
                "{}: [{section}] of {} has no effect: cost {} holds these components fixed at \
                 their estimates",
                case.file,
                fixed.join(", "),
                preset.name()
            ));
        }
    }
    out
}

impl Case {
    /// States e's upper bound `hi` (from 0) where `[bounds]` does not set e itself.
    pub fn bound_e_unless_set(&mut self, hi: f64) {
        let b = self.content.bounds.get_or_insert_with(Default::default);
        b.e.get_or_insert([0.0, hi]);
    }

    /// States the search's bounds in `[bounds]`: e's and mu's ranges, the bound on every
    /// velocity component (m/s) and on every yaw rate (rad/s).
    pub fn state_bounds(&mut self, e: [f64; 2], mu: [f64; 2], velocity: f64, yaw_rate: f64) {
        let b = self.content.bounds.get_or_insert_with(Default::default);
        b.e = Some(e);
        b.mu = Some(mu);
        b.velocity = Some(velocity);
        b.yaw_rate = Some(yaw_rate);
    }
}

/// True when the case gives something to fit: estimates, known components or observations
/// (a case may also hold a solve's `[coefficients]` and state).
pub fn is_fit_case(case: &Case) -> bool {
    let c = &case.content;
    c.estimates.is_some() || c.known.is_some() || !c.observations.is_empty()
}

/// Checks that a case has something to fit. One file may hold both a solve and a fit of the
/// same crash: a fit reads its estimates, observations and bounds and leaves
/// `[coefficients]`, `[initial]` and `[final]` to `pim solve`; a file with only those is a
/// solve case, which the error says.
pub fn check_fit_sections(case: &Case) -> Result<()> {
    if is_fit_case(case) {
        return Ok(());
    }
    let c = &case.content;
    for (name, present) in [
        ("[coefficients]", c.coefficients.is_some()),
        ("[initial]", c.initial.is_some()),
        ("[final]", c.final_.is_some()),
    ] {
        if present {
            return Err(input(
                case,
                format!(
                    "{name} is for `pim solve`; a fit takes [estimates.initial] / \
                     [estimates.final] (both may live in one file)"
                ),
            ));
        }
    }
    Ok(())
}

/// The range of e of a case file without `[bounds] e`: e's physical range (a RICSAC refit
/// states Brach's and Vossou & Koulocheris' [0, 0.2]).
pub const CASE_E_RANGE: [f64; 2] = [0.0, 1.0];

/// True when the case's `[bounds]` sets `bound` itself (rather than leaving it to the
/// default).
pub fn sets_bound(case: &Case, bound: pim_fit::SearchBound) -> bool {
    bound_in(case.content.bounds.as_ref(), bound)
}

/// True when `[bounds]` (as given) sets `bound`.
pub fn bound_in(
    bounds: Option<&crate::sections::BoundsSection>,
    bound: pim_fit::SearchBound,
) -> bool {
    use pim_fit::SearchBound as B;
    let Some(b) = bounds else {
        return false;
    };
    match bound {
        B::E => b.e.is_some(),
        B::Mu => b.mu.is_some(),
        B::Et => b.et.is_some(),
        B::Friction => b.friction.is_some(),
        B::Velocity => b.velocity.is_some(),
        B::YawRate => b.yaw_rate.is_some(),
    }
}

/// The case's settings on top of `base`, checked: the velocity limits of a case file (the
/// physical ranges of `crate::ranges` unless `[bounds]` sets them), then its `[bounds]`.
pub fn settings_from(case: &Case, base: FitSettings) -> Result<pim_fit::ValidSettings> {
    let mut s = base;
    // A case file's crash is whatever the user brings: its velocities are bounded by the
    // physical ranges of the inputs (100 m/s, 15 rad/s), not by the RICSAC setting of Vossou &
    // Koulocheris (20 m/s, 5 rad/s), unless its [bounds] say otherwise.
    s.velocity_bound = crate::ranges::SPEED.hi;
    s.yaw_rate_bound = crate::ranges::YAW_RATE.hi;
    // Likewise e: its physical range, from perfectly plastic to perfectly elastic, not the
    // [0, 0.2] that suits RICSAC's speeds.
    s.e = CASE_E_RANGE;
    if let Some(b) = case.content.bounds {
        if let Some(e) = b.e {
            s.e = e;
        }
        if let Some(mu) = b.mu {
            s.mu = mu;
        }
        if let Some(et) = b.et {
            s.et = et;
        }
        if let Some(f) = b.friction {
            s.friction = f;
        }
        if let Some(v) = b.velocity {
            s.velocity_bound = v;
        }
        if let Some(w) = b.yaw_rate {
            s.yaw_rate_bound = w;
        }
    }
    s.check()
        .map_err(|e| input(case, e.to_string().replacen("bounds: ", "[bounds] ", 1)))
}

/// The geometry inputs a case estimates (`[bounds]` `vehicle1` / `vehicle2` / `crush_angle`),
/// SI and degrees; empty when the geometry is taken as exact.
pub fn geometry(case: &Case) -> Result<Vec<GeometryBound>> {
    use pim_fit::GeometryInput as G;
    let Some(b) = case.content.bounds else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (v, centre) in [(1u8, b.vehicle1), (2, b.vehicle2)] {
        let Some(c) = centre else { continue };
        if v == 2 && case.is_barrier() {
            return Err(input(
                case,
                "[bounds] vehicle2: vehicle 2 is a fixed barrier, which has no impact centre to \
                 estimate; bound crush_angle to estimate the barrier face's angle"
                    .to_string(),
            ));
        }
        let point = c.impact_point.unwrap_or_default();
        if (c.d.is_some() || c.phi.is_some()) && (point.x.is_some() || point.y.is_some()) {
            return Err(input(
                case,
                format!(
                    "[bounds] vehicle{v}: bound the impact centre by d / phi or by impact_point \
                     x / y, not both"
                ),
            ));
        }
        for (input, range) in [
            (G::D(v), c.d),
            (G::Phi(v), c.phi),
            (G::X(v), point.x),
            (G::Y(v), point.y),
        ] {
            if let Some(bounds) = range {
                out.push(GeometryBound { input, bounds });
            }
        }
    }
    if let Some(bounds) = b.crush_angle {
        out.push(GeometryBound {
            input: G::CrushAngle,
            bounds,
        });
    }
    Ok(out)
}

/// Fits a case: the coefficients, and the geometry inputs that `[bounds]` bounds
/// ([`pim_fit::fit_geometry`]).
pub fn fit(
    case: &Case,
    problem: &FitProblem,
    settings: &pim_fit::ValidSettings,
) -> Result<pim_fit::FitReport> {
    pim_fit::fit_geometry(problem, &geometry(case)?, settings)
        .map_err(|e| input(case, e.to_string().replacen("bounds: ", "[bounds] ", 1)))
}
