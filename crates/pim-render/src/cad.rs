//! The scene for CAD: a reconstruction's plan as a DXF drawing (AutoCAD 2000, read by every
//! CAD program), each kind of thing on a layer of its own, both vehicles in their colours
//! (vehicle 1 blue, ACI 5; vehicle 2 red, ACI 1).
//!
//! The coordinates are the plan's, as the scene figure and the editor draw it: the page's
//! right and up in the display length unit (the drawing's units say which: feet or metres).
//! For a case written in the natural frame that is its own x and y; for an SAE case (x ahead,
//! y to the right) the page's right is its y and the page's up its x, so that the drawing lies
//! over a survey drawn with north up.
//!
//! | layer | what |
//! |---|---|
//! | `CONTACT` | each vehicle's outline at contact (closed) |
//! | `REST` | each vehicle's outline at rest, where its fitted run-out ends (closed) |
//! | `PATHS` | each CG's path: the braking before contact, then the fitted run-out |
//! | `TYRE_PATHS` | the path of each tyre that left a mark |
//! | `EVIDENCE` | each rest as the scene gives it (a point, a circle of its mean sigma) and each mark (a point, a circle of its sigma) |
//! | `ZONES` | each friction zone (closed) and its friction as text |
//! | `IMPACT` | the impact centre (a point) |

use crate::plan::Page;
use dxf::entities::{Circle, Entity, EntityType, LwPolyline, ModelPoint, Text};
use dxf::enums::{AcadVersion, Units};
use dxf::tables::Layer;
use dxf::{Color, Drawing, LwPolylineVertex, Point};
use pim_case::units::UnitSystem;

/// The layers, in the order written, with their colours (ACI).
pub const LAYERS: [(&str, u8); 7] = [
    ("CONTACT", 7),
    ("REST", 7),
    ("PATHS", 7),
    ("TYRE_PATHS", 8),
    ("EVIDENCE", 7),
    ("ZONES", 3),
    ("IMPACT", 7),
];

/// Each vehicle's colour (ACI): 1 blue, 2 red.
const VEHICLE: [u8; 2] = [5, 1];

/// The plan of the reconstruction `done` of `case` as a DXF file's bytes, in `units`' length
/// unit (see the module docs). `None` without an answer.
///
/// # Errors
/// The fitted run-outs cannot be found again, or the drawing cannot be written (a message).
pub fn reconstruction_dxf(
    case: &pim_case::case::Case,
    done: &pim_studies::reconstruct::Reconstructed,
    units: UnitSystem,
) -> Result<Option<Vec<u8>>, crate::RenderError> {
    let Some(runouts) = crate::runout::fitted_runouts(case, done)? else {
        return Ok(None);
    };
    reconstruction_dxf_of(case, done, &runouts, units).map(Some)
}

