//! A case started from nothing, and its sections added one at a time: each section written
//! with starting values (a mid-size car, a dry road) in the case's own units, a comment after
//! every value naming its unit and what to put there. The values are places to start, not
//! evidence: a rest, a skid or an EDR added this way is meant to be replaced by what the scene
//! gave.

use crate::edit::{CaseEdit, Quantity};
use crate::error::{InputError, Result};
use crate::units::UnitsSection;
use pim_core::Convention;

/// A value of a section's template, in SI.
#[derive(Debug, Clone, Copy)]
enum Start {
    /// A number and what it measures.
    Num(f64, Quantity),
    /// A text.
    Text(&'static str),
    /// A point `{ x, y }` (m).
    Point(f64, f64),
    /// A yaw rate `{ omega }` per vehicle (rad/s).
    Omega(f64),
    /// TOML written as is.
    Raw(&'static str),
}

/// A section the page (or a user) can add: its name, what it holds, its values.
#[derive(Debug, Clone, Copy)]
pub struct Section {
    /// Its table's dotted name (`vehicle1`, `runout.vehicle2`).
    pub table: &'static str,
    /// What it is for, in a line.
    pub what: &'static str,
    values: &'static [(&'static str, Start, &'static str)],
}

const DEG: f64 = std::f64::consts::PI / 180.0;

macro_rules! vehicle {
    ($heading:expr, $x:expr, $what:expr) => {
        &[
            ("description", Start::Text($what), "what it is"),
            (
                "mass",
                Start::Num(1500.0, Quantity::Mass),
                "with its occupants",
            ),
            (
                "heading",
                Start::Num($heading, Quantity::Angle),
                "deg: its heading at contact",
            ),
            ("position", Start::Point($x, 0.0), "its CG at contact"),
            ("length", Start::Num(4.7, Quantity::Length), "overall"),
            ("width", Start::Num(1.8, Quantity::Length), "overall"),
            (
                "cg_to_front",
                Start::Num(2.2, Quantity::Length),
                "CG to the front bumper",
            ),
        ]
    };
}

macro_rules! chassis {
    () => {
        &[
            ("wheelbase", Start::Num(2.7, Quantity::Length), ""),
            ("track", Start::Num(1.55, Quantity::Length), ""),
            (
                "cg_to_front_axle",
                Start::Num(1.1, Quantity::Length),
                "CG to the front axle",
            ),
            (
                "wheels",
                Start::Text("rolling"),
                "each wheel after the impact: locked, rolling, abs, or a table of the four",
            ),
            (
                "braking",
                Start::Num(0.0, Quantity::Plain),
                "the rolling wheels' braking, a fraction of the friction",
            ),
        ]
    };
}

/// The sections that can be added, in the order a case is usually written. A rest is not
/// among them: it is where the scene puts it, placed on the plan (`pim serve`'s Rest tool) or
/// written in `[scene.vehicleN]`.
pub const SECTIONS: [Section; 10] = [
    Section {
        table: "vehicle1",
        what: "vehicle 1: mass, size (its yaw inertia estimated from them unless given), where it was at contact",
        values: vehicle!(0.0, -2.5, "vehicle 1"),
    },
    Section {
        table: "vehicle2",
        what: "vehicle 2: mass, size (its yaw inertia estimated from them unless given), where it was at contact",
        values: vehicle!(90.0 * DEG, 1.2, "vehicle 2"),
    },
    Section {
        table: "impact",
        what: "the impact centre and the crush surface",
        values: &[
            ("centre", Start::Point(0.0, 0.0), "the impact centre"),
            (
                "crush_angle_from_vehicle1",
                Start::Num(0.0, Quantity::Angle),
                "deg: the crush surface's normal from vehicle 1's nose",
            ),
        ],
    },
    Section {
        table: "estimates.initial",
        what: "what is known at contact: each vehicle's yaw rate",
        values: &[
            ("vehicle1", Start::Omega(0.0), ""),
            ("vehicle2", Start::Omega(0.0), ""),
        ],
    },
    Section {
        table: "sigma.initial",
        what: "how well it is known",
        values: &[
            ("vehicle1", Start::Omega(5.0 * DEG), ""),
            ("vehicle2", Start::Omega(5.0 * DEG), ""),
        ],
    },
    Section {
        table: "runout",
        what: "the road after the impact: its friction and spread",
        values: &[
            (
                "friction",
                Start::Num(0.72, Quantity::Plain),
                "dry asphalt: a drag-sled's value if measured",
            ),
            (
                "friction_sigma",
                Start::Num(0.05, Quantity::Plain),
                "its spread",
            ),
        ],
    },
    Section {
        table: "runout.vehicle1",
        what: "vehicle 1's wheels after the impact",
        values: chassis!(),
    },
    Section {
        table: "runout.vehicle2",
        what: "vehicle 2's wheels after the impact",
        values: chassis!(),
    },
    Section {
        table: "pre_impact.vehicle1",
        what: "vehicle 1 before the impact: its skid up to contact",
        values: &[
            (
                "skid",
                Start::Num(10.0, Quantity::Length),
                "locked-wheel skid up to the impact",
            ),
            (
                "braking",
                Start::Num(1.0, Quantity::Plain),
                "1: all wheels locked",
            ),
        ],
    },
    Section {
        table: "pre_impact.vehicle2",
        what: "vehicle 2 before the impact: its EDR",
        values: &[(
            "edr",
            Start::Raw("edr"),
            "speed, s before contact, g, sigma",
        )],
    },
];

use crate::units::unit_label;

fn label(q: Quantity, units: &UnitsSection) -> String {
    match q {
        Quantity::Length | Quantity::Crush => units.length.label().to_string(),
        Quantity::Speed => unit_label(units.speed),
        Quantity::Mass => unit_label(units.mass),
        Quantity::YawInertia => unit_label(units.yaw_inertia),
        Quantity::YawRate => unit_label(units.yaw_rate),
        Quantity::Angle | Quantity::Plain => String::new(),
    }
}

/// A number written in the file's unit, to three significant digits (an angle to a degree)
/// and always as a float.
fn written(si: f64, q: Quantity, units: &UnitsSection) -> String {
    let x = si / q.si_per_unit(units);
    let x = if q == Quantity::Angle || x == 0.0 {
        x.round()
    } else {
        let scale = 10f64.powi(2 - x.abs().log10().floor() as i32);
        (x * scale).round() / scale
    };
    toml_edit::Value::from(x + 0.0).to_string()
}

impl Section {
    /// The section as TOML in a file with these units: `[name]` and a line per value with its
    /// comment.
    pub fn text(&self, units: &UnitsSection) -> String {
        let length = units.length.label();
        let mut out = format!("[{}]\n", self.table);
        for (key, start, comment) in self.values {
            let (value, unit) = match *start {
                Start::Num(si, q) => (written(si, q, units), label(q, units)),
                Start::Text(t) => (toml_edit::Value::from(t).to_string(), String::new()),
                Start::Point(x, y) => (
                    format!(
                        "{{ x = {}, y = {} }}",
                        written(x, Quantity::Length, units),
                        written(y, Quantity::Length, units)
                    ),
                    length.to_string(),
                ),
                Start::Omega(w) => (
                    format!("{{ omega = {} }}", written(w, Quantity::YawRate, units)),
                    label(Quantity::YawRate, units),
                ),
                Start::Raw("edr") => {
                    let speed = written(13.0, Quantity::Speed, units);
                    let sigma = written(0.7, Quantity::Speed, units);
                    (
                        format!("[ {{ speed = {speed}, time = 0.5, deceleration = 0.0, sigma = {sigma} }} ]"),
                        label(Quantity::Speed, units),
                    )
                }
                Start::Raw(raw) => (raw.to_string(), String::new()),
            };
            let note = match (unit.is_empty(), comment.is_empty()) {
                (true, true) => String::new(),
                (false, true) => format!("  # {unit}"),
                (true, false) => format!("  # {comment}"),
                (false, false) => format!("  # {unit}: {comment}"),
            };
            out.push_str(&format!("{key} = {value}{note}\n"));
        }
        out
    }
}

/// The section named `name` of [`SECTIONS`].
pub fn section(name: &str) -> Option<&'static Section> {
    SECTIONS.iter().find(|s| s.table == name)
}

/// The sections of [`SECTIONS`] the case text does not write yet.
///
/// # Errors
/// Text that is not TOML.
pub fn missing(file: &str, text: &str) -> Result<Vec<&'static Section>> {
    let edit = CaseEdit::new(file, text)?;
    Ok(SECTIONS.iter().filter(|s| !edit.has(s.table)).collect())
}

