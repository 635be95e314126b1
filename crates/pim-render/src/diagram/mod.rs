//! `pim draw`: a to-scale plan view of a collision at contact (plotters, SVG).
//!
//! The fixed frame has the impact centre C at the origin. Drawn: both outlines (from the case's
//! `length`, `width`, `cg_to_front`, or a default by mass class, marked as such), the CGs and
//! noses, C, the crush surface with its normal n and tangent t, the CG velocities at contact
//! (and at separation when solved), the impulse on each vehicle at C, the PDOF arrows, a scale
//! bar and the axes; the thick edge of each outline is its front. A key on the right names every element and states the arrow scales.

use pim_case::case::VehicleSection;
use pim_case::units::UnitSystem;
use pim_core::{Convention, Impact, VehicleId, VehicleResult, Velocities};
use plotters::prelude::*;

mod labels;
mod outline;
mod paint;

use outline::{barrier_wall, rotate};
pub use outline::{DrawnVehicle, Outline};

const VEHICLE_COLORS: [RGBColor; 2] = [RGBColor(31, 119, 180), RGBColor(214, 39, 40)];
const SEPARATION_COLORS: [RGBColor; 2] = [RGBColor(120, 170, 215), RGBColor(240, 140, 140)];
const IMPULSE_COLOR: RGBColor = RGBColor(40, 40, 40);
const SURFACE_COLOR: RGBColor = RGBColor(44, 160, 44);
const PDOF_COLOR: RGBColor = RGBColor(148, 103, 189);

/// A whole diagram.
#[derive(Debug, Clone)]
pub struct Diagram {
    /// First line of the key.
    pub title: String,
    /// Both vehicles.
    pub vehicles: [DrawnVehicle; 2],
    /// Unit normal of the crush surface.
    pub normal: [f64; 2],
    /// Units of the axes and labels (the geometry stays in metres; the drawing converts).
    pub units: UnitSystem,
    /// The frame the labels speak in: natural, or SAE's (the same picture, with y to the right
    /// of x and headings clockwise).
    pub frame: Convention,
    /// What the drawing shows, under the title: a solve (its coefficients), a fit (its cost
    /// function, branch and cost) or the case alone.
    pub subtitle: Option<String>,
    /// Lines the key shows under the title (e.g. the bounds a fitted answer rests on).
    pub notes: Vec<String>,
    /// Where the impact centre C lies in the case's fixed frame (natural axes, m): the origin,
    /// or the case's `[impact] centre`, so that the plan view and the scene of a case put every
    /// point at the same place.
    pub centre: [f64; 2],
    /// Degrees the drawing is turned on the page (0 until drawn; see [`crate::plan::Page`]).
    turned: f64,
}

/// The states and results of a solved (or fitted) collision.
pub struct Solved<'a> {
    /// Contact velocities.
    pub initial: &'a Velocities,
    /// Separation velocities.
    pub separation: &'a Velocities,
    /// Impulse on vehicle 1 `(Px, Py)`, N s.
    pub impulse: [f64; 2],
    /// Per-vehicle results.
    pub vehicles: &'a [VehicleResult; 2],
}

impl<'a> Solved<'a> {
    /// The states and results of a solve.
    pub fn of_report(r: &'a pim_core::ImpactReport) -> Self {
        Solved {
            initial: &r.initial,
            separation: &r.separation,
            impulse: [r.impulse.px, r.impulse.py],
            vehicles: &r.vehicles,
        }
    }

    /// The states and results of a fitted branch.
    pub fn of_fit(s: &'a pim_fit::Solution) -> Self {
        Solved {
            initial: &s.initial,
            separation: &s.separation,
            impulse: [s.impulse.px, s.impulse.py],
            vehicles: &s.vehicles,
        }
    }
}

