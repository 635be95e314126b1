//! The RICSAC refit from code (what `pim batch` does): `cargo run --release --example batch`.
use pim_fit::{CostPreset, FitSettings, MomentBranch};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/ricsac.csv");
    let tests = pim_case::ricsac::parse("data/ricsac.csv", &std::fs::read_to_string(path)?)?;
    let plan = pim_studies::batch::BatchPlan {
        costs: vec![CostPreset::Q2],
        branches: vec![MomentBranch::Zero],
        models: vec![pim_fit::FitModel::Pim],
        settings: FitSettings::default(),
        timing: false,
        case_e_max: None,
    };
    let records = pim_studies::batch::run(&tests, &plan, &pim_studies::watch::Unwatched);
    println!("test  outcome        e      mu     cost  loss %");
    for r in &records {
        match (&r.branch, r.solved()) {
            (Some(b), true) => println!(
                "{:>4}  {:<10} {:.3}  {:+.3}  {:>7.3}  {:>6.1}",
                r.test,
                r.outcome,
                b.e.unwrap_or(f64::NAN),
                b.mu.unwrap_or(f64::NAN),
                b.cost.unwrap_or(f64::NAN),
                b.energy_loss_percent.unwrap_or(f64::NAN)
            ),
            _ => println!("{:>4}  {}", r.test, r.outcome),
        }
    }
    Ok(())
}
