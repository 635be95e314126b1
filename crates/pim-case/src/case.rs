//! The TOML case file of a solve, a sensitivity study and a fit.

use crate::error::{InputError, Result};
pub use crate::parse::{line_col, parse_toml};
pub use crate::sections::*;
use crate::units::UnitsSection;
use pim_core::{Coefficients, Collision, Convention, Vehicle, VehicleId, Velocities};
use serde::Deserialize;

/// Largest case file accepted, bytes (a case is a few hundred bytes).
pub const MAX_CASE_BYTES: u64 = 1 << 20;

/// The whole case file. Unknown keys are rejected so that a typo cannot be silently ignored.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseFile {
    /// Free text.
    #[serde(default)]
    pub title: Option<String>,
    /// How headings are given: `natural` (default, the nose) or `brach` (the papers' form).
    #[serde(default)]
    pub convention: Convention,
    /// Units of the file's numbers (default SI).
    #[serde(default)]
    pub units: UnitsSection,
    /// Vehicle 1.
    pub vehicle1: VehicleSection,
    /// Vehicle 2.
    pub vehicle2: VehicleSection,
    /// Crush surface.
    pub impact: ImpactSection,
    /// Coefficients (solve, sensitivity).
    #[serde(default)]
    pub coefficients: Option<CoefficientsSection>,
    /// Velocities at contact.
    #[serde(default)]
    pub initial: Option<StateSection>,
    /// Velocities at separation.
    #[serde(default, rename = "final")]
    pub final_: Option<StateSection>,
    /// Estimates (fit): `[estimates.initial]`, `[estimates.final]`.
    #[serde(default)]
    pub estimates: Option<PartialStates>,
    /// Weights of the estimates in (0, 1] (fit), same shape; default 1.
    #[serde(default)]
    pub weights: Option<PartialStates>,
    /// Standard deviations of the estimates (fit), same shape (speed and yaw-rate units):
    /// weights become inverse variances and the cost a chi-square. Not with `[weights]`.
    #[serde(default)]
    pub sigma: Option<PartialStates>,
    /// Components known exactly (fit without `--cost`), same shape.
    #[serde(default)]
    pub known: Option<PartialStates>,
    /// Bounds of the fit.
    #[serde(default)]
    pub bounds: Option<BoundsSection>,
    /// Extra observations (fit), e.g. what an EDR recorded.
    #[serde(default)]
    pub observations: Vec<ObservationSection>,
    /// Uncertainty of the inputs the fit takes as exact (`pim uncertainty`).
    #[serde(default)]
    pub uncertainty: Option<crate::spread::UncertaintySection>,
    /// The run-out to rest: road friction and each vehicle's wheels (`pim runout`).
    #[serde(default)]
    pub runout: Option<crate::scene_sections::RunoutSection>,
    /// The scene's evidence of the run-out: rest positions and headings, marks.
    #[serde(default)]
    pub scene: Option<crate::scene_sections::SceneSection>,
    /// Before the impact: skid marks up to contact and EDR speeds (`pim fit` of a scene).
    #[serde(default)]
    pub pre_impact: Option<crate::scene_sections::PreImpactSection>,
    /// The pose at contact fitted by the whole reconstruction: each value's standard
    /// deviation (see [`crate::contact_pose`]).
    #[serde(default)]
    pub contact_sigma: Option<crate::contact_sigma::ContactSigmaSection>,
    /// Each vehicle's crush profile and stiffness (`[damage]`, see [`crate::damage`]).
    #[serde(default)]
    pub damage: Option<crate::sections::DamageSection>,
    /// A scene diagram or photo behind the plan, set to scale (`pim serve`; no answer reads it).
    #[serde(default)]
    pub background: Option<crate::scene_sections::BackgroundSection>,
    /// `[survey]`: the scene's surveyed points (see [`crate::survey`]).
    #[serde(default)]
    pub survey: Option<crate::scene_sections::SurveySection>,
    /// A motion case's stated starts (never read from a case with an impact; see
    /// [`crate::motion`]).
    #[serde(skip)]
    pub start: Option<crate::scene_sections::StartSection>,
}