impl Diagram {
    /// Builds the diagram of a collision, with contact velocities only (`contact`) or a solved
    /// state (`solved`).
    pub fn new(
        title: &str,
        impact: &Impact,
        sections: [&VehicleSection; 2],
        contact: Option<&Velocities>,
        solved: Option<Solved>,
    ) -> Self {
        let cgs = impact.cg_positions();
        let arms = impact.lever_arms();
        let vehicle = |k: usize| {
            let id = VehicleId::from_index(k);
            let point = impact.to_body(id, arms[k]);
            let sec = sections[k];
            let label = match &sec.description {
                Some(d) => format!("vehicle {} ({d})", k + 1),
                None => format!("vehicle {}", k + 1),
            };
            let v = |s: &Velocities| {
                let x = s.vehicle(id);
                [x.vx, x.vy]
            };
            let sign = if k == 0 { 1.0 } else { -1.0 };
            DrawnVehicle {
                label,
                outline: Outline::of(sec, point),
                heading: impact.nose_heading(id),
                cg: cgs[k],
                contact: solved.as_ref().map(|s| v(s.initial)).or(contact.map(&v)),
                separation: solved.as_ref().map(|s| v(s.separation)),
                yaw_separation: solved.as_ref().map(|s| s.separation.vehicle(id).omega),
                impulse: solved
                    .as_ref()
                    .map(|s| [sign * s.impulse[0], sign * s.impulse[1]]),
                pdof: solved.as_ref().and_then(|s| {
                    let r = &s.vehicles[k];
                    let a = s.initial.vehicle(id);
                    let b = s.separation.vehicle(id);
                    let d = [b.vx - a.vx, b.vy - a.vy];
                    let n = d[0].hypot(d[1]);
                    (n > 0.0).then(|| ([d[0] / n, d[1] / n], r.pdof, r.clock))
                }),
                barrier: false,
            }
        };
        Diagram {
            title: title.to_string(),
            vehicles: {
                let first = vehicle(0);
                let second = if impact.is_barrier() {
                    barrier_wall(impact, &first)
                } else {
                    vehicle(1)
                };
                [first, second]
            },
            normal: impact.normal(),
            units: UnitSystem::Si,
            frame: Convention::Natural,
            subtitle: None,
            notes: Vec::new(),
            centre: [0.0, 0.0],
            turned: 0.0,
        }
    }

    /// The same diagram labelled in the units `units` and the frame `frame`.
    pub fn labelled(mut self, units: UnitSystem, frame: Convention) -> Self {
        self.units = units;
        self.frame = frame;
        self
    }

    /// The same diagram with the impact centre at `centre` (natural axes, m).
    pub fn centred(mut self, centre: [f64; 2]) -> Self {
        self.centre = centre;
        self
    }

    /// The geometry in the display length unit (velocities and impulses keep their SI values;
    /// their arrows scale with the vehicles).
    ///
    /// Laid on the page as every figure of the case is ([`crate::plan::Page`]): positions and
    /// vectors turned with it, C at the case's impact centre.
    fn in_display_units(&self) -> Self {
        let k = self.units.length(1.0);
        let page = crate::plan::Page::of(self.frame);
        let mut d = self.clone();
        d.turned = page.turn_degrees();
        let c = page.point(self.centre);
        d.centre = [k * c[0], k * c[1]];
        d.normal = page.point(self.normal);
        for v in &mut d.vehicles {
            let cg = page.point([self.centre[0] + v.cg[0], self.centre[1] + v.cg[1]]);
            v.cg = [k * cg[0], k * cg[1]];
            v.heading += d.turned;
            for w in [&mut v.contact, &mut v.separation, &mut v.impulse]
                .into_iter()
                .flatten()
            {
                *w = page.point(*w);
            }
            if let Some(p) = &mut v.pdof {
                p.0 = page.point(p.0);
            }
            let b = &mut v.outline.body;
            b.cg_to_front *= k;
            b.cg_to_rear *= k;
            b.width *= k;
        }
        d
    }

    /// Vehicle `k`'s outline as drawn: on the page, in the display length unit (the corners of
    /// the body, in order).
    pub fn outline_on_page(&self, k: usize) -> Vec<(f64, f64)> {
        self.in_display_units().outline_points(k)
    }

