//! The lines of the table output that give a branch's estimated impact geometry.

use pim_case::units::UnitSystem;
use std::fmt::Write as _;

/// The estimated geometry of a branch: each input with its range, and the search over it.
pub(crate) fn geometry_block(
    s: &mut String,
    g: &pim_fit::GeometryEstimate,
    u: UnitSystem,
    cost: Option<f64>,
) {
    let unit = u.length_label();
    let _ = writeln!(
        s,
        "  geometry: vehicle 1 d {:.3} {unit} phi {:.2} deg, vehicle 2 d {:.3} {unit} phi {:.2} deg, \
         crush angle {:.2} deg",
        u.length(g.vehicle1.d),
        g.vehicle1.phi,
        u.length(g.vehicle2.d),
        g.vehicle2.phi,
        g.crush_angle
    );
    for r in &g.ranges {
        let (f, unit): (&dyn Fn(f64) -> f64, &str) =
            if pim_fit::GeometryInput::name_is_length(&r.input) {
                (&|x| u.length(x), unit)
            } else {
                (&|x| x, "deg")
            };
        let mut flags = Vec::new();
        if r.at_bound {
            flags.push("on a bound");
        }
        if !r.identifiable {
            flags.push("not pinned down");
        }
        let _ = writeln!(
            s,
            "    {:<24} {:>13}  within {:.0} % of the optimum: {:.3} .. {:.3}  (bounds \
             {:.3} .. {:.3}){}",
            r.input,
            format!("{:.3} {unit}", f(r.value)),
            r.tolerance * 100.0,
            f(r.low),
            f(r.high),
            f(r.bounds[0]),
            f(r.bounds[1]),
            if flags.is_empty() {
                String::new()
            } else {
                format!("; {}", flags.join(", "))
            }
        );
    }
    let at = [
        "no coefficients admit an answer",
        "the coefficients are proven optimal",
    ];
    let _ = writeln!(
        s,
        "  geometry search: {} grid points ({} per input), {} refinements, {} fits; {} at this \
         geometry; {}",
        g.search.grid_points,
        g.search.points_per_input,
        g.search.refinements,
        g.search.fits,
        at[usize::from(cost.is_some())],
        g.search.proof.statement(cost)
    );
}