/// [`reconstruction_dxf`] of the fitted run-outs `runouts`
/// ([`crate::runout::fitted_runouts`]).
///
/// # Errors
/// The drawing cannot be written (a message).
pub fn reconstruction_dxf_of(
    case: &pim_case::case::Case,
    done: &pim_studies::reconstruct::Reconstructed,
    runouts: &pim_studies::runout::RunoutResult,
    units: UnitSystem,
) -> Result<Vec<u8>, crate::RenderError> {
    let Some(best) = &done.outcome.best else {
        return Err(crate::RenderError::Nothing("no reconstruction"));
    };
    let page = Page::of(case.written);
    let at = |x: f64, y: f64| page.xy((units.length(x), units.length(y)));
    let mut d = Drawing::new();
    d.header.version = AcadVersion::R2000;
    // The same case gives the same file on every machine: no clock, no time zone and no random
    // identifiers (the dates 2000-01-01 00:00 both local and universal, the identifiers nil).
    let midnight = chrono::NaiveDate::from_ymd_opt(2000, 1, 1)
        .and_then(|d| d.and_hms_opt(0, 0, 0))
        .unwrap_or_default();
    let local = chrono::TimeZone::from_local_datetime(&chrono::Local, &midnight)
        .earliest()
        .unwrap_or_default();
    let universal = chrono::TimeZone::from_utc_datetime(&chrono::Utc, &midnight);
    d.header.creation_date = local;
    d.header.update_date = local;
    d.header.creation_date_universal = universal;
    d.header.update_date_universal = universal;
    d.header.fingerprint_guid = Default::default();
    d.header.version_guid = Default::default();
    d.header.default_drawing_units = if units == UnitSystem::Us {
        Units::Feet
    } else {
        Units::Meters
    };
    for (name, color) in LAYERS {
        d.add_layer(Layer {
            name: name.into(),
            color: Color::from_index(color),
            ..Default::default()
        });
    }
    let tracks = pim_studies::playback::tracks(done, best, runouts, 0.02);
    for t in &tracks {
        let k = t.index;
        let color = VEHICLE[t.vehicle.index().min(1)];
        let run = &runouts.runouts[k];
        let outline = |m| crate::runout::outline_on_page(runouts, k, m, units, case.written);
        add(
            &mut d,
            "CONTACT",
            color,
            polyline(&outline(&run.start), true),
        );
        add(&mut d, "REST", color, polyline(&outline(&run.rest), true));
        let path: Vec<(f64, f64)> = t.poses.iter().map(|(_, m)| at(m.x, m.y)).collect();
        add(&mut d, "PATHS", color, polyline(&path, false));
        let evidence = runouts.inputs[k].evidence.as_ref();
        for tyre in crate::runout::tyre_traces(run, evidence) {
            let p: Vec<(f64, f64)> = tyre.iter().map(|&(x, y)| at(x, y)).collect();
            add(&mut d, "TYRE_PATHS", color, polyline(&p, false));
        }
        let Some(e) = evidence else { continue };
        if let Some(r) = &e.rest {
            let sigma = units.length(0.5 * (r.sigma_xy[0] + r.sigma_xy[1]));
            marker(&mut d, color, at(r.x, r.y), sigma);
        }
        for m in &e.marks {
            marker(&mut d, color, at(m.x, m.y), units.length(m.sigma));
        }
    }
    let zones = runouts
        .inputs
        .first()
        .map_or(&[][..], |v| &v.chassis.zones[..]);
    for z in zones {
        let corners: Vec<(f64, f64)> = z.corners.iter().map(|c| at(c[0], c[1])).collect();
        add(&mut d, "ZONES", 3, polyline(&corners, true));
        let n = corners.len() as f64;
        let mid = corners
            .iter()
            .fold((0.0, 0.0), |m, c| (m.0 + c.0 / n, m.1 + c.1 / n));
        let text = Text {
            location: Point::new(mid.0, mid.1, 0.0),
            text_height: units.length(0.5),
            value: format!("friction {}", crate::tables::num(z.friction, 2)),
            ..Default::default()
        };
        add(&mut d, "ZONES", 3, EntityType::Text(text));
    }
    let c = case.impact_centre();
    let (h, v) = at(c[0], c[1]);
    add(
        &mut d,
        "IMPACT",
        7,
        EntityType::ModelPoint(ModelPoint::new(Point::new(h, v, 0.0))),
    );
    let mut bytes = Vec::new();
    d.save(&mut bytes).map_err(crate::err)?;
    Ok(bytes)
}

/// `points` as a light-weight polyline, `closed` or open.
fn polyline(points: &[(f64, f64)], closed: bool) -> EntityType {
    let mut p = LwPolyline::default();
    // A closed outline's last corner repeats its first: the flag closes it instead.
    let n = if closed && points.len() > 1 && points.first() == points.last() {
        points.len() - 1
    } else {
        points.len()
    };
    p.vertices = points[..n]
        .iter()
        .map(|&(x, y)| LwPolylineVertex {
            x,
            y,
            ..Default::default()
        })
        .collect();
    p.set_is_closed(closed);
    EntityType::LwPolyline(p)
}

/// A piece of evidence at `p` on the `EVIDENCE` layer: a point and a circle of radius
/// `sigma`.
fn marker(d: &mut Drawing, color: u8, p: (f64, f64), sigma: f64) {
    let centre = Point::new(p.0, p.1, 0.0);
    add(
        d,
        "EVIDENCE",
        color,
        EntityType::ModelPoint(ModelPoint::new(centre.clone())),
    );
    add(
        d,
        "EVIDENCE",
        color,
        EntityType::Circle(Circle::new(centre, sigma)),
    );
}

/// `what` added on `layer` in the colour `color` (ACI).
fn add(d: &mut Drawing, layer: &str, color: u8, what: EntityType) {
    let mut e = Entity::new(what);
    e.common.layer = layer.into();
    e.common.color = Color::from_index(color);
    d.add_entity(e);
}
