//! The RICSAC refit from code (what `pim batch` does): `cargo run --release --example batch`.
use pim_fit::{CostPreset, FitSettings, MomentBranch};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/ricsac.csv");
    let tests = pim_cli::ricsac::load(&path)?;
    let plan = pim_cli::batch::BatchPlan {
        costs: vec![CostPreset::Q2],
        branches: vec![MomentBranch::Zero],
        settings: FitSettings::default(),
        timing: false,
    };
    let records = pim_cli::batch::run(&tests, &plan, &|| {});
    println!("{}", pim_cli::batch::summary_table(&records, &plan.costs));
    Ok(())
}