/// A loaded case: the file name (for messages) and its content.
#[derive(Debug, Clone)]
pub struct Case {
    /// The path as given on the command line.
    pub file: String,
    /// The parsed content.
    pub content: CaseFile,
    /// The text it was parsed from (to say where a field is written).
    pub source: String,
    /// The convention the file was written in (`content.convention` is the one its numbers
    /// are in after loading: an SAE file is mirrored into the natural form).
    pub written: Convention,
    /// The file's `[units]` as written (`content.units` is SI after loading): the units its
    /// results are shown in by default.
    pub written_units: UnitsSection,
}

pub use crate::parse::printable;

/// An input error at the dotted field `path` of the text `source` of `file` (see
/// [`Case::error_at`]).
pub fn error_at(file: &str, source: &str, path: &str, what: impl std::fmt::Display) -> InputError {
    let shown = crate::parse::display_path(source, path);
    // A field the file does not write itself (`vx` of a velocity given as speed and
    // direction) is placed at the nearest enclosing one it does write.
    let mut at = path;
    let mut place = crate::parse::locate(source, at);
    while place.is_none() {
        let Some((parent, _)) = at.rsplit_once('.') else {
            break;
        };
        at = parent;
        place = crate::parse::locate(source, at);
    }
    match place {
        Some((line, col)) => {
            InputError::located(file, format!("{file}:{line}:{col}: {shown}: {what}"))
        }
        None => InputError::new(file, format!("{shown}: {what}")),
    }
}

pub(crate) fn finite(file: &str, source: &str, path: &str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(error_at(
            file,
            source,
            path,
            format!("must be a finite number, got {value}"),
        ))
    }
}

impl Case {
    /// Parses case-file text; `file` names it in messages. The content is returned in SI with
    /// the impact centres in polar form (`d`, `phi`), whatever units and form the file used.
    pub fn from_text(file: &str, text: &str) -> Result<Self> {
        let content: CaseFile = parse_toml(file, text).map_err(|e| {
            if crate::scene_sections::is_motion(text) {
                InputError::new(
                    file,
                    format!(
                        "[start] makes it a motion case (the vehicles from a stated state, no \
                         impact): `pim runout {file}` follows it"
                    ),
                )
            } else {
                e
            }
        })?;
        let mut case = Case {
            file: file.to_string(),
            written: content.convention,
            written_units: content.units,
            content,
            source: text.to_string(),
        };
        case.content.title = case.content.title.as_deref().map(printable);
        for v in [&mut case.content.vehicle1, &mut case.content.vehicle2] {
            v.description = v.description.as_deref().map(printable);
        }
        for o in &mut case.content.observations {
            o.name = o.name.as_deref().map(printable);
        }
        case.check_survey()?;
        case.resolve_barrier()?;
        case.resolve_forms()?;
        case.check_states()?;
        case.resolve_impact_points()?;
        case.convert_to_si();
        case.estimate_inertias();
        case.check_ranges()?;
        case.check_outlines()?;
        if let Some(b) = &case.content.background {
            b.check()
                .map_err(|(key, what)| case.error_at(&format!("background.{key}"), what))?;
        }
        if let Some(b) = &case.content.bounds {
            b.check()
                .map_err(|(path, what)| case.error_at(&path, what))?;
        }
        Ok(case)
    }

    /// An input error at the field `path` (dotted, as in the file: `vehicle1.width`), in the one
    /// form `FILE:LINE:COL: FIELD: what is wrong` (`FILE: FIELD: ...` when the field is not
    /// written in the file).
    pub fn error_at(&self, path: &str, what: impl std::fmt::Display) -> InputError {
        error_at(&self.file, &self.source, path, what)
    }

    /// Where the dotted field `path` is written: `FILE:LINE:COL: FIELD`, or `FILE: FIELD`.
    pub fn at(&self, path: &str) -> String {
        let shown = crate::parse::display_path(&self.source, path);
        match crate::parse::locate(&self.source, path) {
            Some((line, col)) => format!("{}:{line}:{col}: {shown}", self.file),
            None => format!("{}: {shown}", self.file),
        }
    }

