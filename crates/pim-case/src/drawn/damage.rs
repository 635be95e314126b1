//! The damage's inputs of an uncertainty study: each stiffness coefficient, damage width and
//! crush depth with a standard deviation is drawn (in the case file's own units).

use super::input::Input;
use crate::case::Case;
use crate::spread::Spread;

/// The drawn inputs of a case's `[damage]` (none without one).
pub(super) fn inputs(case: &Case) -> Vec<Input> {
    let mut out: Vec<Input> = Vec::new();
    let Some(d) = &case.content.damage else {
        return out;
    };
    {
        for (k, name) in ["vehicle1", "vehicle2"].into_iter().enumerate() {
            let Some(v) = (if k == 0 { &d.vehicle1 } else { &d.vehicle2 }) else {
                continue;
            };
            // Crush and stiffness are drawn in the file's own units, kept where they can be:
            // A and depths at least 0, B and the width above 0.
            type Set = fn(&mut crate::sections::DamageVehicleSection, f64, f64);
            let fields: [(&str, Option<f64>, Option<f64>, Set); 3] = [
                ("a", v.a, v.a_sigma, |s, x, _| s.a = Some(x.max(0.0))),
                ("b", v.b, v.b_sigma, |s, x, n| s.b = Some(x.max(1e-6 * n))),
                ("width", v.width, v.width_sigma, |s, x, n| {
                    s.width = Some(x.max(1e-6 * n))
                }),
            ];
            for (field, nominal, sd, set) in fields {
                if let (Some(nominal), Some(sd)) = (nominal, sd) {
                    if sd > 0.0 {
                        out.push(Input {
                            name: format!("damage.{name}.{field}"),
                            spread: Spread::Normal(sd),
                            nominal,
                            apply: Box::new(move |case: &mut Case, x| {
                                if let Some(s) = damage_vehicle_mut(case, k) {
                                    set(s, x, nominal)
                                }
                            }),
                        });
                    }
                }
            }
            if let (Some(depths), Some(sd)) = (&v.depths, v.depth_sigma) {
                if sd > 0.0 {
                    for (i, &nominal) in depths.iter().enumerate() {
                        out.push(Input {
                            name: format!("damage.{name}.C{}", i + 1),
                            spread: Spread::Normal(sd),
                            nominal,
                            apply: Box::new(move |case: &mut Case, x| {
                                if let Some(c) = damage_vehicle_mut(case, k)
                                    .and_then(|s| s.depths.as_mut())
                                    .and_then(|d| d.get_mut(i))
                                {
                                    *c = x.max(0.0);
                                }
                            }),
                        });
                    }
                }
            }
        }
    }
    out
}

fn damage_vehicle_mut(
    case: &mut Case,
    k: usize,
) -> Option<&mut crate::sections::DamageVehicleSection> {
    let d = case.content.damage.as_mut()?;
    if k == 0 {
        d.vehicle1.as_mut()
    } else {
        d.vehicle2.as_mut()
    }
}
