//! The scene on the page: what [`crate::answer`] draws of a case (positions to the right and
//! up in the display length unit, the frame's way round).

use crate::error::AnswerError;
use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_core::Convention;
use serde::Serialize;

/// The scene on the page: positions to the right and up, in the case's display length unit
/// (`length_label`), the frame's way round (`frame`: an SAE case is drawn as a map, x up).
#[derive(Debug, Serialize, Default)]
pub struct Plan {
    /// `natural` or `sae`.
    pub frame: &'static str,
    /// The length unit's label (`m`, `ft`).
    pub length_label: &'static str,
    /// Metres per display length unit.
    pub metres: f64,
    /// The speed unit's label.
    pub speed_label: &'static str,
    /// Metres per second per display speed unit.
    pub speed_metres: f64,
    /// Each vehicle.
    pub vehicles: Vec<PlanVehicle>,
    /// The case's `[background]` image, placed on the page.
    pub background: Option<PlanBackground>,
    /// The impact centre and the crush surface's normal, on the page.
    pub impact: Option<PlanImpact>,
    /// The ground's friction zones (`[[runout.zones]]`), on the page.
    pub zones: Vec<PlanZone>,
    /// The answer's motion in time (a reconstruction's), for the time slider.
    pub motion: Option<crate::motion::PlanMotion>,
    /// The speeds before contact beside the EDR's (`speed_history.svg` of `pim fit --out`),
    /// when a vehicle has an EDR.
    pub speed_history: Option<String>,
    /// The case's surveyed points (`[survey]`), on the page.
    pub survey: Vec<PlanSurveyPoint>,
}

/// A surveyed point on the page.
#[derive(Debug, Serialize, Default)]
pub struct PlanSurveyPoint {
    /// The surveyor's id.
    pub id: String,
    /// Where it lies on the page.
    pub at: [f64; 2],
    /// The surveyor's code, if any.
    pub code: Option<String>,
    /// What it is, if said.
    pub description: Option<String>,
}

/// A friction zone on the page: its corners and its friction.
#[derive(Debug, Serialize, Default)]
pub struct PlanZone {
    /// The polygon's corners, the display length unit on the page.
    pub corners: Vec<[f64; 2]>,
    /// Its friction coefficient.
    pub friction: f64,
}

/// The impact on the page: the centre and the direction of the crush surface's normal as the
/// case gives it (`crush_angle`), degrees counter-clockwise from the page's right.
#[derive(Debug, Serialize, Default)]
pub struct PlanImpact {
    /// The impact centre.
    pub centre: [f64; 2],
    /// The normal's direction.
    pub normal: f64,
}

/// A background image on the page: pixel `(u, v)` (right, down from its top left) lies at
/// `at + per_pixel R(rotation) ((u, v) - pixels[0])` with the pixel's down turned to the
/// page's down.
#[derive(Debug, Serialize, Default)]
pub struct PlanBackground {
    /// The image's path inside the folder served (`GET /api/image?path=`).
    pub image: String,
    /// The two points on the image that set its scale, pixels.
    pub pixels: [[f64; 2]; 2],
    /// Their distance, the display length unit.
    pub distance: f64,
    /// Where the first point lies on the page.
    pub at: [f64; 2],
    /// Display length units per pixel.
    pub per_pixel: f64,
    /// Degrees turned counter-clockwise on the page.
    pub rotation: f64,
    /// Not moved by dragging.
    pub locked: bool,
}

