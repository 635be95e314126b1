//! `[contact_sigma]`: the pose at contact as unknowns of the whole reconstruction.
//!
//! A case states where the vehicles were at contact (each CG `position` and `heading`, the
//! impact centre, the crush surface's angle). Those are rarely known to better than a foot and
//! a few degrees, and they move the answer: the impact point decides the lever arm of the
//! impulse, a heading the direction of an EDR's speed, a position where each run-out starts.
//! With `[contact_sigma]` the reconstruction fits them: each value written becomes an unknown
//! held near the case's value by a prior of that standard deviation (a term `(x - x_case)^2 /
//! sigma^2` of the chi-square), and the rests, marks and the impact's evidence move it.
//!
//! ```toml
//! [contact_sigma]                        # the case's length unit and degrees
//! vehicle1 = { heading = 3.0 }           # rotated about its CG
//! vehicle2 = { heading = 3.0, impact_point = { x = 0.8 } }   # the impact point along its side
//! centre = { x = 1.0, y = 1.0 }          # the impact centre in the scene
//! crush_angle = 5.0
//! ```
//!
//! Per vehicle, `position = { x, y }` moves its CG in the scene (the case's axes) with the
//! impact centre held, so that the impact point on the vehicle moves with it; `impact_point =
//! { x, y }` moves the impact centre on the vehicle (its axes: x forward, y to the left) with the
//! impact centre held in the scene, so that the vehicle moves; the two are alternatives.
//! `heading` turns the vehicle about its CG, or, with `impact_point`, about the impact centre.
//! `centre` moves the impact centre in the scene with the vehicles held (a vehicle whose
//! `impact_point` is fitted moves with it). `crush_angle` turns the
//! crush surface; a case that gives `crush_angle_from_vehicle1` keeps the surface on vehicle 1
//! as vehicle 1 turns.
//!
//! The offsets are held in SI and the natural frame ([`ContactUnknown`]); [`Case::with_contact`]
//! is the case at an offset, every quantity that rests on the pose (the impact's geometry, the
//! run-outs' starts, the headings an observation is measured along) derived from it as from
//! the file.

use crate::case::Case;
pub use crate::contact_sigma::{AxesSigma, ContactSigmaSection, PoseSigma};
use crate::error::Result;
use pim_core::VehicleId;

/// What a pose unknown moves (vehicles by index 0 and 1, axes 0 = x and 1 = y).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseInput {
    /// A vehicle's heading, rad counter-clockwise.
    Heading(usize),
    /// A vehicle's CG in the scene along a natural axis, m.
    Position(usize, usize),
    /// The impact centre on a vehicle along its axis (forward, left), m.
    ImpactPoint(usize, usize),
    /// The impact centre in the scene along a natural axis, m.
    Centre(usize),
    /// The crush surface's angle, rad counter-clockwise.
    CrushAngle,
}

impl PoseInput {
    /// Whether it is an angle (rad) rather than a length (m).
    pub fn is_angle(self) -> bool {
        matches!(self, PoseInput::Heading(_) | PoseInput::CrushAngle)
    }

    /// The vehicle it moves (index 0 or 1), if any.
    pub fn vehicle(self) -> Option<usize> {
        match self {
            PoseInput::Heading(k) | PoseInput::Position(k, _) | PoseInput::ImpactPoint(k, _) => {
                Some(k)
            }
            PoseInput::Centre(_) | PoseInput::CrushAngle => None,
        }
    }

    /// Whether it is a y coordinate of the scene or of a vehicle (written mirrored in an SAE
    /// case), or an angle (written clockwise there).
    pub fn mirrored(self) -> bool {
        match self {
            PoseInput::Heading(_) | PoseInput::CrushAngle => true,
            PoseInput::Position(_, a) | PoseInput::ImpactPoint(_, a) | PoseInput::Centre(a) => {
                a == 1
            }
        }
    }
}

/// One unknown of the pose at contact: what it moves, the standard deviation of its prior (m
/// or rad) and its field in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactUnknown {
    /// What it moves.
    pub input: PoseInput,
    /// The prior's standard deviation, m or rad.
    pub sigma: f64,
    /// Its field (`contact_sigma.vehicle2.impact_point.x`), for messages.
    pub field: String,
    /// Its name in tables (`vehicle2.impact_point.x`).
    pub name: String,
    /// Whether its prior weighs in the fit (false: left out, the value still fitted).
    pub prior: bool,
}

const AXES: [&str; 2] = ["x", "y"];