    /// The PDOF arrow of vehicle `k`, on its own body: along the force, from just inside the
    /// outline on the side the force comes from, towards the CG (stopping short of it, where
    /// the velocity arrows start).
    fn pdof_arrow(&self, k: usize) -> Option<([f64; 2], [f64; 2])> {
        let v = &self.vehicles[k];
        let (u, _, _) = v.pdof?;
        let back = rotate([-u[0], -u[1]], -v.heading);
        let edge = v.outline.exit(back);
        let (a, b) = (0.9 * edge, 0.25 * edge);
        let start = [v.cg[0] - a * u[0], v.cg[1] - a * u[1]];
        let end = [v.cg[0] - b * u[0], v.cg[1] - b * u[1]];
        Some((start, end))
    }

    fn outline_points(&self, k: usize) -> Vec<(f64, f64)> {
        let v = &self.vehicles[k];
        v.outline
            .corners()
            .iter()
            .map(|c| {
                let p = rotate(*c, v.heading);
                (v.cg[0] + p[0], v.cg[1] + p[1])
            })
            .collect()
    }

    /// Metres of arrow per m/s, so that the longest velocity arrow is 0.6 of the longer vehicle.
    fn velocity_scale(&self) -> f64 {
        let max = self
            .vehicles
            .iter()
            .flat_map(|v| [v.contact, v.separation])
            .flatten()
            .map(|u| u[0].hypot(u[1]))
            .fold(0.0, f64::max);
        if max > 0.0 {
            0.6 * self.longest() / max
        } else {
            0.0
        }
    }

    /// Metres of arrow per N s: the impulse arrow is 0.5 of the longer vehicle.
    fn impulse_scale(&self) -> f64 {
        let max = self
            .vehicles
            .iter()
            .filter_map(|v| v.impulse)
            .map(|u| u[0].hypot(u[1]))
            .fold(0.0, f64::max);
        if max > 0.0 {
            0.5 * self.longest() / max
        } else {
            0.0
        }
    }

    fn longest(&self) -> f64 {
        self.vehicles
            .iter()
            .map(|v| v.outline.length())
            .fold(0.0, f64::max)
    }

    /// Every segment drawn (for the extent of the view).
    fn extent(&self) -> ([f64; 2], [f64; 2]) {
        let mut pts: Vec<[f64; 2]> = vec![self.centre];
        let sv = self.velocity_scale();
        let si = self.impulse_scale();
        for (k, v) in self.vehicles.iter().enumerate() {
            pts.extend(self.outline_points(k).iter().map(|p| [p.0, p.1]));
            for u in [v.contact, v.separation].into_iter().flatten() {
                pts.push([v.cg[0] + sv * u[0], v.cg[1] + sv * u[1]]);
            }
            if let Some(p) = v.impulse {
                pts.push([self.centre[0] + si * p[0], self.centre[1] + si * p[1]]);
            }
            if let Some((a, _)) = self.pdof_arrow(k) {
                pts.push(a);
            }
        }
        // `min` and `max` pass over a NaN: a point not finite makes the extent so.
        if pts.iter().flatten().any(|x| !x.is_finite()) {
            return ([f64::NAN; 2], [f64::NAN; 2]);
        }
        let lo = pts
            .iter()
            .fold([f64::INFINITY; 2], |a, p| [a[0].min(p[0]), a[1].min(p[1])]);
        let hi = pts.iter().fold([f64::NEG_INFINITY; 2], |a, p| {
            [a[0].max(p[0]), a[1].max(p[1])]
        });
        (lo, hi)
    }

    /// The diagram as SVG text.
    ///
    /// A diagram whose extent is not finite (a non-finite dimension or velocity that reached it
    /// without validation) is an error, never handed to the plotting library, whose axis ticks
    /// would not end.
    pub fn svg(&self) -> Result<String, crate::RenderError> {
        let (lo, hi) = self.extent();
        if !lo.iter().chain(&hi).all(|x| x.is_finite()) {
            return Err(crate::RenderError::NotFinite(
                "a dimension or velocity of the plan view (check length, width, cg_to_front and \
                 the velocities)",
            ));
        }
        let mut buf = String::new();
        self.in_display_units().draw_into(&mut buf)?;
        Ok(buf)
    }
}