/// One vehicle on the page.
#[derive(Debug, Serialize, Default)]
pub struct PlanVehicle {
    /// 1 or 2.
    pub vehicle: u8,
    /// Its outline at contact (closed polygon).
    pub contact: Vec<[f64; 2]>,
    /// Its outline at rest, where the run-out ends.
    pub rest: Vec<[f64; 2]>,
    /// Its outline every half second of the run-out.
    pub every: Vec<Vec<[f64; 2]>>,
    /// The CG's path.
    pub path: Vec<[f64; 2]>,
    /// The rest position the scene gives (CG), its heading on the page (deg counter-clockwise
    /// from the page's right) and its standard deviations.
    pub given_rest: Option<GivenRest>,
    /// The marks the scene gives: position and standard deviation.
    pub marks: Vec<[f64; 3]>,
    /// The path of each tyre that left a mark (a mark's residual is its distance from it).
    pub traces: Vec<Vec<[f64; 2]>>,
    /// Its CG at contact.
    pub cg: [f64; 2],
    /// Its heading at contact, degrees counter-clockwise from the page's right.
    pub heading: f64,
    /// The length of its skid up to contact (`[pre_impact.vehicleN] skid`), display unit.
    pub skid: Option<f64>,
    /// Its crush profile on its outline at contact (`[damage.vehicleN]`), a closed polygon.
    pub damage: Vec<[f64; 2]>,
}

/// A rest position given by the scene, on the page.
#[derive(Debug, Serialize)]
pub struct GivenRest {
    /// Its CG.
    pub at: [f64; 2],
    /// Its standard deviations along the page's axes (right, up).
    pub sigma: [f64; 2],
    /// The vehicle's outline there.
    pub outline: Vec<[f64; 2]>,
    /// The tyres measured at rest, when the rest is given by them.
    pub tyres: Vec<[f64; 2]>,
    /// The heading given at rest on the page, degrees counter-clockwise from the page's right
    /// (a rest given as its CG and heading: the page turns it by a knob).
    pub heading: Option<f64>,
}

/// The friction `zones` (SI, natural frame) on the page (`on_page`).
fn zones_on_page(
    zones: &[pim_runout::Zone],
    on_page: impl Fn(f64, f64) -> [f64; 2],
) -> Vec<PlanZone> {
    zones
        .iter()
        .map(|z| PlanZone {
            corners: z.corners.iter().map(|c| on_page(c[0], c[1])).collect(),
            friction: z.friction,
        })
        .collect()
}

/// The scene on the page: the run-outs `runouts` (or without them, the vehicles where they
/// stand and the evidence only).
pub(crate) fn plan(
    case: &Case,
    runouts: Option<&pim_studies::runout::RunoutResult>,
    units: UnitSystem,
) -> Result<Plan, AnswerError> {
    let page = pim_render::plan::Page::of(case.written);
    let mut out = Sketch {
        convention: case.written,
        units: case.written_units,
        background: case.background().cloned(),
        survey: case.survey().cloned(),
    }
    .plan(&case.file, units);
    let page_angle = |a: f64| page_angle(&page, a);
    if let Ok(impact) = case.impact() {
        let c = case.impact_centre();
        let (h, v) = page.xy((units.length(c[0]), units.length(c[1])));
        out.impact = Some(PlanImpact {
            centre: [h, v],
            normal: page_angle(impact.collision().crush_angle.to_radians()),
        });
    }
    let Some(r) = runouts else {
        return Ok(out);
    };
    plan_runouts(case, r, units, out)
}

/// A direction (natural frame, radians) on the page, degrees counter-clockwise from the
/// page's right.
fn page_angle(page: &pim_render::plan::Page, a: f64) -> f64 {
    let (o, d) = (page.xy((0.0, 0.0)), page.xy((a.cos(), a.sin())));
    (d.1 - o.1).atan2(d.0 - o.0).to_degrees()
}

/// What the text of a case being built gives the plan before it is a case: its frame, its
/// units, its background and its survey (every other section ignored).
#[derive(Debug, serde::Deserialize)]
pub(crate) struct Sketch {
    /// The frame it is written in.
    #[serde(default)]
    pub(crate) convention: Convention,
    /// Its `[units]` as written.
    #[serde(default)]
    pub(crate) units: pim_case::units::UnitsSection,
    /// Its `[background]`.
    #[serde(default)]
    pub(crate) background: Option<pim_case::scene_sections::BackgroundSection>,
    /// Its `[survey]`.
    #[serde(default)]
    pub(crate) survey: Option<pim_case::survey::SurveySection>,
}

