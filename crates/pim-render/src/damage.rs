//! The damage in tables: the crush energies beside PIM's energy loss, CRASH3's delta-V beside
//! PIM's, and the fit with the crush energy as evidence.

use pim_case::units::UnitSystem;
use pim_studies::damage_assess::Assessment;
use pim_studies::damage_fit::FitDamage;
use std::fmt::Write;

fn kj(x: f64) -> String {
    format!("{:.1}", x / 1000.0)
}

/// The crush of an assessment, as lines of a table: per vehicle its profile, energy, PDOF
/// factor, barrier-equivalent speed and CRASH3's delta-V against PIM's, then the totals and
/// the difference, the relation in words and the warnings.
pub fn damage_lines(a: &Assessment, u: UnitSystem) -> String {
    let mut s = String::new();
    let sp = u.speed_label();
    let (depth_label, depth) = match u {
        UnitSystem::Us => ("in", 1.0 / 0.0254),
        _ => ("cm", 100.0),
    };
    let _ = writeln!(
        s,
        "damage (CRASH3 linear stiffness, crush linear between the measured points)"
    );
    let _ = writeln!(
        s,
        "  {:<10} {:<6} {:>8} {:<30} {:>8} {:>7} {:>6} {:>8} {:>7} {:>6} {:>6} {:>8} {:>8}",
        "",
        "face",
        format!("width {depth_label}"),
        format!("crush depths, {depth_label}"),
        "E kJ",
        "PDOF",
        "factor",
        "E' kJ",
        format!("BEV {sp}"),
        "h m",
        "gamma",
        format!("CRASH3 dV"),
        format!("PIM dV")
    );
    for (k, v) in a.vehicles.iter().enumerate() {
        let Some(v) = v else { continue };
        let depths: Vec<String> = v
            .depths
            .iter()
            .map(|c| format!("{:.1}", c * depth))
            .collect();
        let mut depths = depths.join(" ");
        if !v.measured {
            depths.push_str(" (balance)");
        }
        let _ = writeln!(
            s,
            "  {:<10} {:<6} {:>8.1} {:<30} {:>8} {:>7.1} {:>6.3} {:>8} {:>7.2} {:>6.2} {:>6.3} {:>8.2} {:>8.2}",
            format!("vehicle {}", k + 1),
            v.side.name(),
            v.width * depth,
            depths,
            kj(v.crush_energy),
            v.pdof,
            v.pdof_factor,
            kj(v.energy),
            u.speed(v.barrier_equivalent_speed),
            v.moment_arm,
            v.effective_mass_factor,
            u.speed(v.crash3_delta_v),
            u.speed(v.pim_delta_v),
        );
    }
    let _ = writeln!(
        s,
        "  (E the profile's energy, E' with the direction-of-force factor 1 + tan^2 of the PDOF's \
         angle from the face's normal; delta-V in {sp}; PDOF clockwise from the nose)"
    );
    let z =
        a.z.map_or_else(|| "no sigma".to_string(), |z| format!("{z:+.2} sigma"));
    let _ = writeln!(
        s,
        "  crush energy {} +- {} kJ; expected energy loss {} kJ ({}); PIM's energy loss {} kJ; \
         difference {} kJ ({z})",
        kj(a.crush_energy),
        kj(a.crush_energy_sigma),
        kj(a.expected_loss),
        a.relation.name(),
        kj(a.energy_loss),
        kj(a.difference),
    );
    let diffs: Vec<String> = a
        .vehicles
        .iter()
        .enumerate()
        .filter_map(|(k, v)| {
            v.as_ref().map(|v| {
                format!(
                    "vehicle {} {:+.2} {sp}",
                    k + 1,
                    u.speed(v.crash3_delta_v - v.pim_delta_v)
                )
            })
        })
        .collect();
    let _ = writeln!(s, "  CRASH3 delta-V - PIM's: {}", diffs.join(", "));
    let _ = writeln!(s, "  {}", a.relation_note);
    for w in &a.warnings {
        let _ = writeln!(s, "  warning: {w}");
    }
    s
}

/// The damage of a fit: the crush at the fit's answer and, when the crush energy is evidence,
/// the fit with it.
pub fn fit_damage_lines(d: &FitDamage, u: UnitSystem) -> String {
    let mut s = String::new();
    if let Some(a) = &d.at_fit {
        let _ = writeln!(s, "\nat the best answer above (without the crush energy):");
        s.push_str(&damage_lines(a, u));
    }
    if let Some(why) = &d.not_evidence {
        let _ = writeln!(s, "crush energy not fitted: {why}");
    }
    if let Some(f) = &d.with_energy {
        let sp = u.speed_label();
        let _ = writeln!(
            s,
            "\nfit with the crush energy as evidence ({} branch):",
            f.moment.name()
        );
        let _ = writeln!(
            s,
            "  e {:.4}  mu {:.4}  em {:.4}  cost {:.6} (the case's evidence {:.6}, the energy's \
             {:.6}); energy residual {:+.2} sigma",
            f.e,
            f.mu,
            f.em,
            f.cost,
            f.cost_without_energy,
            f.cost - f.cost_without_energy,
            f.energy_z
        );
        if f.velocity_sigma_assumed {
            let _ = writeln!(
                s,
                "  (the case gives no standard deviations: its weighted velocity residuals count \
                 beside the energy's as if their sigma were 1 m/s and 1 rad/s; give [sigma] for \
                 a chi-square)"
            );
        }
        if let Some(c) = &f.chi_square {
            let _ = writeln!(
                s,
                "  {}",
                crate::statistics::chi_square_words(c.value, c.degrees_of_freedom, c.p_value)
            );
        }
        for (when, v) in [("contact   ", &f.initial), ("separation", &f.final_)] {
            let v = v.to_vector();
            let _ = writeln!(
                s,
                "  {when} v1 ({:.2}, {:.2}) {sp}, w1 {:.3} rad/s; v2 ({:.2}, {:.2}) {sp}, w2 {:.3} rad/s",
                u.speed(v[0]),
                u.speed(v[1]),
                v[2],
                u.speed(v[3]),
                u.speed(v[4]),
                v[5]
            );
        }
        let _ = writeln!(
            s,
            "  delta-V {:.2} / {:.2} {sp}; energy loss {} kJ",
            u.speed(f.delta_v[0]),
            u.speed(f.delta_v[1]),
            kj(f.energy_loss)
        );
        let _ = writeln!(
            s,
            "  {}",
            if f.proven {
                format!(
                    "proven optimal: the cost meets the certified optimum without the energy \
                     ({:.6}), which no answer can go below",
                    f.lower_bound
                )
            } else {
                format!(
                    "best found (Gauss-Newton with the exact fit inside, from each branch's \
                     optimum and from the optimum in each of {} slices of the e range; {} exact \
                     fits): not proven global; no answer costs less than the certified optimum \
                     without the energy, {:.6}",
                    pim_fit::E_SLICES,
                    f.fits,
                    f.lower_bound
                )
            }
        );
        if let Some(a) = &f.damage {
            s.push_str(&damage_lines(a, u));
        }
    }
    s
}
