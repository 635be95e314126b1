//! Plausibility warnings of a case: values that are valid but look like a mistake of units,
//! form or geometry. Each names the field and where it is written; none is an error, and none
//! fires on the example cases (tested).

use crate::case::Case;
use crate::sections::AT_REST;
use pim_core::{impact_point_cartesian, wrap_degrees, VehicleId};

/// Speeds above this (m/s, 252 km/h) draw a plausibility warning.
pub const PLAUSIBLE_SPEED: f64 = 70.0;

/// Masses above this (kg, a loaded heavy truck) draw a plausibility warning: a rail vehicle or a
/// heavy-haul combination is accepted up to [`crate::ranges::MASS`], and said.
pub const PLAUSIBLE_MASS: f64 = 60_000.0;

/// Masses from this (kg) up look like a fixed obstacle modelled as a vehicle (IMPC
/// spreadsheets and pycrash give a barrier 1e6 lb, 453.6 t): the warning points to
/// `barrier = true`, which models a rigid barrier exactly.
pub const BARRIER_LIKE_MASS: f64 = 200_000.0;

/// The range of yaw inertia over mass (m^2) of road vehicles; outside it, a warning.
pub const INERTIA_PER_MASS: (f64, f64) = (1.0, 3.5);

/// How far outside the vehicle's outline an impact centre may lie before it draws a warning, m
/// (the deepest crush of a road vehicle is about this).
pub const CRUSH_MARGIN: f64 = 1.0;

/// Yaw rates above this (rad/s, about 460 deg/s) in a file read in rad/s look like degrees
/// per second. Real separation yaw rates reach 5.2 rad/s in RICSAC test 10 and about 6 rad/s
/// after offset impacts at highway speed; a value in deg/s read as rad/s is mostly beyond the
/// 15 rad/s of the range check (refused with the same hint), so this warns on the 8-15 rad/s
/// between.
pub const PLAUSIBLE_YAW_RATE: f64 = 8.0;

/// A sideslip above this (degrees) with no yaw rate draws a warning.
pub const PLAUSIBLE_SIDESLIP: f64 = 30.0;

/// Reading an angle written in radians as degrees matters when the two readings differ by more
/// than this (degrees): below it (a heading of 0.04, 2.3 deg apart) the warning would only be
/// noise about a vehicle nearly along an axis.
pub const RADIANS_MISREAD: f64 = 5.0;

/// An angle in degrees that looks like radians: not zero, within 2 pi, not a whole number, and
/// large enough that its radian reading lies more than [`RADIANS_MISREAD`] from it
/// (`|a| (180/pi - 1) > 5`, that is `|a| > 0.089`).
fn looks_like_radians(a: f64) -> bool {
    a != 0.0
        && a.abs() <= std::f64::consts::TAU
        && a.fract() != 0.0
        && (a.to_degrees() - a).abs() > RADIANS_MISREAD
}