impl Sketch {
    /// The sketch of `text`, if it is TOML whose frame, units, background and survey read.
    pub(crate) fn of(text: &str) -> Option<Sketch> {
        toml::from_str(text).ok()
    }

    /// The sketch of the text `text` of `file` and whether it is a case `pim fit` reads: a
    /// case, or a case being built whose frame, units, background and survey read.
    ///
    /// # Errors
    /// Text that is neither (with pim's message for the case).
    pub(crate) fn read(file: &str, text: &str) -> Result<(Sketch, bool), AnswerError> {
        match Case::from_text(file, text) {
            Ok(case) => Ok((
                Sketch {
                    convention: case.written,
                    units: case.written_units,
                    background: case.background().cloned(),
                    survey: case.survey().cloned(),
                },
                true,
            )),
            Err(e) => Self::of(text)
                .filter(|_| !Self::is_started(text))
                .map(|s| (s, false))
                .ok_or_else(|| AnswerError::Input(e.to_string())),
        }
    }

    /// Whether `text` writes both vehicles and the impact, the sections every case has (then
    /// it is meant as a case, and held to one).
    fn is_started(text: &str) -> bool {
        #[derive(serde::Deserialize)]
        struct Required {
            vehicle1: Option<toml::Value>,
            vehicle2: Option<toml::Value>,
            impact: Option<toml::Value>,
        }
        toml::from_str::<Required>(text)
            .is_ok_and(|v| v.vehicle1.is_some() && v.vehicle2.is_some() && v.impact.is_some())
    }

    /// Checks the text an edit made: as a case when it was one before (or writes both
    /// vehicles and the impact), else its background as a case checks it.
    ///
    /// # Errors
    /// pim's message for a case; the background's fault otherwise.
    pub(crate) fn check_edited(file: &str, text: &str, was_case: bool) -> Result<(), AnswerError> {
        if was_case || Self::is_started(text) {
            return Case::from_text(file, text)
                .map(|_| ())
                .map_err(|e| AnswerError::Input(e.to_string()));
        }
        let Some(s) = Self::of(text) else {
            return Err(AnswerError::Input(format!(
                "{file}: its [units], [background] or [survey] do not read"
            )));
        };
        if let Some(b) = &s.background {
            b.check().map_err(|(key, what)| {
                AnswerError::Input(format!("{file}: background.{key}: {what}"))
            })?;
        }
        Ok(())
    }

    /// The unit system the text's `[units]` shows its results in.
    pub(crate) fn system(&self) -> UnitSystem {
        UnitSystem::of(&self.units)
    }

    /// The plan of the sketch (of the file `file`) in `units`.
    pub(crate) fn plan(&self, file: &str, units: UnitSystem) -> Plan {
        // Written in the file's frame and length unit.
        let length = self.units.length.to_si();
        let on_page = |x: f64, y: f64| {
            self.convention
                .page_of_written([x, y].map(|v| units.length(v * length)))
        };
        let mut out = Plan {
            frame: if self.convention.mirrors() {
                "sae"
            } else {
                "natural"
            },
            length_label: units.length_label(),
            metres: units.length(1.0).recip(),
            speed_label: units.speed_label(),
            speed_metres: units.speed(1.0).recip(),
            vehicles: Vec::new(),
            background: None,
            impact: None,
            zones: Vec::new(),
            motion: None,
            speed_history: None,
            survey: Vec::new(),
        };
        if let Some(b) = self.background.as_ref().filter(|b| b.check().is_ok()) {
            let at = b.at.map_or([0.0, 0.0], |p| [p.x, p.y]);
            let [p, q] = b.pixels;
            let distance = units.length(b.distance * length);
            let folder = std::path::Path::new(file)
                .parent()
                .unwrap_or(std::path::Path::new(""));
            out.background = Some(PlanBackground {
                image: folder.join(&b.image).to_string_lossy().replace('\\', "/"),
                pixels: b.pixels,
                distance,
                at: on_page(at[0], at[1]),
                per_pixel: distance / (q[0] - p[0]).hypot(q[1] - p[1]),
                rotation: b.rotation,
                locked: b.locked,
            });
        }
        if let Some(s) = &self.survey {
            out.survey = s
                .points
                .iter()
                .map(|p| PlanSurveyPoint {
                    id: p.id.clone(),
                    at: on_page(p.x, p.y),
                    code: p.code.clone(),
                    description: p.description.clone(),
                })
                .collect();
        }
        out
    }
}

