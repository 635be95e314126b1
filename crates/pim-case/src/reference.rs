//! Reference tables of the papers shipped with the data (`data/reference/`).

/// One row of Brach 1984 Table 1 (`data/reference/brach1984_table1.csv`).
#[derive(Debug, Clone, serde::Deserialize)]
pub struct BrachRow {
    /// A (em free) or B (em = 1).
    pub branch: String,
    /// Test number.
    pub test: u32,
    /// Brach's sum of squares (his units and weights).
    pub sum_of_squares: f64,
    /// Energy loss, percent.
    pub energy_loss_percent: f64,
    /// Restitution.
    pub e: f64,
    /// Moment restitution.
    pub em: f64,
    /// Friction.
    pub mu: f64,
}

/// The file (in `data/reference/`) of the table in which Vossou & Koulocheris (2018) print the
/// errors of a cost function's fits. Their results section swaps the labels of Tables 4 and 5
/// relative to their equations: Table 5 holds the contact components (Q1), Table 4 the
/// separation components (Q2), Table 6 all twelve (Q3); see the files' comments.
pub fn vossou_table(cost: pim_fit::CostPreset) -> &'static str {
    match cost {
        pim_fit::CostPreset::Q1 => "vossou2018_table5.csv",
        pim_fit::CostPreset::Q2 => "vossou2018_table4.csv",
        pim_fit::CostPreset::Q3 => "vossou2018_table6.csv",
    }
}

/// Why a reference table cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// The CSV itself (its reader's message).
    #[error(transparent)]
    Csv(#[from] csv::Error),
    /// A cell that should hold a number (row and column from 1).
    #[error("row {row}: column {column}: not a number: {cell:?}")]
    NotANumber {
        /// Its row, from 1.
        row: usize,
        /// Its column, from 1.
        column: usize,
        /// What it holds.
        cell: String,
    },
}

/// The costs Vossou & Koulocheris (2018) print for one cost function: per test, the sum of the
/// squares of the errors in one of their Tables 4-6 (`data/reference/vossou2018_table*.csv`:
/// a `test` column and one column per fitted component, errors in m/s and rad/s).
pub fn parse_vossou(text: &str) -> Result<Vec<(u32, f64)>, ReferenceError> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut out = Vec::new();
    for (i, row) in rdr.records().enumerate() {
        let row = row?;
        let number = |j: usize| -> Result<f64, ReferenceError> {
            let cell = row.get(j).unwrap_or("").trim();
            cell.parse::<f64>().map_err(|_| ReferenceError::NotANumber {
                row: i + 1,
                column: j + 1,
                cell: cell.to_string(),
            })
        };
        let test = number(0)?;
        let cost = (1..row.len())
            .map(number)
            .try_fold(0.0, |acc, v| v.map(|v| acc + v * v))?;
        out.push((test as u32, cost));
    }
    Ok(out)
}

/// Parses the Brach 1984 Table 1 reference file.
pub fn parse_brach(text: &str) -> Result<Vec<BrachRow>, csv::Error> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    rdr.deserialize().collect::<Result<Vec<BrachRow>, _>>()
}