/// The case text with the section `name` appended (after a blank line), written in the file's
/// units; every other byte kept.
///
/// # Errors
/// Text that is not TOML, a section the file already writes, or a name that is not one of
/// [`SECTIONS`].
pub fn with_section(file: &str, text: &str, name: &str) -> Result<String> {
    let edit = CaseEdit::new(file, text)?;
    let Some(s) = section(name) else {
        let names: Vec<&str> = SECTIONS.iter().map(|s| s.table).collect();
        return Err(InputError::new(
            file,
            format!(
                "[{name}]: not a section that can be added ({})",
                names.join(", ")
            ),
        ));
    };
    if edit.has(name) {
        return Err(InputError::new(
            file,
            format!("[{name}] is written already"),
        ));
    }
    let mut out = text.to_string();
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    if !out.is_empty() && !out.ends_with("\n\n") {
        out.push('\n');
    }
    out.push_str(&s.text(&edit.units()?));
    CaseEdit::new(file, &out)?;
    Ok(out)
}

/// The case text without the section `name` (a table `vehicle2`, `scene.vehicle1`, or one
/// entry of an array of tables, `observations.0`, `runout.zones.1`); every other byte kept.
/// The top of the file and `[units]` are not removed: every number is written in them.
///
/// # Errors
/// Text that is not TOML, a section the file does not write, or the top or `[units]`.
pub fn without_section(file: &str, text: &str, name: &str) -> Result<String> {
    if name.is_empty() || name == "units" {
        return Err(InputError::new(
            file,
            format!(
                "[{name}]: the top of the file and [units] stay (every value is written in their \
                 units and frame)"
            ),
        ));
    }
    let mut edit = CaseEdit::new(file, text)?;
    if !edit.remove(name) {
        return Err(InputError::new(
            file,
            format!("[{name}]: the file writes no such section"),
        ));
    }
    Ok(edit.text())
}

/// A new case's text: its title, its frame and its units, ready for sections.
pub fn new_case(title: &str, convention: Convention, units: &UnitsSection) -> String {
    let frame = match convention {
        Convention::Sae => "sae",
        _ => "natural",
    };
    let about = match convention {
        Convention::Sae => "SAE frame: x north, y east, headings clockwise",
        _ => "natural frame: x east, y north, headings counter-clockwise",
    };
    format!(
        "# {about}.\ntitle = {}\nconvention = \"{frame}\"\n\n[units]\nspeed = \"{}\"\nlength = \"{}\"\nmass = \"{}\"\nyaw_inertia = \"{}\"\nyaw_rate = \"{}\"\n",
        toml_edit::Value::from(crate::parse::printable(title)),
        unit_label(units.speed),
        units.length.label(),
        unit_label(units.mass),
        unit_label(units.yaw_inertia),
        unit_label(units.yaw_rate),
    )
}