/// The run-outs `r` of `case` drawn on the plan `out`.
fn plan_runouts(
    case: &Case,
    r: &pim_studies::runout::RunoutResult,
    units: UnitSystem,
    mut out: Plan,
) -> Result<Plan, AnswerError> {
    let page = pim_render::plan::Page::of(case.written);
    let page_angle = |a: f64| page_angle(&page, a);
    let on_page = |x: f64, y: f64| {
        let (h, v) = page.xy((units.length(x), units.length(y)));
        [h, v]
    };
    out.zones = r
        .inputs
        .first()
        .map_or(Vec::new(), |v| zones_on_page(&v.chassis.zones, on_page));
    let outline = |k: usize, m: &pim_runout::Motion| -> Vec<[f64; 2]> {
        pim_render::runout::outline_on_page(r, k, m, units, case.written)
            .into_iter()
            .map(|(h, v)| [h, v])
            .collect()
    };
    let damage = pim_case::damage::Damage::of(case).ok().flatten();
    // Each vehicle's skid before the impact, m.
    let skids = case
        .pre_impact_vehicles()
        .map(|p| p.map(|v| v.and_then(|v| v.skid).map(|s| s.distance)))
        .unwrap_or_default();
    for (k, (input, run)) in r.inputs.iter().zip(&r.runouts).enumerate() {
        let crush = damage
            .as_ref()
            .and_then(|d| d.vehicles[input.id.index()].as_ref())
            .map(|d| {
                pim_render::runout::damage_on_page(r, k, &run.start, d, units, case.written)
                    .into_iter()
                    .map(|(h, v)| [h, v])
                    .collect()
            })
            .unwrap_or_default();
        let evidence = input.evidence.as_ref();
        let given_rest = evidence.and_then(|e| e.rest).map(|rest| {
            // Where the CG rests as measured (the tyres' rest is of their centroid).
            let (x, y) = rest.cg();
            let pose = pim_runout::Motion {
                x,
                y,
                heading: rest.heading.unwrap_or(run.rest.heading),
                ..pim_runout::Motion::default()
            };
            GivenRest {
                at: on_page(x, y),
                sigma: case
                    .written
                    .page_of_written(rest.sigma_xy.map(|s| units.length(s)))
                    .map(f64::abs),
                outline: outline(k, &pose),
                tyres: input
                    .rest_tyres
                    .iter()
                    .map(|t| on_page(t[0], t[1]))
                    .collect(),
                heading: rest
                    .heading
                    .filter(|_| input.rest_tyres.is_empty())
                    .map(page_angle),
            }
        });
        let marks = evidence
            .map(|e| {
                e.marks
                    .iter()
                    .map(|m| {
                        let [h, v] = on_page(m.x, m.y);
                        [h, v, units.length(m.sigma)]
                    })
                    .collect()
            })
            .unwrap_or_default();
        let traces = pim_render::runout::tyre_traces(run, evidence)
            .into_iter()
            .map(|t| t.into_iter().map(|(x, y)| on_page(x, y)).collect())
            .collect();
        let every = run.sample(0.5).iter().map(|(_, m)| outline(k, m)).collect();
        out.vehicles.push(PlanVehicle {
            vehicle: input.id.index() as u8 + 1,
            contact: outline(k, &run.start),
            rest: outline(k, &run.rest),
            every,
            path: run
                .sample(0.05)
                .iter()
                .map(|(_, m)| on_page(m.x, m.y))
                .collect(),
            given_rest,
            marks,
            traces,
            cg: on_page(run.start.x, run.start.y),
            heading: page_angle(run.start.heading),
            skid: skids[input.id.index()].map(|l| units.length(l)),
            damage: crush,
        });
    }
    Ok(out)
}