impl Case {
    /// Plausibility warnings (not errors): headings that look like radians (other angles when
    /// every non-zero angle of the case does), yaw inertias far from mass x (1.0 .. 3.5) m^2, impact centres outside
    /// the outline (the case's, or typical for the mass) by more than [`CRUSH_MARGIN`], speeds
    /// above [`PLAUSIBLE_SPEED`], yaw rates above [`PLAUSIBLE_YAW_RATE`] (degrees per second
    /// meant?), and a contact velocity more than [`PLAUSIBLE_SIDESLIP`] from the vehicle's
    /// heading with no yaw rate.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = self.tyre_warnings();
        out.extend(self.radians_warnings());
        out.extend(self.vehicle_warnings());
        out.extend(self.side_warnings());
        out.extend(self.state_warnings());
        out.extend(self.overlap_warning());
        out
    }

    /// Angles that look like radians in a case read in degrees.
    fn radians_warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let c = &self.content;
        let vehicles = [("vehicle1", &c.vehicle1), ("vehicle2", &c.vehicle2)];
        // Radians: when every non-zero angle of the case looks like radians (a single small
        // angle in degrees, such as a crush angle of 3.4, is common).
        let mut angles: Vec<(String, f64)> = Vec::new();
        for (name, v) in vehicles {
            if v.barrier {
                continue;
            }
            angles.push((format!("{name}.heading"), v.heading));
            if v.impact_point.is_none() {
                if let Some(phi) = v.phi {
                    angles.push((format!("{name}.phi"), phi));
                }
            }
        }
        angles.push(("impact.crush_angle".into(), c.impact.crush_angle));
        // Warned only when every non-zero angle of its kind looks like radians: a single small
        // angle in degrees is common (a heading of -4.1, a vehicle a few degrees off an axis,
        // beside one at 90; a crush angle of 3.4), while a case written in radians has no
        // heading above 2 pi. The value is shown as the file writes it (an SAE case's angles
        // are stored mirrored).
        // Headings are judged among the headings (an impact centre angle or a crush angle of a
        // few degrees is common beside headings in radians), every other angle among all.
        let nonzero: Vec<&(String, f64)> = angles.iter().filter(|(_, a)| *a != 0.0).collect();
        let radians = |heading_only: bool| {
            let judged: Vec<_> = nonzero
                .iter()
                .filter(|(p, _)| !heading_only || p.ends_with(".heading"))
                .collect();
            !judged.is_empty() && judged.iter().all(|(_, a)| looks_like_radians(*a))
        };
        let (headings, all) = (radians(true), radians(false));
        let written = if self.written == pim_core::Convention::Sae {
            -1.0
        } else {
            1.0
        };
        for (path, a) in nonzero
            .into_iter()
            .filter(|(p, _)| all || (headings && p.ends_with(".heading")))
        {
            let a = written * a;
            out.push(format!(
                "{}: {a} is read as degrees; it looks like radians ({:.1} deg)",
                self.at(path),
                a.to_degrees()
            ));
        }
        out
    }

    /// Masses beyond road vehicles, yaw inertias out of proportion, impact centres outside the
    /// outline.
    fn vehicle_warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let c = &self.content;
        for (name, v) in [("vehicle1", &c.vehicle1), ("vehicle2", &c.vehicle2)] {
            if v.barrier {
                continue;
            }
            if v.mass > PLAUSIBLE_MASS {
                let mut w = format!(
                    "{}: {:.0} kg is heavier than any road vehicle (a loaded heavy truck is at \
                     most about {:.0} t): a rail vehicle or a heavy-haul combination?",
                    self.at(&format!("{name}.mass")),
                    v.mass,
                    PLAUSIBLE_MASS / 1000.0
                );
                if v.mass >= BARRIER_LIKE_MASS {
                    w.push_str(
                        " If it stands for a wall or a fixed obstacle (IMPC spreadsheets and \
                         pycrash give a barrier 1e6 lb), write [vehicle2] barrier = true: it \
                         models a rigid barrier exactly",
                    );
                }
                out.push(w);
            }
            let k = v.yaw_inertia / v.mass;
            if !(INERTIA_PER_MASS.0..=INERTIA_PER_MASS.1).contains(&k) {
                out.push(format!(
                    "{}: yaw_inertia / mass = {k:.2} m^2, outside the {} .. {} m^2 of road \
                     vehicles: check the units of mass and yaw_inertia",
                    self.at(&format!("{name}.yaw_inertia")),
                    INERTIA_PER_MASS.0,
                    INERTIA_PER_MASS.1
                ));
            }
            // The impact centre against the outline (in SI, the vehicle's own frame).
            let (x, y) = impact_point_cartesian(v.d(), v.phi());
            let (o, _) = v.outline();
            let (front, rear, width) = (o.cg_to_front, o.cg_to_rear, o.width);
            let length = front + rear;
            let outside = (x - front).max(-rear - x).max(y.abs() - width / 2.0);
            if outside > CRUSH_MARGIN {
                let field = if v.impact_point.is_some() {
                    "impact_point"
                } else {
                    "d"
                };
                out.push(format!(
                    "{}: the impact centre ({x:.2}, {y:.2}) m from the CG lies {outside:.2} m \
                     outside the vehicle ({length:.2} x {width:.2} m, front {front:.2} m ahead \
                     of the CG{}): check the impact point and [units] length",
                    self.at(&format!("{name}.{field}")),
                    if v.length.is_some() {
                        ""
                    } else {
                        "; typical for its mass"
                    }
                ));
            }
        }
        out
    }

    /// The side of the crush surface: a choice, not a fact, when both CGs lie on one side.
    fn side_warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let Ok(impact) = self.impact() {
            if impact.side_basis() == pim_core::SideBasis::Velocities {
                let side = if impact.side() >= 0.0 { "+n" } else { "-n" };
                let other = if side == "+n" { "-n" } else { "+n" };
                let [g1, g2] = impact.cg_positions();
                // Both on one side is also what a heading written in the other form gives.
                let conv = self.content.convention.other();
                let hint = match pim_core::Impact::new(self.collision(conv)) {
                    Ok(alt) if alt.side_basis() == pim_core::SideBasis::Geometry => format!(
                        " With convention = \"{}\" ({}) they would lie on opposite sides: check \
                         which form the headings were written in.",
                        conv.name(),
                        if conv == pim_core::Convention::Brach {
                            "vehicle 1's heading is its tail, as in Brach's papers"
                        } else {
                            "vehicle 1's heading is where its nose points"
                        }
                    ),
                    _ => String::new(),
                };
                out.push(format!(
                    "{}: both centres of gravity lie on one side of the crush surface (vehicle 1's \
                     CG at ({:.2}, {:.2}) m, vehicle 2's at ({:.2}, {:.2}) m from the impact \
                     centre, natural axes): which vehicle is on which side is read from the \
                     estimated contact velocities ([estimates.initial]), which approach at the \
                     impact centre only with vehicle 1 on the {side} side.{hint} If the vehicles \
                     met the other way, state it: [impact] vehicle1_side = \"{other}\"",
                    self.at("impact.crush_angle"),
                    g1[0] + 0.0,
                    g1[1] + 0.0,
                    g2[0] + 0.0,
                    g2[1] + 0.0,
                ));
            }
            if impact.side_basis() == pim_core::SideBasis::Mobility && !self.is_barrier() {
                let [h1, h2] = impact.cg_heights();
                let side = |x: f64| if x >= 0.0 { "+n" } else { "-n" };
                let reading = side(impact.side());
                let other = if reading == "+n" { "-n" } else { "+n" };
                out.push(format!(
                    "{}: both centres of gravity lie on the {} side of the crush surface \
                     (vehicle 1 {:.3} {len}, vehicle 2 {:.3} {len} above the plane through the \
                     impact centre, along n at crush_angle): which vehicle is on which side is read \
                     from the heights weighted by mobility, sgn(m2 h1 - m1 h2), as vehicle 1 \
                     on the {reading} side. If the vehicles met the other way, state it: \
                     [impact] vehicle1_side = \"{other}\"",
                    self.at("impact.crush_angle"),
                    side(if h1.abs() >= h2.abs() { h1 } else { h2 }),
                    h1 / self.written_units.length.to_si(),
                    h2 / self.written_units.length.to_si(),
                    len = self.written_units.length.label(),
                ));
            }
        }
        out
    }

    /// Speeds, yaw rates and sideslip of the states and estimates.
    fn state_warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let c = &self.content;
        let vehicles = [&c.vehicle1, &c.vehicle2];
        // States and estimates: speeds, yaw rates, sideslip. Each entry: the path of the
        // vehicle's state, vx, vy, omega, the vehicle, and whether it is the contact state.
        type State = (String, f64, f64, Option<f64>, usize, bool);
        let mut states: Vec<State> = Vec::new();
        for (sec, st, contact) in [("initial", &c.initial, true), ("final", &c.final_, false)] {
            if let Some(st) = st {
                let vehicle2 = st.vehicle2.unwrap_or(AT_REST);
                for (k, v) in [st.vehicle1, vehicle2].into_iter().enumerate() {
                    let path = format!("{sec}.vehicle{}", k + 1);
                    states.push((path, v.vx, v.vy, Some(v.omega), k, contact));
                }
            }
        }
        if let Some(e) = &c.estimates {
            for (sec, st, contact) in [
                ("estimates.initial", &e.initial, true),
                ("estimates.final", &e.final_, false),
            ] {
                if let Some(st) = st {
                    for (k, v) in [st.vehicle1, st.vehicle2].into_iter().enumerate() {
                        if let (Some(vx), Some(vy)) = (v.vx, v.vy) {
                            let path = format!("{sec}.vehicle{}", k + 1);
                            states.push((path, vx, vy, v.omega, k, contact));
                        }
                    }
                }
            }
        }
        for (path, vx, vy, omega, k, at_contact) in states {
            let speed = vx.hypot(vy);
            if speed > PLAUSIBLE_SPEED {
                out.push(format!(
                    "{}: speed {speed:.1} m/s ({:.0} km/h) is above {PLAUSIBLE_SPEED} m/s: check \
                     [units] speed",
                    self.at(&format!("{path}.vx")),
                    speed * 3.6
                ));
            }
            // The slip this catches is a number in degrees per second in a file read in rad/s;
            // a file that says `yaw_rate = "deg/s"` cannot make it (a violent spin is then
            // simply a fast one; the range check refuses what no vehicle does).
            let in_degrees =
                self.written_units.yaw_rate == crate::units::YawRateUnit::DegreesPerSecond;
            if let Some(w) = omega.filter(|w| w.abs() > PLAUSIBLE_YAW_RATE && !in_degrees) {
                out.push(format!(
                    "{}: a yaw rate of {w:.2} rad/s ({:.0} deg/s) is above {PLAUSIBLE_YAW_RATE} \
                     rad/s: degrees per second meant? check [units] yaw_rate",
                    self.at(&format!("{path}.omega")),
                    w.to_degrees()
                ));
            }
            // Sideslip at contact, for a vehicle that is not turning.
            let v = vehicles[k];
            if at_contact && !v.barrier && omega == Some(0.0) && speed > 1.0 {
                let nose = c.convention.nose(VehicleId::from_index(k), v.heading);
                let slip = wrap_degrees(vy.atan2(vx).to_degrees() - nose).abs();
                if slip > PLAUSIBLE_SIDESLIP && slip < 180.0 - PLAUSIBLE_SIDESLIP {
                    out.push(format!(
                        "{}: the vehicle moves {slip:.0} deg off its heading with no yaw rate: \
                         check the heading, the velocity components and [convention]",
                        self.at(&format!("{path}.vx"))
                    ));
                }
            }
        }
        out
    }

    /// Outlines at contact that overlap beyond any crush: the two bodies (both given by
    /// `length`, `width` and `cg_to_front`, placed by the case's geometry) interpenetrate by more than
    /// [`PLAUSIBLE_ENGAGEMENT`] along the direction that separates them soonest. At contact the
    /// undeformed outlines overlap by about the crush to come; far more says a CG position, a
    /// heading or the impact point is off (a hand-computed position, a sign of the frame).
    fn overlap_warning(&self) -> Option<String> {
        let c = &self.content;
        if self.is_barrier() {
            return None;
        }
        let impact = self.impact().ok()?;
        let cgs = impact.cg_positions();
        let mut bodies = Vec::new();
        for (k, (v, id)) in [
            (&c.vehicle1, pim_core::VehicleId::One),
            (&c.vehicle2, pim_core::VehicleId::Two),
        ]
        .into_iter()
        .enumerate()
        {
            // Only outlines the case gives whole: a default CG-to-front would misplace them.
            let (length, width, front) = (v.length?, v.width?, v.cg_to_front?);
            let (s, co) = impact.nose_heading(id).to_radians().sin_cos();
            let corners: Vec<[f64; 2]> = [
                (front, 0.5 * width),
                (front, -0.5 * width),
                (front - length, -0.5 * width),
                (front - length, 0.5 * width),
            ]
            .iter()
            .map(|(x, y)| [cgs[k][0] + co * x - s * y, cgs[k][1] + s * x + co * y])
            .collect();
            bodies.push(corners);
        }
        let depth = penetration(&bodies[0], &bodies[1]);
        let u = self.written_units.length.to_si();
        let len = self.written_units.length.label();
        (depth > PLAUSIBLE_ENGAGEMENT).then(|| {
            format!(
                "{}: the outlines at contact overlap by {:.2} {len} (vehicle1.position, \
                 heading, impact_point and vehicle2's as given): more than {:.2} {len}, deeper \
                 than the crush of car-to-car crashes; check the CG positions, the headings \
                 and the frame",
                self.at("vehicle2.position"),
                depth / u,
                PLAUSIBLE_ENGAGEMENT / u
            )
        })
    }
}

