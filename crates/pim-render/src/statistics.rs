//! A chi-square and its probability in words, one rule for every fit and reconstruction
//! ([`pim_fit::judged_dof`]).

/// A chi-square in words, one rule for every fit and reconstruction: `chi-square 0.090 with 5
/// degrees of freedom, p = 0.9999`; with none left, what that means and how it is judged
/// ([`pim_fit::judged_dof`]).
pub fn chi_square_words(value: f64, dof: i64, p: Option<f64>) -> String {
    let p = p.map_or_else(|| "not a number".to_string(), format_p);
    if dof > 0 {
        return format!("chi-square {value:.3} with {dof} degrees of freedom, p = {p}");
    }
    let free = pim_fit::ChiSquare::unknowns_undetermined(dof);
    let count = if free > 0 {
        format!(
            "more unknowns than pieces of evidence: {free} combination{} of the unknowns not \
             determined by count",
            if free == 1 { "" } else { "s" }
        )
    } else {
        "as many unknowns as pieces of evidence".to_string()
    };
    format!(
        "chi-square {value:.3} with {dof} degrees of freedom ({count}; what the fit still misses \
         is judged as one degree of freedom), p = {p}"
    )
}

/// A probability: four decimals, or two significant digits below 0.0001.
pub fn format_p(p: f64) -> String {
    if p >= 1e-4 || p == 0.0 {
        format!("{p:.4}")
    } else {
        format!("{p:.1e}")
    }
}
