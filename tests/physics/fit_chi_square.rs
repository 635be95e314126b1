//! With standard deviations (`[sigma]`) the fit's cost is a chi-square: on data simulated from
//! the forward model with exactly those sigmas, its values follow the chi-square law of the
//! stated degrees of freedom (seeded).
use crate::common;
use common::{normal, ricsac9_truth, sigma_toml, state_toml, RICSAC9_GEOMETRY};
use pim_case::case::Case;
use pim_core::*;
use pim_fit::{ChiSquare, CostPreset, MomentBranch, Status};
use pim_studies::fitcase::{self, CostChoice};
use rand::SeedableRng;

#[test]
fn chi_square_of_simulated_data_follows_its_law() {
    let (sv, sw) = (0.2, 0.1);
    let x = Velocities::from_vector(&nalgebra::Vector6::new(-9.48, 0.0, 0.0, 0.0, 9.48, 0.0));
    let (_, truth) = ricsac9_truth(&x, 0.1, || 0.5).unwrap();
    let sep = truth.separation.to_vector();
    let settings = pim_fit::FitSettings {
        branches: vec![MomentBranch::Zero],
        ..Default::default()
    }
    .check()
    .unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(2026);
    let n = 200;
    let (mut sum, mut below_5, mut dof) = (0.0, 0, 0);
    for _ in 0..n {
        let f: Vec<f64> = (0..6)
            .map(|k| sep[k] + normal(&mut rng) * if k % 3 == 2 { sw } else { sv })
            .collect();
        let text = format!(
            "{RICSAC9_GEOMETRY}[estimates.initial]\n{}[estimates.final]\n{}[sigma.final]\n{}",
            state_toml(x.to_vector().as_slice()),
            state_toml(&f),
            sigma_toml(sv, sw)
        );
        let case = Case::from_text("sim", &text).unwrap();
        let problem = fitcase::problem(&case, CostChoice::Preset(CostPreset::Q2)).unwrap();
        let unit = fitcase::sigma_unit(&case).unwrap().unwrap();
        assert!((unit - sw * sw).abs() < 1e-15);
        let report = pim_fit::fit(&problem, &settings).unwrap();
        let b = &report.branches[0];
        assert_eq!(b.status, Status::Optimal);
        let cost = b.solution.as_ref().unwrap().cost;
        let c = ChiSquare::new(&problem, MomentBranch::Zero, cost, unit);
        dof = c.degrees_of_freedom;
        sum += c.value;
        if c.p_value.unwrap() < 0.05 {
            below_5 += 1;
        }
    }
    // Q2, zero branch: 6 estimates, 6 unknown components + e, mu - 6 equations = 2 parameters.
    assert_eq!(dof, 4);
    // Mean of chi^2_4 is 4 with sd sqrt(8 / 200) = 0.2 for the mean of 200: within 3 sd.
    let mean = sum / n as f64;
    assert!((mean - 4.0).abs() < 0.6, "mean chi-square {mean}");
    // About 5 % of p-values below 0.05 (binomial sd 1.5 %): between 1 % and 10 %.
    assert!((2..=20).contains(&below_5), "{below_5} of {n} below 0.05");
    println!("mean chi-square {mean:.3} (dof 4), {below_5}/{n} p-values below 0.05");
}

#[test]
fn sigma_and_weights_together_are_refused() {
    let text = format!(
        "{RICSAC9_GEOMETRY}
[estimates.final]
vehicle1 = {{ vx = -3.0 }}
[sigma.final]
vehicle1 = {{ vx = 0.2 }}
[weights.final]
vehicle1 = {{ vx = 0.5 }}
"
    );
    let case = Case::from_text("both.toml", &text).unwrap();
    let e = fitcase::problem(&case, CostChoice::Custom).unwrap_err();
    // The entry given both ways is named, with both places.
    assert!(
        e.message
            .contains("both.toml:21:19: weights.final.vehicle1.vx: given as a weight here")
            && e.message
                .contains("both.toml:19:19: sigma.final.vehicle1.vx"),
        "{e}"
    );
    // A sigma in km/h is converted like the estimates.
    let text = format!(
        "{RICSAC9_GEOMETRY}
[units]
speed = \"km/h\"
[estimates.final]
vehicle1 = {{ vx = -10.8 }}
[sigma.final]
vehicle1 = {{ vx = 0.72 }}
"
    );
    let case = Case::from_text("kmh.toml", &text).unwrap();
    assert!((fitcase::sigma_unit(&case).unwrap().unwrap() - 0.04).abs() < 1e-12);
}

/// A standard deviation so large that its weight underflows is said of the standard deviation
/// the file wrote, with its place, not as "weight 0".
#[test]
fn an_underflowing_weight_is_said_of_its_sigma() {
    let text = format!(
        "{RICSAC9_GEOMETRY}
[estimates.final]
vehicle1 = {{ vx = -3.0, vy = 1.0 }}
[sigma.final]
vehicle1 = {{ vx = 1e200, vy = 0.1 }}
"
    );
    let case = Case::from_text("big.toml", &text).unwrap();
    let e = fitcase::problem(&case, CostChoice::Custom).unwrap_err();
    assert!(
        e.message.starts_with("big.toml:")
            && e.message
                .contains("sigma.final.vehicle1.vx: a standard deviation of 1e200")
            && e.message.contains("underflows"),
        "{e}"
    );
    assert!(!e.message.contains("weight 0 must"), "{e}");
}