impl Case {
    /// The unknowns `[contact_sigma]` gives, checked: none without the section.
    ///
    /// # Errors
    /// A located error for a standard deviation that is not a number above 0, a barrier's
    /// pose, or a vehicle given both `position` and `impact_point`.
    pub fn contact_unknowns(&self) -> Result<Vec<ContactUnknown>> {
        let Some(s) = self.content.contact_sigma else {
            return Ok(Vec::new());
        };
        let length = self.written_units.length.to_si();
        let mut out = Vec::new();
        let mut push = |input: PoseInput, name: String, sd: Option<f64>| -> Result<()> {
            let Some(sd) = sd else { return Ok(()) };
            let field = format!("contact_sigma.{name}");
            let limit = if input.is_angle() { 90.0 } else { 1000.0 };
            if !(sd.is_finite() && sd > 0.0 && sd <= limit) {
                return Err(self.error_at(
                    &field,
                    format!(
                        "{sd}: a standard deviation above 0 and at most {limit} {}",
                        if input.is_angle() {
                            "deg"
                        } else {
                            "(the case's length unit)"
                        }
                    ),
                ));
            }
            let sigma = if input.is_angle() {
                sd.to_radians()
            } else {
                sd * length
            };
            let prior = s.priors_left_out & (1 << out.len().min(31)) == 0;
            out.push(ContactUnknown {
                input,
                sigma,
                field,
                name,
                prior,
            });
            Ok(())
        };
        for (k, v) in [s.vehicle1, s.vehicle2].into_iter().enumerate() {
            let Some(v) = v else { continue };
            let name = format!("vehicle{}", k + 1);
            if self.content.vehicle(k).barrier {
                return Err(self.error_at(
                    &format!("contact_sigma.{name}"),
                    "a barrier does not move: its face is [contact_sigma] crush_angle",
                ));
            }
            if v.position.is_some() && v.impact_point.is_some() {
                return Err(self.error_at(
                    &format!("contact_sigma.{name}.impact_point"),
                    "give position (the CG moves in the scene) or impact_point (the impact \
                     centre moves on the vehicle), not both",
                ));
            }
            push(PoseInput::Heading(k), format!("{name}.heading"), v.heading)?;
            for (a, axis) in AXES.iter().enumerate() {
                let p = v.position.and_then(|p| [p.x, p.y][a]);
                push(
                    PoseInput::Position(k, a),
                    format!("{name}.position.{axis}"),
                    p,
                )?;
                let q = v.impact_point.and_then(|p| [p.x, p.y][a]);
                push(
                    PoseInput::ImpactPoint(k, a),
                    format!("{name}.impact_point.{axis}"),
                    q,
                )?;
            }
        }
        for (a, axis) in AXES.iter().enumerate() {
            let c = s.centre.and_then(|p| [p.x, p.y][a]);
            push(PoseInput::Centre(a), format!("centre.{axis}"), c)?;
        }
        push(PoseInput::CrushAngle, "crush_angle".into(), s.crush_angle)?;
        if out.is_empty() {
            return Err(self.error_at(
                "contact_sigma",
                "no standard deviation given: write the ones of the pose the reconstruction \
                 should fit, e.g. vehicle1 = { heading = 3.0 }",
            ));
        }
        Ok(out)
    }

    /// The case with the prior of its pose's unknown `i` (of [`Case::contact_unknowns`]) left
    /// out: the value is still fitted, its prior no longer weighs (a row of the consistency
    /// table). Unchanged without `[contact_sigma]`.
    pub fn without_contact_prior(&self, i: usize) -> Case {
        let mut out = self.clone();
        if let Some(s) = out.content.contact_sigma.as_mut() {
            s.priors_left_out |= 1 << i.min(31);
        }
        out
    }

    /// The case with its pose at contact moved by `offsets` (as [`Case::with_contact`]) and held
    /// there: its `[contact_sigma]` dropped, the pose no longer fitted.
    ///
    /// # Errors
    /// A located error where the case's impact cannot be formed.
    pub fn with_contact_held(&self, unknowns: &[ContactUnknown], offsets: &[f64]) -> Result<Case> {
        let mut out = self.with_contact(unknowns, offsets)?;
        out.content.contact_sigma = None;
        Ok(out)
    }