/// The estimated contact velocities of a fit case, when all six are given.
pub fn estimated_contact(case: &pim_case::case::Case) -> Option<Velocities> {
    case.estimated_contact()
}

/// The diagram of a case, solved or not, labelled in the case's own units and frame.
pub fn diagram(
    case: &pim_case::case::Case,
    impact: &Impact,
    contact: Option<&Velocities>,
    solved: Option<Solved>,
) -> Diagram {
    Diagram::new(&case.heading(), impact, case.vehicles(), contact, solved)
        .labelled(UnitSystem::of(&case.written_units), case.written)
        .centred(case.impact_centre())
}

/// The diagram of `pim draw`: the case at contact, solved with `options` when it has
/// `[coefficients]` and a state, with the estimated contact velocities when it is a fit case.
pub fn case_diagram(
    case: &pim_case::case::Case,
    options: &pim_core::SolveOptions,
) -> Result<Diagram, pim_studies::documents::DocumentError> {
    let impact = case.impact()?;
    let solved = if case.solvable() {
        Some(pim_studies::documents::solve(case, options)?.report)
    } else {
        None
    };
    let contact = estimated_contact(case);
    Ok(diagram(
        case,
        &impact,
        contact.as_ref(),
        solved.as_ref().map(Solved::of_report),
    ))
}

/// The diagram of a solved case (`pim solve --out`, the report): the solved states, with a
/// subtitle saying it is a solve and with which coefficients.
pub fn of_solve(case: &pim_case::case::Case, s: &pim_studies::documents::Solved) -> Diagram {
    let contact = estimated_contact(case);
    let mut d = diagram(
        case,
        &s.impact,
        contact.as_ref(),
        Some(Solved::of_report(&s.report)),
    );
    let c = &s.report.coefficients;
    d.subtitle = Some(format!(
        "solved {}: e {}, mu {}, em {}",
        if s.forward { "forwards" } else { "backwards" },
        c.e,
        c.mu,
        c.em
    ));
    d
}

/// The diagram of a fitted case (`pim fit --out`, the report): the best branch's fitted states
/// at its own geometry, with a subtitle naming the fit, its cost function, branch and cost, and
/// the bounds the answer rests on in the key. `cost` is the cost function's name.
pub fn of_fit(
    case: &pim_case::case::Case,
    f: &pim_studies::documents::Fitted,
    cost: &str,
) -> Result<Diagram, crate::RenderError> {
    let report = &f.report;
    let contact = estimated_contact(case);
    let best = report.best_branch().and_then(|b| b.solution.as_ref());
    // With estimated geometry, the collision at the best branch's estimate.
    let mut impact = f.problem.impact;
    if let Some(g) = report.best_branch().and_then(|b| b.geometry.as_ref()) {
        let mut c = *impact.collision();
        g.apply(&mut c);
        impact = Impact::new(c).map_err(crate::RenderError::Impact)?;
    }
    let mut d = diagram(case, &impact, contact.as_ref(), best.map(Solved::of_fit));
    if let Some(b) = report.best_branch() {
        d.subtitle = Some(match (report.model, b.solution.as_ref()) {
            (pim_fit::FitModel::Tangential, Some(s)) => {
                format!("fit, cost {cost}: tangential model, cost {:.4}", s.cost)
            }
            (_, Some(s)) => format!(
                "fit, cost {cost}: {} (e {:.3}, mu {:.3}, em {:.3}), cost {:.4}",
                crate::tables::branch_short(b.moment),
                s.e,
                s.mu,
                s.em,
                s.cost
            ),
            (_, None) => format!("fit, cost {cost}: no admissible answer"),
        });
    }
    let best_record = f
        .document
        .branches
        .iter()
        .find(|r| Some(r.moment) == report.best);
    for b in best_record.iter().flat_map(|r| &r.bounds_reached) {
        d.notes.push(format!(
            "rests on [bounds] {} ({}, {})",
            b.bound,
            b.at,
            match b.source {
                pim_documents::records::BoundSource::Case => "set in the case",
                pim_documents::records::BoundSource::Default => "a default",
            }
        ));
    }
    Ok(d)
}
