//! A rest given as it is measured: the contact points of two or more tyres
//! (`[scene.vehicleN] rest_tyres`), each with its standard deviation.
//!
//! The chi-square of the points against a vehicle resting at CG `c` with heading `theta` is
//! `sum_j w_j |c + R(theta) a_j - q_j|^2`, with `a_j` the tyre's place on the vehicle (ahead of
//! the CG and to its left: the run-out section's wheelbase, CG to front axle and track), `q_j`
//! the point measured and `w_j = 1 / sigma_j^2`. Written about the weighted centroids
//! (`a' = a - a_bar`, `q' = q - q_bar`, `sum w a' = 0`), the position of the vehicle's point
//! `a_bar` and the heading separate:
//!
//! `chi2 = W |p - q_bar|^2 + I (theta - theta_hat)^2 + misfit + O(dtheta^3)`,
//!
//! with `p = c + R(theta) a_bar`, `W = sum w`, `I = sum w |a'|^2`, `theta_hat` the weighted
//! Procrustes rotation `atan2(sum w a' x q', sum w a' . q')` and `misfit` the points' own
//! disagreement with the vehicle's geometry (their measured spacing against its wheelbase and
//! track), which no rest of the vehicle can change. So the points are the rest of the point
//! `a_bar` at `q_bar` with a standard deviation `1 / sqrt(W)` per coordinate and the heading
//! `theta_hat` with `1 / sqrt(I)` ([`pim_runout::Rest::point`]): the run-out is measured
//! against the tyres, no CG is computed by hand, and the misfit is said as a warning.

use crate::case::Case;
use crate::error::Result;
use crate::scene_sections::SceneVehicleSection;
use pim_runout::{Chassis, Rest};

/// The tyres' rest: the rest it stands for, and the points' disagreement with the geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct TyreRest {
    /// The rest of the tyres' weighted centroid on the vehicle, with the heading.
    pub rest: Rest,
    /// The chi-square no rest of the vehicle removes.
    pub misfit: f64,
    /// Its degrees of freedom: two per point less three.
    pub dof: usize,
}

/// The rest the tyre points `(wheel, [x, y], sigma)` give (natural frame, m) for a vehicle
/// whose wheel `w` lies at `position(w)` (its frame).
///
/// # Errors
/// Fewer than two distinct wheels.
pub fn fit(
    points: &[(usize, [f64; 2], f64)],
    position: impl Fn(usize) -> [f64; 2],
) -> std::result::Result<TyreRest, String> {
    let mut wheels: Vec<usize> = points.iter().map(|p| p.0).collect();
    wheels.sort_unstable();
    wheels.dedup();
    if wheels.len() != points.len() || points.len() < 2 {
        return Err(format!(
            "give two or more different tyres (found {} points of {} tyres): one tyre does not \
             give the heading",
            points.len(),
            wheels.len()
        ));
    }
    let w: Vec<f64> = points.iter().map(|p| p.2.powi(-2)).collect();
    let total: f64 = w.iter().sum();
    let a: Vec<[f64; 2]> = points.iter().map(|p| position(p.0)).collect();
    let q: Vec<[f64; 2]> = points.iter().map(|p| p.1).collect();
    let mean = |v: &[[f64; 2]]| {
        let mut m = [0.0, 0.0];
        for (x, wi) in v.iter().zip(&w) {
            m[0] += wi * x[0] / total;
            m[1] += wi * x[1] / total;
        }
        m
    };
    let (ab, qb) = (mean(&a), mean(&q));
    let (mut dot, mut cross, mut inertia) = (0.0, 0.0, 0.0);
    for ((x, y), wi) in a.iter().zip(&q).zip(&w) {
        let (u, v) = ([x[0] - ab[0], x[1] - ab[1]], [y[0] - qb[0], y[1] - qb[1]]);
        dot += wi * (u[0] * v[0] + u[1] * v[1]);
        cross += wi * (u[0] * v[1] - u[1] * v[0]);
        inertia += wi * (u[0] * u[0] + u[1] * u[1]);
    }
    let heading = cross.atan2(dot);
    let (s, c) = heading.sin_cos();
    let misfit = a
        .iter()
        .zip(&q)
        .zip(&w)
        .map(|((x, y), wi)| {
            let (u, v) = ([x[0] - ab[0], x[1] - ab[1]], [y[0] - qb[0], y[1] - qb[1]]);
            wi * ((c * u[0] - s * u[1] - v[0]).powi(2) + (s * u[0] + c * u[1] - v[1]).powi(2))
        })
        .sum();
    let sd = total.sqrt().recip();
    Ok(TyreRest {
        rest: Rest {
            x: qb[0],
            y: qb[1],
            heading: Some(heading),
            sigma_xy: [sd, sd],
            sigma_heading: inertia.sqrt().recip(),
            point: ab,
        },
        misfit,
        dof: 2 * points.len() - 3,
    })
}