    /// The case with its pose at contact moved by `offsets` (one per unknown, m and rad, the
    /// natural frame): each vehicle's heading, CG or impact point, the impact centre and the
    /// crush angle, as [`crate::contact_pose`] says. All zeros give the case as it is.
    ///
    /// # Errors
    /// A located error where the case's impact cannot be formed.
    pub fn with_contact(&self, unknowns: &[ContactUnknown], offsets: &[f64]) -> Result<Case> {
        let impact = self.impact()?;
        let cgs = impact.cg_positions();
        let c0 = self.impact_centre();
        let of = |input: PoseInput| -> f64 {
            unknowns
                .iter()
                .zip(offsets)
                .filter(|(u, _)| u.input == input)
                .map(|(_, x)| *x)
                .sum()
        };
        let centre = [
            c0[0] + of(PoseInput::Centre(0)),
            c0[1] + of(PoseInput::Centre(1)),
        ];
        let mut out = self.clone();
        let mut turn1 = 0.0;
        for (k, id) in [VehicleId::One, VehicleId::Two].into_iter().enumerate() {
            if self.content.vehicle(k).barrier {
                continue;
            }
            let turn = of(PoseInput::Heading(k));
            if k == 0 {
                turn1 = turn;
            }
            let nose = impact.nose_heading(id).to_radians() + turn;
            let by_point = unknowns
                .iter()
                .any(|u| matches!(u.input, PoseInput::ImpactPoint(j, _) if j == k));
            let v = out.content.vehicle_mut(k);
            let (x, y) = if by_point {
                let (x, y) = pim_core::impact_point_cartesian(v.d(), v.phi());
                (
                    x + of(PoseInput::ImpactPoint(k, 0)),
                    y + of(PoseInput::ImpactPoint(k, 1)),
                )
            } else {
                // The CG held (or moved), the impact centre seen from the turned vehicle.
                let p = [
                    c0[0] + cgs[k][0] + of(PoseInput::Position(k, 0)),
                    c0[1] + cgs[k][1] + of(PoseInput::Position(k, 1)),
                ];
                let (dx, dy) = (centre[0] - p[0], centre[1] - p[1]);
                let (sin, cos) = nose.sin_cos();
                (cos * dx + sin * dy, -sin * dx + cos * dy)
            };
            let (d, phi) = pim_core::impact_point_polar(x, y);
            v.d = Some(d);
            v.phi = Some(phi);
            v.heading = pim_core::wrap_degrees(v.heading + turn.to_degrees());
        }
        let i = &mut out.content.impact;
        let surface = of(PoseInput::CrushAngle)
            + if i.crush_angle_from_vehicle1.is_some() {
                turn1
            } else {
                0.0
            };
        i.crush_angle = pim_core::wrap_degrees(i.crush_angle + surface.to_degrees());
        let moved = unknowns
            .iter()
            .any(|u| matches!(u.input, PoseInput::Centre(_)));
        if moved {
            let (length, flip) = self.length_and_flip();
            // The fitted centre is no longer the surveyed point it was placed on.
            i.centre = Some(crate::sections::CentreSection {
                x: centre[0] / length,
                y: flip * centre[1] / length,
                point: None,
            });
        }
        Ok(out)
    }

    /// The value the case states of each unknown, m and rad in the natural frame: a vehicle's
    /// nose heading, its CG's coordinate in the scene, the impact centre's on the vehicle or in
    /// the scene, the crush angle.
    ///
    /// # Errors
    /// A located error where the case's impact cannot be formed.
    pub fn contact_values(&self, unknowns: &[ContactUnknown]) -> Result<Vec<f64>> {
        let impact = self.impact()?;
        let cgs = impact.cg_positions();
        let c0 = self.impact_centre();
        let ids = [VehicleId::One, VehicleId::Two];
        Ok(unknowns
            .iter()
            .map(|u| match u.input {
                PoseInput::Heading(k) => impact.nose_heading(ids[k]).to_radians(),
                PoseInput::Position(k, a) => c0[a] + cgs[k][a],
                PoseInput::ImpactPoint(k, a) => {
                    let v = self.content.vehicle(k);
                    let (x, y) = pim_core::impact_point_cartesian(v.d(), v.phi());
                    [x, y][a]
                }
                PoseInput::Centre(a) => c0[a],
                PoseInput::CrushAngle => self.content.impact.crush_angle.to_radians(),
            })
            .collect())
    }

    /// The offsets that move `nominal`'s pose at contact to this case's (the inverse of
    /// [`Case::with_contact`] between two cases that differ by a pose): m and rad, one per
    /// unknown.
    ///
    /// # Errors
    /// A located error where either case's impact cannot be formed.
    pub fn contact_offsets_from(
        &self,
        nominal: &Case,
        unknowns: &[ContactUnknown],
    ) -> Result<Vec<f64>> {
        let (a, b) = (
            self.contact_values(unknowns)?,
            nominal.contact_values(unknowns)?,
        );
        let wrap = |x: f64| {
            (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
        };
        let turn1 = if self.content.impact.crush_angle_from_vehicle1.is_some() {
            let (s, n) = (self.impact()?, nominal.impact()?);
            (s.nose_heading(VehicleId::One) - n.nose_heading(VehicleId::One)).to_radians()
        } else {
            0.0
        };
        Ok(unknowns
            .iter()
            .zip(a.iter().zip(&b))
            .map(|(u, (x, y))| match u.input {
                PoseInput::Heading(_) => wrap(x - y),
                PoseInput::CrushAngle => wrap(x - y - turn1),
                _ => x - y,
            })
            .collect())
    }
}