    /// How the `i`-th (0-based) observation is named in messages, tables and figures: by its
    /// `name`, or `observation N` (1-based).
    pub fn observation_label(&self, i: usize) -> String {
        match self
            .content
            .observations
            .get(i)
            .and_then(|o| o.name.as_ref())
        {
            Some(n) => format!("observation {n:?}"),
            None => format!("observation {}", i + 1),
        }
    }

    /// True when vehicle 2 is a fixed barrier (`[vehicle2] barrier = true`).
    pub fn is_barrier(&self) -> bool {
        self.content.vehicle2.barrier
    }

    /// Checks the vehicles' required numbers and a barrier's section (vehicle 2 only, nothing
    /// that a barrier does not have, at rest in the states), and fills in the barrier.
    fn resolve_barrier(&mut self) -> Result<()> {
        let file = self.file.clone();
        let c = &mut self.content;
        if c.vehicle1.barrier {
            return Err(InputError::new(
                &file,
                "[vehicle1] barrier = true: only vehicle 2 can be a barrier; put the moving \
                 vehicle first",
            ));
        }
        if c.vehicle2.barrier {
            let v = &mut c.vehicle2;
            let given: Vec<&str> = [
                ("mass", !v.mass.is_nan()),
                ("yaw_inertia", !v.yaw_inertia.is_nan()),
                ("heading", !v.heading.is_nan()),
                ("d", v.d.is_some()),
                ("phi", v.phi.is_some()),
                ("impact_point", v.impact_point.is_some()),
            ]
            .iter()
            .filter(|(_, g)| *g)
            .map(|(n, _)| *n)
            .collect();
            if !given.is_empty() {
                return Err(InputError::new(
                    &file,
                    format!(
                        "[vehicle2] is a barrier (barrier = true) and cannot have {}: a fixed \
                         rigid barrier has no mass, inertia or heading, and the crush surface \
                         ([impact] crush_angle) orients it",
                        given.join(", ")
                    ),
                ));
            }
            v.mass = f64::INFINITY;
            v.yaw_inertia = f64::INFINITY;
            v.heading = 0.0;
            v.d = Some(0.0);
            v.phi = Some(0.0);
            for (name, st) in [("initial", &mut c.initial), ("final", &mut c.final_)] {
                let Some(st) = st else { continue };
                match st.vehicle2 {
                    None => st.vehicle2 = Some(AT_REST),
                    Some(w) if w.vx == 0.0 && w.vy == 0.0 && w.omega == 0.0 => {}
                    Some(w) => {
                        return Err(InputError::new(
                            &file,
                            format!(
                                "[{name}] vehicle2 = {{ vx = {}, vy = {}, omega = {} }}: vehicle \
                                 2 is a fixed barrier and does not move; leave it out",
                                w.vx, w.vy, w.omega
                            ),
                        ))
                    }
                }
            }
            return Ok(());
        }
        for (name, v) in [("vehicle1", &c.vehicle1), ("vehicle2", &c.vehicle2)] {
            for (field, x, what) in [
                ("mass", v.mass, "the vehicle's mass"),
                (
                    "yaw_inertia",
                    crate::inertia::inertia_or_outline(&self.source, name, v),
                    crate::inertia::INERTIA_WANTED,
                ),
                ("heading", v.heading, "where its nose points, degrees"),
            ] {
                if x.is_nan() {
                    let hint = if name == "vehicle2" {
                        " (or barrier = true for a fixed barrier)"
                    } else {
                        ""
                    };
                    return Err(error_at(
                        &file,
                        &self.source,
                        &format!("{name}.{field}"),
                        format!("missing or not a number; give {what}{hint}"),
                    ));
                }
                finite(&file, &self.source, &format!("{name}.{field}"), x)?;
            }
        }
        for (name, st) in [("initial", &c.initial), ("final", &c.final_)] {
            if let Some(st) = st {
                if st.vehicle2.is_none() {
                    return Err(InputError::new(
                        &file,
                        format!(
                            "[{name}] vehicle2: missing; give {{ vx = .., vy = .., omega = .. }}"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Checks that each vehicle gives its impact centre in exactly one form and writes the
    /// polar form (`impact_point` is converted, in the file's length unit).
    fn resolve_impact_points(&mut self) -> Result<()> {
        let file = self.file.clone();
        for (name, v) in [
            ("vehicle1", &mut self.content.vehicle1),
            ("vehicle2", &mut self.content.vehicle2),
        ] {
            match (v.impact_point, v.d, v.phi) {
                (Some(p), None, None) => {
                    let source = &self.source;
                    finite(&file, source, &format!("{name}.impact_point.x"), p.x)?;
                    finite(&file, source, &format!("{name}.impact_point.y"), p.y)?;
                    let (d, phi) = pim_core::impact_point_polar(p.x, p.y);
                    v.d = Some(d);
                    v.phi = Some(phi);
                }
                (None, Some(_), Some(_)) => {}
                (Some(_), _, _) => {
                    return Err(InputError::new(
                        &file,
                        format!(
                            "[{name}] gives the impact centre twice: use either impact_point = \
                             {{ x = .., y = .. }} or d and phi, not both"
                        ),
                    ))
                }
                (None, d, _) => {
                    let missing = if d.is_none() { "d" } else { "phi" };
                    return Err(InputError::new(
                        &file,
                        format!(
                            "[{name}] {missing}: missing; give the impact centre as impact_point = \
                             {{ x = .., y = .. }} (from the CG, x forward, y to the left) or as d \
                             (CG to impact centre) and phi (degrees counter-clockwise from the nose)"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Converts every number with a unit to SI (`[units]`).
    fn convert_to_si(&mut self) {
        let u = self.content.units;
        let (speed, length, mass, inertia, rate) = (
            u.speed.to_si(),
            u.length.to_si(),
            u.mass.to_si(),
            u.yaw_inertia.to_si(),
            u.yaw_rate.to_si(),
        );
        let c = &mut self.content;
        for v in [&mut c.vehicle1, &mut c.vehicle2] {
            v.mass *= mass;
            v.yaw_inertia *= inertia;
            for x in [&mut v.d, &mut v.length, &mut v.width, &mut v.cg_to_front]
                .into_iter()
                .flatten()
            {
                *x *= length;
            }
            if let Some(p) = &mut v.impact_point {
                p.x *= length;
                p.y *= length;
            }
        }
        let velocity = |v: &mut VelocitySection| {
            v.vx *= speed;
            v.vy *= speed;
            v.omega *= rate;
        };
        for s in [&mut c.initial, &mut c.final_].into_iter().flatten() {
            velocity(&mut s.vehicle1);
            s.vehicle2.iter_mut().for_each(velocity);
        }
        for states in [&mut c.estimates, &mut c.known, &mut c.sigma]
            .into_iter()
            .flatten()
        {
            states.scale(speed, rate);
        }
        if let Some(b) = &mut c.bounds {
            if let Some(v) = &mut b.velocity {
                *v *= speed;
            }
            let scale = |r: &mut [f64; 2]| r.iter_mut().for_each(|x| *x *= length);
            for centre in [&mut b.vehicle1, &mut b.vehicle2].into_iter().flatten() {
                if let Some(d) = &mut centre.d {
                    scale(d);
                }
                if let Some(p) = &mut centre.impact_point {
                    [&mut p.x, &mut p.y].into_iter().flatten().for_each(scale);
                }
            }
            if let Some(w) = &mut b.yaw_rate {
                *w *= rate;
            }
        }
        for o in &mut c.observations {
            o.value *= speed;
            if let Some(s) = &mut o.sigma {
                *s *= speed;
            }
        }
        if let Some(u) = &mut c.uncertainty {
            *u = u.to_si(mass, inertia, length);
        }
        // Converted once: the content is SI from here on.
        c.units = UnitsSection::default();
    }

    /// The collision in the papers' form (pim-core's [`Vehicle`]) for a given convention.
    pub(crate) fn collision(&self, convention: Convention) -> Collision {
        let v = |s: &VehicleSection, id: VehicleId| {
            if s.barrier {
                return Vehicle::barrier();
            }
            Vehicle {
                mass: s.mass,
                yaw_inertia: s.yaw_inertia,
                heading: convention.theta(id, s.heading),
                d: s.d(),
                phi: s.phi(),
            }
        };
        Collision {
            vehicle1: v(&self.content.vehicle1, VehicleId::One),
            vehicle2: v(&self.content.vehicle2, VehicleId::Two),
            crush_angle: self.content.impact.crush_angle,
        }
    }

    /// The collision, checked by pim-core (messages name the vehicle and field).
    pub fn impact(&self) -> Result<pim_core::Impact> {
        let impact = pim_core::Impact::new(self.collision(self.content.convention))
            .map_err(|e| InputError::new(&self.file, e))?;
        Ok(match self.stated_side()? {
            Some(side) => impact.with_side(side),
            // Both CGs on one side: the side under which the estimated contact velocities
            // approach, when they say; mobility otherwise.
            None => match self.estimated_contact() {
                Some(v) => impact.with_side_from_velocities(&v),
                None => impact,
            },
        })
    }

    /// The side of the crush surface the case states for vehicle 1 (`[impact] vehicle1_side`):
    /// +1 for `"+n"`, -1 for `"-n"`.
    pub fn stated_side(&self) -> Result<Option<f64>> {
        match self.content.impact.vehicle1_side.as_deref().map(str::trim) {
            None => Ok(None),
            Some("+n") | Some("n") => Ok(Some(1.0)),
            Some("-n") => Ok(Some(-1.0)),
            Some(other) => Err(self.error_at(
                "impact.vehicle1_side",
                format!(
                    "{other:?}: accepted \"+n\" (vehicle 1 on the side the normal n at \
                     crush_angle points to) or \"-n\""
                ),
            )),
        }
    }

    /// Why the vehicles of this case do not approach each other at the impact centre in the
    /// contact state `v`, in words: where the case put the centres of mass and the impact
    /// centre, and whether the other heading convention would make it an impact. `None` when
    /// they do approach.
    pub fn explain_not_approaching(&self, v: &Velocities) -> Option<String> {
        let impact = self.impact().ok()?;
        impact.check_approach(v).err()?;
        let [g1, g2] = impact.cg_positions();
        let n = impact.normal();
        let (vn, _) = impact.relative_velocity(v);
        let conv = self.content.convention;
        let mirrored = if self.written == Convention::Sae {
            " (read from SAE: y and angles mirrored)"
        } else {
            ""
        };
        let z = |x: f64| if x.abs() < 5e-3 { 0.0 } else { x };
        let mut text = format!(
            "with convention = \"{}\" ({}) the case puts, in the fixed frame{mirrored} with the \
             impact centre C at (0, 0) m: vehicle 1's CG at ({:.2}, {:.2}) m, nose towards {:.1} deg; \
             vehicle 2's CG at ({:.2}, {:.2}) m, nose towards {:.1} deg; crush-surface normal \
             ({:.3}, {:.3}); the velocity of vehicle 1's point at C relative to vehicle 2's along \
             that normal is {:.3} m/s, away from vehicle 2's side of the crush surface",
            conv.name(),
            match conv {
                Convention::Natural | Convention::Sae => "headings are where the noses point",
                Convention::Brach => "vehicle 1's heading is the direction of its tail",
            },
            z(g1[0]),
            z(g1[1]),
            impact.nose_heading(VehicleId::One),
            z(g2[0]),
            z(g2[1]),
            impact.nose_heading(VehicleId::Two),
            z(n[0]),
            z(n[1]),
            vn,
        );
        let other = conv.other();
        if let Ok(alt) = pim_core::Impact::new(self.collision(other)) {
            if alt.check_approach(v).is_ok() {
                text.push_str(&format!(
                    "; with convention = \"{}\" ({}) these velocities would make an impact: \
                     check which form the headings were written in",
                    other.name(),
                    match other {
                        Convention::Natural | Convention::Sae =>
                            "vehicle 1's heading is where its nose points",
                        Convention::Brach =>
                            "vehicle 1's heading is its tail, as in Brach's papers and the RICSAC tables",
                    }
                ));
            }
        }
        Some(text)
    }

    /// The `[coefficients]` section, required and checked.
    pub fn coefficients(&self) -> Result<Coefficients> {
        match self.model()? {
            CaseModel::Pim(c) => Ok(c),
            CaseModel::Tangential(_) | CaseModel::Impc(_) => Err(InputError::new(
                &self.file,
                "[coefficients] select the tangential-restitution model (e, et, friction) or \
                 IMPC (model = \"impc\"), which `pim solve` and `pim draw` take; this command \
                 needs PIM's e, mu, em",
            )),
        }
    }

    /// The model and its coefficients: PIM for `e, mu, em`, the tangential-restitution model
    /// for `e, et, friction`, checked.
    pub fn model(&self) -> Result<CaseModel> {
        let c = self.content.coefficients.ok_or_else(|| {
            InputError::new(
                &self.file,
                "missing section [coefficients] (e, mu, em for PIM, or e, et, friction for the \
                 tangential-restitution model)",
            )
        })?;
        let bad =
            |e: pim_core::PimError| InputError::new(&self.file, format!("[coefficients] {e}"));
        let named = c.model;
        if named == Some(ModelName::Impc) {
            return match (c.mu, c.em, c.et, c.friction) {
                (None, None, None, Some(friction)) => {
                    let m = pim_core::Impc { e: c.e, friction };
                    pim_core::ImpactModel::validate(&m).map_err(bad)?;
                    Ok(CaseModel::Impc(m))
                }
                _ => Err(InputError::new(
                    &self.file,
                    "[coefficients] model = \"impc\" takes e and friction only (IMPC's \
                     tangential restitution is -e; give model = \"tangential\" with et to choose \
                     it)",
                )),
            };
        }
        match (c.mu, c.em, c.et, c.friction) {
            (Some(mu), Some(em), None, None) if named != Some(ModelName::Tangential) => {
                let c = Coefficients { e: c.e, mu, em };
                c.validate().map_err(bad)?;
                Ok(CaseModel::Pim(c))
            }
            (None, None, Some(et), Some(friction)) if named != Some(ModelName::Pim) => {
                let c = pim_core::TangentialCoefficients {
                    e: c.e,
                    et,
                    friction,
                };
                c.validate().map_err(bad)?;
                Ok(CaseModel::Tangential(c))
            }
            (mu, em, et, friction) => {
                let given: Vec<&str> = [("mu", mu), ("em", em), ("et", et), ("friction", friction)]
                    .iter()
                    .filter(|(_, v)| v.is_some())
                    .map(|(n, _)| *n)
                    .collect();
                Err(InputError::new(
                    &self.file,
                    format!(
                        "[coefficients] gives e, {}: give e, mu, em (PIM) or e, et, friction (the \
                         tangential-restitution model)",
                        if given.is_empty() {
                            "nothing else".to_string()
                        } else {
                            given.join(", ")
                        }
                    ),
                ))
            }
        }
    }

    /// Exactly one of `[initial]` / `[final]`: `(state, true)` for initial.
    pub fn known_state(&self) -> Result<(Velocities, bool)> {
        match (&self.content.initial, &self.content.final_) {
            (Some(i), None) => Ok((i.to_velocities(), true)),
            (None, Some(f)) => Ok((f.to_velocities(), false)),
            (Some(_), Some(_)) => Err(InputError::new(
                &self.file,
                "give either [initial] (solve forwards) or [final] (solve backwards), not both",
            )),
            (None, None) => Err(InputError::new(
                &self.file,
                "missing section [initial] (velocities at contact) or [final] (at separation)",
            )),
        }
    }
}