/// The deepest the undeformed outlines of two cars can plausibly overlap at contact, m: the
/// combined crush of both, about a metre in severe car-to-car crashes, with margin.
pub const PLAUSIBLE_ENGAGEMENT: f64 = 1.2;

/// How deep two convex polygons interpenetrate: the least overlap of their projections over
/// the normals of their edges (0 when a normal separates them).
fn penetration(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let mut least = f64::INFINITY;
    for poly in [a, b] {
        for i in 0..poly.len() {
            let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
            let n = [q[1] - p[1], p[0] - q[0]];
            let norm = n[0].hypot(n[1]);
            if norm == 0.0 {
                continue;
            }
            let proj = |pts: &[[f64; 2]]| {
                pts.iter()
                    .map(|x| (x[0] * n[0] + x[1] * n[1]) / norm)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                        (lo.min(v), hi.max(v))
                    })
            };
            let (a0, a1) = proj(a);
            let (b0, b1) = proj(b);
            let overlap = a1.min(b1) - a0.max(b0);
            if overlap <= 0.0 {
                return 0.0;
            }
            least = least.min(overlap);
        }
    }
    if least.is_finite() {
        least
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::penetration;

    #[test]
    fn penetration_of_rectangles() {
        let sq = |x: f64, y: f64| vec![[x, y], [x + 2.0, y], [x + 2.0, y + 1.0], [x, y + 1.0]];
        assert!((penetration(&sq(0.0, 0.0), &sq(1.5, 0.0)) - 0.5).abs() < 1e-12);
        assert!(penetration(&sq(0.0, 0.0), &sq(2.5, 0.0)).abs() < 1e-15);
        assert!((penetration(&sq(0.0, 0.0), &sq(0.0, 0.7)) - 0.3).abs() < 1e-12);
    }
}