/// Point `i` of a vehicle measured at rest, in its frame: tyre `i` (0 to 3), or corner `i - 4`
/// of its outline `corners`.
fn point_on(chassis: &Chassis, corners: Option<[[f64; 2]; 4]>, i: usize) -> [f64; 2] {
    match (i, corners) {
        (0..=3, _) => chassis.wheel_position(i),
        (_, Some(c)) => c[(i - 4).min(3)],
        _ => [0.0, 0.0],
    }
}

/// The name of point `i` (a tyre, or a corner of the outline).
fn point_name(i: usize) -> String {
    match i {
        0..=3 => pim_runout::WHEEL_NAMES[i].to_string(),
        _ => format!("{} corner", pim_runout::WHEEL_NAMES[(i - 4).min(3)]),
    }
}

impl Case {
    /// The tyre points of `[scene.name] rest_tyres`, in SI and the natural frame:
    /// `(wheel, [x, y], sigma)`, each checked.
    pub(crate) fn tyre_points(
        &self,
        name: &str,
        s: &SceneVehicleSection,
        (length, flip): (f64, f64),
    ) -> Result<Vec<(usize, [f64; 2], f64)>> {
        let reach = pim_runout::inverse::MAX_SCENE_DISTANCE / length;
        s.rest_tyres
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let at = |f: &str| format!("scene.{name}.rest_tyres[{i}].{f}");
                let wheel = match (t.wheel, t.corner) {
                    (Some(w), None) => w.wheel(),
                    (None, Some(c)) => c.wheel().map(|c| 4 + c),
                    _ => {
                        return Err(self.error_at(
                            &at("wheel"),
                            "name the tyre (wheel = \"front_left\", ...) or the outline's \
                             corner (corner = \"front_left\", ...) measured, one of the two",
                        ))
                    }
                };
                let Some(wheel) = wheel else {
                    let field = if t.wheel.is_some() { "wheel" } else { "corner" };
                    return Err(self.error_at(
                        &at(field),
                        format!("a {field}: front_left, front_right, rear_left or rear_right"),
                    ));
                };
                for (f, v) in [("x", t.x), ("y", t.y)] {
                    if !(v.is_finite() && v.abs() <= reach) {
                        return Err(self.error_at(
                            &at(f),
                            format!("{v}: must be a number from -{reach} to {reach}"),
                        ));
                    }
                }
                if !(t.sigma.is_finite() && t.sigma > 0.0 && t.sigma <= reach) {
                    return Err(self.error_at(
                        &at("sigma"),
                        format!("{}: a standard deviation must be above 0", t.sigma),
                    ));
                }
                Ok((wheel, [t.x * length, flip * t.y * length], t.sigma * length))
            })
            .collect()
    }

    /// The marks `[scene.name] traces` gives: each point of a trace a mark of its wheel (or
    /// the CG), in SI and the natural frame.
    ///
    /// # Errors
    /// A located error: fewer than two points, a point out of range, a sigma not above 0.
    pub(crate) fn trace_marks(
        &self,
        name: &str,
        s: &SceneVehicleSection,
        chassis: &Chassis,
        (length, flip): (f64, f64),
    ) -> Result<Vec<pim_runout::Mark>> {
        let reach = pim_runout::inverse::MAX_SCENE_DISTANCE / length;
        let mut out = Vec::new();
        for (i, t) in s.traces.iter().enumerate() {
            let at = |f: &str| format!("scene.{name}.traces[{i}].{f}");
            if t.points.len() < 2 {
                return Err(self.error_at(
                    &at("points"),
                    "a trace is two or more points [x, y] along the mark (one point is a mark:                      marks = [ { x, y, sigma } ])",
                ));
            }
            if !(t.sigma.is_finite() && t.sigma > 0.0 && t.sigma <= reach) {
                return Err(self.error_at(
                    &at("sigma"),
                    format!("{}: a standard deviation must be above 0", t.sigma),
                ));
            }
            if let Some(p) = t
                .points
                .iter()
                .find(|p| !p.iter().all(|v| v.is_finite() && v.abs() <= reach))
            {
                return Err(self.error_at(
                    &at("points"),
                    format!("{p:?}: each coordinate a number from -{reach} to {reach}"),
                ));
            }
            let point = t
                .wheel
                .and_then(crate::scene_sections::MarkPoint::wheel)
                .map_or([0.0, 0.0], |w| chassis.wheel_position(w));
            out.extend(t.points.iter().map(|p| pim_runout::Mark {
                x: p[0] * length,
                y: flip * p[1] * length,
                sigma: t.sigma * length,
                heading: None,
                point,
            }));
        }
        Ok(out)
    }

    /// The rest `[scene.name] rest_tyres` gives for a vehicle with `chassis` (none without
    /// tyre points).
    ///
    /// # Errors
    /// A located error: the rest given twice, a point out of range, fewer than two tyres.
    pub(crate) fn rest_of_tyres(
        &self,
        name: &str,
        s: &SceneVehicleSection,
        chassis: &Chassis,
        scale: (f64, f64),
    ) -> Result<Option<TyreRest>> {
        if s.rest_tyres.is_empty() {
            return Ok(None);
        }
        if s.rest.is_some() || s.rest_sigma.is_some() {
            return Err(self.error_at(
                &format!("scene.{name}.rest_tyres"),
                "the rest is given twice: give the tyres measured (rest_tyres) or the CG's rest \
                 and its sigmas (rest, rest_sigma), not both",
            ));
        }
        let points = self.tyre_points(name, s, scale)?;
        let corners = self.corners_of(name)?;
        if points.iter().any(|p| p.0 >= 4) && corners.is_none() {
            return Err(self.error_at(
                &format!("scene.{name}.rest_tyres"),
                format!(
                    "a corner of the outline needs the vehicle's outline: [{name}] length, \
                     width and cg_to_front"
                ),
            ));
        }
        fit(&points, |w| point_on(chassis, corners, w))
            .map(Some)
            .map_err(|why| self.error_at(&format!("scene.{name}.rest_tyres"), why))
    }

    /// The corners of vehicle `name`'s outline in its frame (front left, front right, rear
    /// left, rear right; m ahead of the CG and to its left), where `[name]` gives length, width
    /// and cg_to_front.
    ///
    /// # Errors
    /// None yet: an outline the case does not give is `None`.
    fn corners_of(&self, name: &str) -> Result<Option<[[f64; 2]; 4]>> {
        let k = usize::from(name.ends_with('2'));
        let v = self.content.vehicle(k);
        Ok(match (v.length, v.width, v.cg_to_front) {
            (Some(l), Some(w), Some(f)) => {
                let (r, h) = (f - l, 0.5 * w);
                Some([[f, h], [f, -h], [r, h], [r, -h]])
            }
            _ => None,
        })
    }

    /// A warning for each vehicle whose tyres measured at rest disagree with its geometry
    /// (their misfit's probability below 1 %): the spacings measured and the vehicle's.
    pub(crate) fn tyre_warnings(&self) -> Vec<String> {
        let Ok(inputs) = self.scene_inputs() else {
            return Vec::new();
        };
        let mut out = Vec::new();
        let (length, flip) = self.length_and_flip();
        for v in &inputs.vehicles {
            let name = format!("vehicle{}", v.id.index() + 1);
            let Some(s) = self.content.scene.as_ref().and_then(|sc| {
                if v.id.index() == 0 {
                    &sc.vehicle1
                } else {
                    &sc.vehicle2
                }
                .as_ref()
            }) else {
                continue;
            };
            let (Ok(points), Ok(Some(t))) = (
                self.tyre_points(&name, s, (length, flip)),
                self.rest_of_tyres(&name, s, &v.chassis, (length, flip)),
            ) else {
                continue;
            };
            let p = pim_fit::ChiSquare::p_value_of(t.dof as i64, t.misfit).unwrap_or(1.0);
            if p >= 0.01 {
                continue;
            }
            let unit = match self.written_units.length {
                crate::units::LengthUnit::Metre => "m",
                crate::units::LengthUnit::Foot => "ft",
            };
            let pairs: Vec<String> = points
                .windows(2)
                .map(|w| {
                    let corners = self.corners_of(&name).ok().flatten();
                    let (a, b) = (
                        point_on(&v.chassis, corners, w[0].0),
                        point_on(&v.chassis, corners, w[1].0),
                    );
                    let measured = (w[0].1[0] - w[1].1[0]).hypot(w[0].1[1] - w[1].1[1]);
                    let geometric = (a[0] - b[0]).hypot(a[1] - b[1]);
                    format!(
                        "{} to {} measured {:.2} {unit}, {:.2} {unit} by the vehicle's geometry",
                        point_name(w[0].0),
                        point_name(w[1].0),
                        measured / length,
                        geometric / length
                    )
                })
                .collect();
            out.push(format!(
                "{}: the tyres measured do not fit the vehicle's geometry (chi-square {:.1} with \
                 {} degree{} of freedom, p {:.1e}; {}): check the points, the wheelbase, the CG \
                 to front axle and the track",
                self.at(&format!("scene.{name}.rest_tyres")),
                t.misfit,
                t.dof,
                if t.dof == 1 { "" } else { "s" },
                p,
                pairs.join("; "),
            ));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::fit;

    /// Points of a vehicle resting at a known pose give that pose exactly, with the sigmas of
    /// the separated chi-square, and no misfit; points a spacing apart from the geometry give
    /// the misfit of that spacing.
    #[test]
    fn tyres_give_the_rest_they_measure() {
        let wheels = |w: usize| [[1.4, 0.8], [1.4, -0.8], [-1.3, 0.8], [-1.3, -0.8]][w];
        let (cx, cy, h) = (12.0, -3.0, 2.4f64);
        let (s, c) = h.sin_cos();
        let at = |w: usize| {
            let [a, b] = wheels(w);
            [cx + c * a - s * b, cy + s * a + c * b]
        };
        let t = fit(&[(0, at(0), 0.05), (2, at(2), 0.05)], wheels).unwrap();
        let (x, y) = t.rest.cg();
        assert!((x - cx).abs() < 1e-12 && (y - cy).abs() < 1e-12, "{x} {y}");
        assert!((t.rest.heading.unwrap() - h).abs() < 1e-12);
        assert!((t.rest.point[0] - 0.05).abs() < 1e-12 && (t.rest.point[1] - 0.8).abs() < 1e-12);
        // W = 2 / 0.05^2; I = 2 w (2.7 / 2)^2.
        assert!((t.rest.sigma_xy[0] - 0.05 / 2f64.sqrt()).abs() < 1e-15);
        assert!((t.rest.sigma_heading - 0.05 / (2f64.sqrt() * 1.35)).abs() < 1e-15);
        assert!(t.misfit < 1e-20 && t.dof == 1);
        // The rear tyre measured 0.1 m farther back: a misfit of (0.1 / 0.05)^2 / 2.
        let mut far = at(2);
        far[0] -= 0.1 * c;
        far[1] -= 0.1 * s;
        let t = fit(&[(0, at(0), 0.05), (2, far, 0.05)], wheels).unwrap();
        assert!((t.misfit - 2.0).abs() < 1e-9, "{}", t.misfit);
        // One tyre, or a tyre twice, gives no heading.
        assert!(fit(&[(0, at(0), 0.05)], wheels).is_err());
        assert!(fit(&[(0, at(0), 0.05), (0, at(0), 0.05)], wheels).is_err());
    }
}
