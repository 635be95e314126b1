//! The JSON Schema of every document the toolkit writes, generated from the Rust types that
//! write them (`schemars`, draft 2020-12), so that the schema cannot drift from the output.
//!
//! The command line, the Python package and the browser read the same shapes; the schemas are
//! committed under `docs/schema/` (one file per document, named in [`DOCUMENTS`]) and a test
//! regenerates them and compares.

use crate::batch::BatchRecord;
use crate::case_records::CaseRecord;
use crate::predict::TestPrediction;
use crate::reconstruct_doc::ReconstructionOut;
use crate::reconstruct_study::ReconstructionStudy;
use crate::records::{FitOut, SensitivityOut, SolveOut};
use crate::ricsac_damage::DamageRecord;
use crate::runout::RunoutOut;
use crate::uncertainty::Study;
use serde::Serialize;

/// `pim batch DATA.csv --format json` (and `records.json` of its `--out`): the data file and one
/// record per test and cost function.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct DataBatchOut {
    /// The data file, as given.
    pub data: String,
    /// One record per test and cost function.
    pub records: Vec<BatchRecord>,
}

/// `pim batch DATA.csv --damage VEHICLES.csv --out DIR`'s `damage.json`: each test's crush.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct DamageBatchOut {
    /// The data file, as given.
    pub data: String,
    /// One record per test with crush data.
    pub records: Vec<DamageRecord>,
}

/// `pim predict-dv --format json`: Brach 1984's delta-V prediction of every test.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct PredictionsOut {
    /// One prediction per test.
    pub tests: Vec<TestPrediction>,
}

/// One document: its file name under `docs/schema/`, what writes it, and its schema.
pub struct DocumentSchema {
    /// The schema's file name (`solve.schema.json`).
    pub file: &'static str,
    /// The commands whose JSON output it describes.
    pub written_by: &'static str,
    /// The schema.
    pub schema: schemars::Schema,
}

/// Every document: (file name, what writes it).
pub const DOCUMENTS: [(&str, &str); 11] = [
    (
        "solve.schema.json",
        "pim solve --format json; solve.json of pim solve --out",
    ),
    ("sensitivity.schema.json", "pim sensitivity --format json"),
    (
        "fit.schema.json",
        "pim fit --format json of a case without scene evidence",
    ),
    (
        "reconstruction.schema.json",
        "pim fit --format json of a case with scene evidence (the whole reconstruction)",
    ),
    (
        "uncertainty.schema.json",
        "pim uncertainty --format json of a case without scene evidence",
    ),
    (
        "reconstruction-uncertainty.schema.json",
        "pim uncertainty --format json of a case with scene evidence",
    ),
    ("runout.schema.json", "pim runout --format json"),
    (
        "batch-data.schema.json",
        "pim batch DATA.csv --format json; records.json of its --out",
    ),
    (
        "batch-case-record.schema.json",
        "pim batch DIR --format json: one record per line (JSON Lines), one per case and branch",
    ),
    (
        "damage-batch.schema.json",
        "damage.json of pim batch DATA.csv --damage VEHICLES.csv --out",
    ),
    ("predict-dv.schema.json", "pim predict-dv --format json"),
];

/// The schema of every document in [`DOCUMENTS`]' order.
pub fn documents() -> Vec<DocumentSchema> {
    // The shape as written (a field skipped when empty is optional), not as read.
    let settings = schemars::generate::SchemaSettings::draft2020_12().for_serialize();
    let of = |f: fn(&mut schemars::SchemaGenerator) -> schemars::Schema| {
        f(&mut settings.clone().into_generator())
    };
    let schemas = [
        of(|g| g.root_schema_for::<SolveOut>()),
        of(|g| g.root_schema_for::<SensitivityOut>()),
        of(|g| g.root_schema_for::<FitOut>()),
        of(|g| g.root_schema_for::<ReconstructionOut>()),
        of(|g| g.root_schema_for::<Study>()),
        of(|g| g.root_schema_for::<ReconstructionStudy>()),
        of(|g| g.root_schema_for::<RunoutOut>()),
        of(|g| g.root_schema_for::<DataBatchOut>()),
        of(|g| g.root_schema_for::<CaseRecord>()),
        of(|g| g.root_schema_for::<DamageBatchOut>()),
        of(|g| g.root_schema_for::<PredictionsOut>()),
    ];
    DOCUMENTS
        .iter()
        .zip(schemas)
        .map(|(&(file, written_by), mut schema)| {
            schema.insert(
                "$comment".to_string(),
                format!("The document of {written_by}. Generated from the toolkit's types.").into(),
            );
            DocumentSchema {
                file,
                written_by,
                schema,
            }
        })
        .collect()
}
